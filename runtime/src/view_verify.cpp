// View::verifyHashes: the full, explicit integrity check (docs/FORMAT.md §6, rule V17).
#include "diagnostic.h"
#include "dng/format/xxhash64.h"
#include "dng/view.h"

#include <cstring>

namespace dng {

namespace fmt = format;

Status View::verifyHashes(Diagnostic* out_diag) const {
  if (!valid()) return writeDiagnostic(out_diag, Status::kInvalidArgument, "the view is empty");
  fmt::FileHeader header;
  std::memcpy(&header, data_, sizeof header);
  for (std::uint32_t s = 0; s < header.section_count; ++s) {
    fmt::SectionEntry entry;
    std::memcpy(&entry, data_ + header.section_table_offset + s * sizeof entry, sizeof entry);
    // Bounds were validated by open(); every section, known or not, is covered.
    if (fmt::xxhash64(data_ + entry.offset, entry.size) != entry.hash)
      return writeDiagnostic(out_diag, Status::kSectionHashMismatch, "V17: section %u ('%.4s') hash does not match", s,
                             reinterpret_cast<const char*>(&entry.tag));
  }
  if (out_diag != nullptr) *out_diag = Diagnostic();
  return Status::kOk;
}

} // namespace dng
