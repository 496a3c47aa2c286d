// View::verifyHashes: the full, explicit integrity check (docs/FORMAT.md §6, rules V17 and V18).
#include "diagnostic.h"
#include "dng/format/xxhash64.h"
#include "dng/view.h"

#include <cstring>

namespace dng {

namespace fmt = format;

namespace {

// Offset of the first non-zero byte in [begin, end), or `end`.
std::uint64_t firstNonZero(const std::uint8_t* data, std::uint64_t begin, std::uint64_t end) {
  while (begin < end && data[begin] == 0)
    ++begin;
  return begin;
}

} // namespace

Status View::verifyHashes(Diagnostic* out_diag) const {
  if (!valid()) return writeDiagnostic(out_diag, Status::kInvalidArgument, "the view is empty");
  fmt::FileHeader header;
  std::memcpy(&header, data_, sizeof header);
  for (std::uint32_t s = 0; s < header.section_count; ++s) {
    fmt::SectionEntry entry;
    std::memcpy(&entry, data_ + header.section_table_offset + s * sizeof entry, sizeof entry);
    // Bounds were validated by open(); every section, known or not, is covered.
    if (fmt::xxhash64(data_ + entry.offset, entry.size) != entry.hash)
      return writeRuleDiagnostic(out_diag, Status::kSectionHashMismatch, "V17",
                                 "section %u ('%.4s') hash does not match", s,
                                 reinterpret_cast<const char*>(&entry.tag));
  }
  // V18: the bytes no section covers (alignment padding after the table and between sections) are zero.
  // Hashes cover payloads only, so this is the one place damage could otherwise hide. open() has
  // checked that the sections are sorted, disjoint and inside the file.
  const std::uint64_t table_end =
      header.section_table_offset + std::uint64_t(header.section_count) * sizeof(fmt::SectionEntry);
  if (firstNonZero(data_, fmt::kHeaderSize, header.section_table_offset) < header.section_table_offset)
    return writeRuleDiagnostic(out_diag, Status::kNonZeroPadding, "V18",
                               "padding before the section table is not zero");
  std::uint64_t cursor = table_end;
  for (std::uint32_t s = 0; s <= header.section_count; ++s) {
    fmt::SectionEntry entry{};
    entry.offset = size_; // after the last section: up to the end of the file
    if (s < header.section_count)
      std::memcpy(&entry, data_ + header.section_table_offset + s * sizeof entry, sizeof entry);
    const std::uint64_t bad = firstNonZero(data_, cursor, entry.offset);
    if (bad < entry.offset)
      return writeRuleDiagnostic(out_diag, Status::kNonZeroPadding, "V18", "byte %llu, padding before %s, is not zero",
                                 (unsigned long long)bad,
                                 s < header.section_count ? "a section" : "the end of the file");
    cursor = entry.offset + entry.size;
  }
  if (out_diag != nullptr) *out_diag = Diagnostic();
  return Status::kOk;
}

} // namespace dng
