// The on-disk layout: constants and the byte positions of fields as a writer lays them out.
// (Sizes and offsets of every struct are pinned by static_asserts in dng/format/layout.h.)
#include "dng/format/layout.h"
#include "sample_files.h"

#include <gtest/gtest.h>

namespace dng {
namespace {

using format::FileHeader;

TEST(Layout, MagicCatchesTextModeDamage) {
  EXPECT_EQ(format::kMagic[0], 0x89);
  EXPECT_EQ(format::kMagic[4], '\r');
  EXPECT_EQ(format::kMagic[5], '\n');
  EXPECT_EQ(format::kMagic[6], 0x1A);
  EXPECT_EQ(format::kMagic[7], '\n');
}

TEST(Layout, TagsReadAsTheirLettersOnDisk) {
  const std::uint32_t tag = format::kTagGrid;
  unsigned char bytes[4];
  std::memcpy(bytes, &tag, 4);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes), 4), "GRID");
  EXPECT_NE(format::kTagBrickTop, format::kTagBrickPool);
}

TEST(Layout, WriterPlacesTableAfterHeaderAndSectionsOn64ByteBoundaries) {
  const auto bytes = testing::smallBrickedBox();
  const auto header = testing::peek<FileHeader>(bytes, 0);
  EXPECT_EQ(header.header_size, 128u);
  EXPECT_EQ(header.section_table_offset, 128u);
  EXPECT_EQ(header.file_size, bytes.size());
  EXPECT_EQ(header.section_count, 4u); // GRID, META, BTOP, BPOL
  for (std::uint32_t tag : {format::kTagGrid, format::kTagMetadata, format::kTagBrickTop, format::kTagBrickPool}) {
    const auto entry = testing::entryOf(bytes, tag);
    EXPECT_EQ(entry.offset % 64, 0u);
    EXPECT_GE(entry.offset, 128u + 4 * sizeof(format::SectionEntry));
  }
  EXPECT_EQ(testing::entryOf(bytes, format::kTagGrid).flags, format::kSectionRequired);
  EXPECT_EQ(testing::entryOf(bytes, format::kTagMetadata).flags, 0u);
  for (unsigned char b : header.reserved)
    EXPECT_EQ(b, 0);
}

} // namespace
} // namespace dng
