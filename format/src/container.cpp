// Container assembly: header, section table, aligned sections, hashes (docs/FORMAT.md §2-3).
#include "dng/format/writer.h"
#include "dng/format/xxhash64.h"

#include <cstring>

namespace dng {
namespace format {
namespace {

std::uint64_t alignUp(std::uint64_t value, std::uint64_t alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

// True when the header's section table lies inside `bytes`.
bool tableFits(const FileHeader& header, std::size_t size) {
  return header.section_count <= kMaxSections && header.section_table_offset <= size &&
         std::uint64_t(header.section_count) * sizeof(SectionEntry) <= size - header.section_table_offset;
}

// Fills the table hash (when the table fits) and then the header hash.
void sealHeader(std::vector<std::uint8_t>& bytes) {
  FileHeader header;
  std::memcpy(&header, bytes.data(), sizeof header);
  if (tableFits(header, bytes.size())) {
    const std::uint64_t table_bytes = std::uint64_t(header.section_count) * sizeof(SectionEntry);
    header.section_table_hash = xxhash64(bytes.data() + header.section_table_offset, table_bytes);
    std::memcpy(bytes.data(), &header, sizeof header);
  }
  header.header_hash = xxhash64(bytes.data(), offsetof(FileHeader, header_hash));
  std::memcpy(bytes.data(), &header, sizeof header);
}

} // namespace

void ContainerBuilder::addSection(std::uint32_t tag, std::uint32_t flags, const void* data, std::size_t size) {
  const auto* begin = static_cast<const std::uint8_t*>(data);
  sections_.push_back({tag, flags, std::vector<std::uint8_t>(begin, begin + size)});
}

std::vector<std::uint8_t> ContainerBuilder::finish() const {
  const std::uint64_t table_offset = kHeaderSize;
  std::uint64_t cursor = table_offset + sections_.size() * sizeof(SectionEntry);
  std::vector<SectionEntry> table;
  for (const Pending& section : sections_) {
    cursor = alignUp(cursor, kSectionAlignment);
    table.push_back({section.tag, section.flags, cursor, section.bytes.size(),
                     xxhash64(section.bytes.data(), section.bytes.size())});
    cursor += section.bytes.size();
  }

  std::vector<std::uint8_t> bytes(cursor, 0); // zero padding between sections is part of the spec
  FileHeader header{};
  std::memcpy(header.magic, kMagic, sizeof kMagic);
  header.version_major = major_;
  header.version_minor = minor_;
  header.header_size = kHeaderSize;
  header.file_size = cursor;
  header.section_count = std::uint32_t(sections_.size());
  header.section_table_offset = table_offset;
  std::memcpy(bytes.data(), &header, sizeof header);
  if (!table.empty()) std::memcpy(bytes.data() + table_offset, table.data(), table.size() * sizeof(SectionEntry));
  for (std::size_t s = 0; s < sections_.size(); ++s) {
    if (!sections_[s].bytes.empty())
      std::memcpy(bytes.data() + table[s].offset, sections_[s].bytes.data(), sections_[s].bytes.size());
  }
  sealHeader(bytes);
  return bytes;
}

void resealHashes(std::vector<std::uint8_t>& bytes) {
  if (bytes.size() < kHeaderSize) return;
  FileHeader header;
  std::memcpy(&header, bytes.data(), sizeof header);
  for (std::uint32_t s = 0; tableFits(header, bytes.size()) && s < header.section_count; ++s) {
    std::uint8_t* slot = bytes.data() + header.section_table_offset + s * sizeof(SectionEntry);
    SectionEntry entry;
    std::memcpy(&entry, slot, sizeof entry);
    if (entry.offset <= bytes.size() && entry.size <= bytes.size() - entry.offset) {
      entry.hash = xxhash64(bytes.data() + entry.offset, entry.size);
      std::memcpy(slot, &entry, sizeof entry);
    }
  }
  sealHeader(bytes);
}

} // namespace format
} // namespace dng
