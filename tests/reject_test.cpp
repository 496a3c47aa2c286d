// The loader against damaged files: each rule of docs/FORMAT.md §6 rejects with its own status,
// never crashes (CI runs this under AddressSanitizer), and acceptable variations are accepted.
#include "analytic_fields.h"
#include "dng/format/codec.h"
#include "dng/format/writer.h"
#include "dng/view.h"
#include "sample_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dng {
namespace {

using format::FileHeader;
using format::GridSection;
using format::SectionEntry;
using testing::entryOf;
using testing::entryOffset;
using testing::peek;
using testing::poke;
using Bytes = std::vector<std::uint8_t>;

Status openStatus(const Bytes& bytes, std::size_t size) {
  View view;
  Diagnostic diag;
  const Status status = View::open(bytes.data(), size, &view, &diag);
  EXPECT_EQ(diag.status, status);
  if (status != Status::kOk) {
    EXPECT_FALSE(view.valid());
    EXPECT_NE(diag.message[0], '\0') << "a rejection must say why";
  }
  return status;
}
Status openStatus(const Bytes& bytes) { return openStatus(bytes, bytes.size()); }

// Patches a field of the GRID section and reseals every hash so only the patched rule can fire.
template <class Patch> Bytes withGrid(Bytes bytes, Patch patch) {
  const std::size_t at = entryOf(bytes, format::kTagGrid).offset;
  auto grid = peek<GridSection>(bytes, at);
  patch(grid);
  poke(bytes, at, grid);
  format::resealHashes(bytes);
  return bytes;
}

template <class Patch> Bytes withEntry(Bytes bytes, std::uint32_t tag, Patch patch) {
  const std::size_t at = entryOffset(bytes, tag);
  auto entry = peek<SectionEntry>(bytes, at);
  patch(entry);
  poke(bytes, at, entry);
  format::resealHashes(bytes);
  return bytes;
}

// Index of the first top entry of `kind` in a bricked file.
std::size_t firstTile(const Bytes& bytes, format::TileKind kind) {
  const auto top = entryOf(bytes, format::kTagBrickTop);
  for (std::size_t t = 0; t < top.size / 8; ++t) {
    if (format::entryKind(peek<std::uint64_t>(bytes, top.offset + t * 8)) == kind) return top.offset + t * 8;
  }
  ADD_FAILURE() << "no tile of the requested kind";
  return 0;
}

TEST(Accept, ValidFilesOpen) {
  EXPECT_EQ(openStatus(testing::smallBrickedBox()), Status::kOk);
  EXPECT_EQ(openStatus(testing::smallDensePlane()), Status::kOk);
}

TEST(Reject, EveryTruncationOfBothEncodings) {
  for (const Bytes& file : {testing::smallBrickedBox(), testing::smallDensePlane()}) {
    for (std::size_t length = 0; length < file.size(); ++length) {
      ASSERT_EQ(openStatus(file, length), Status::kTruncated) << "length " << length;
    }
  }
}

TEST(Reject, TrailingGarbage) {
  Bytes file = testing::smallBrickedBox();
  file.push_back(0);
  EXPECT_EQ(openStatus(file), Status::kTrailingBytes);
}

TEST(Reject, BadMagicAndTextModeDamage) {
  Bytes file = testing::smallDensePlane();
  file[1] = 'X';
  EXPECT_EQ(openStatus(file), Status::kBadMagic);
  Bytes text_mode = testing::smallDensePlane();
  text_mode.erase(text_mode.begin() + 4); // CR LF became LF
  EXPECT_EQ(openStatus(text_mode), Status::kBadMagic);
}

TEST(Reject, NewerAndZeroMajorVersion) {
  for (std::uint16_t major : {std::uint16_t(2), std::uint16_t(0), std::uint16_t(0xFFFF)}) {
    Bytes file = testing::smallBrickedBox();
    poke(file, offsetof(FileHeader, version_major), major);
    format::resealHashes(file);
    EXPECT_EQ(openStatus(file), Status::kUnsupportedVersion) << major;
  }
}

TEST(Accept, NewerMinorVersion) {
  format::ContainerBuilder builder;
  const Bytes base = testing::smallDensePlane();
  // Rebuild the same sections under version 1.7.
  for (std::uint32_t tag : {format::kTagGrid, format::kTagMetadata, format::kTagDense}) {
    const auto e = entryOf(base, tag);
    builder.addSection(tag, e.flags, base.data() + e.offset, e.size);
  }
  builder.setVersion(1, 7);
  const Bytes file = builder.finish();
  View view;
  ASSERT_EQ(View::open(file.data(), file.size(), &view), Status::kOk);
  EXPECT_EQ(view.versionMinor(), 7);
}

TEST(Reject, HeaderAndTableBytesChangedAfterWriting) {
  Bytes header = testing::smallBrickedBox();
  header[60] ^= 1; // a reserved byte
  EXPECT_EQ(openStatus(header), Status::kHeaderHashMismatch);
  Bytes table = testing::smallBrickedBox();
  table[128 + 4] ^= 2; // flags of the first entry
  EXPECT_EQ(openStatus(table), Status::kSectionTableHashMismatch);
  Bytes size = testing::smallBrickedBox();
  poke(size, offsetof(FileHeader, header_size), std::uint32_t(256));
  format::resealHashes(size);
  EXPECT_EQ(openStatus(size), Status::kBadHeader);
}

TEST(Reject, SectionTableOutOfRules) {
  Bytes count = testing::smallBrickedBox();
  poke(count, offsetof(FileHeader, section_count), std::uint32_t(1000));
  format::resealHashes(count);
  EXPECT_EQ(openStatus(count), Status::kBadSectionTable);
  Bytes offset = testing::smallBrickedBox();
  poke(offset, offsetof(FileHeader, section_table_offset), std::numeric_limits<std::uint64_t>::max() - 63);
  format::resealHashes(offset);
  EXPECT_EQ(openStatus(offset), Status::kBadSectionTable);
  Bytes inside_header = testing::smallBrickedBox();
  poke(inside_header, offsetof(FileHeader, section_table_offset), std::uint64_t(64));
  format::resealHashes(inside_header);
  EXPECT_EQ(openStatus(inside_header), Status::kBadSectionTable);
}

TEST(Reject, SectionOffsetsAndSizesThatOverflow) {
  const Bytes file = testing::smallBrickedBox();
  const std::uint64_t huge = std::numeric_limits<std::uint64_t>::max();
  EXPECT_EQ(openStatus(withEntry(file, format::kTagBrickPool, [&](SectionEntry& e) { e.size = huge; })),
            Status::kSectionOutOfBounds);
  EXPECT_EQ(openStatus(withEntry(file, format::kTagBrickPool, [&](SectionEntry& e) { e.offset = huge - 63; })),
            Status::kSectionOutOfBounds);
  EXPECT_EQ(openStatus(withEntry(file, format::kTagBrickPool, [&](SectionEntry& e) { e.size += 1; })),
            Status::kSectionOutOfBounds);
  EXPECT_EQ(openStatus(withEntry(file, format::kTagBrickPool, [&](SectionEntry& e) { e.offset += 8; })),
            Status::kSectionMisaligned);
  const std::uint64_t grid_offset = entryOf(file, format::kTagGrid).offset;
  EXPECT_EQ(openStatus(withEntry(file, format::kTagBrickTop, [&](SectionEntry& e) { e.offset = grid_offset; })),
            Status::kSectionOverlap);
  EXPECT_EQ(openStatus(withEntry(file, format::kTagGrid, [&](SectionEntry& e) { e.offset = 128; })),
            Status::kSectionOverlap); // inside the section table
}

TEST(Reject, UnknownRequiredSectionButNotUnknownOptional) {
  const Bytes base = testing::smallDensePlane();
  for (std::uint32_t flags : {format::kSectionRequired, 0u}) {
    format::ContainerBuilder builder;
    for (std::uint32_t tag : {format::kTagGrid, format::kTagDense}) {
      const auto e = entryOf(base, tag);
      builder.addSection(tag, e.flags, base.data() + e.offset, e.size);
    }
    const char extra[] = "from the future";
    builder.addSection(format::makeTag('X', 'T', 'R', 'A'), flags, extra, sizeof extra);
    EXPECT_EQ(openStatus(builder.finish()), flags ? Status::kUnknownRequiredSection : Status::kOk);
  }
}

TEST(Reject, MissingAndDuplicateSections) {
  const Bytes base = testing::smallDensePlane();
  const auto grid = entryOf(base, format::kTagGrid);
  const auto dense = entryOf(base, format::kTagDense);
  format::ContainerBuilder no_grid;
  no_grid.addSection(format::kTagDense, 1, base.data() + dense.offset, dense.size);
  EXPECT_EQ(openStatus(no_grid.finish()), Status::kMissingSection);
  format::ContainerBuilder no_payload;
  no_payload.addSection(format::kTagGrid, 1, base.data() + grid.offset, grid.size);
  EXPECT_EQ(openStatus(no_payload.finish()), Status::kMissingSection);
  format::ContainerBuilder twice;
  twice.addSection(format::kTagGrid, 1, base.data() + grid.offset, grid.size);
  twice.addSection(format::kTagGrid, 1, base.data() + grid.offset, grid.size);
  twice.addSection(format::kTagDense, 1, base.data() + dense.offset, dense.size);
  EXPECT_EQ(openStatus(twice.finish()), Status::kDuplicateSection);
}

TEST(Reject, NonFiniteOrDegenerateGridTransform) {
  const Bytes file = testing::smallBrickedBox();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.origin[1] = nan; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.origin[2] = -inf; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.origin[0] = 3e38f; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.voxel_size = 1e30f; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.voxel_size = inf; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.voxel_size = 0.0f; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.voxel_size = 1e-45f; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.band = nan; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.band = -1.0f; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.dims[0] = 0; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.dims[2] = 0xFFFFFFFFu; })), Status::kBadGrid);
  EXPECT_EQ(openStatus(withGrid(file, [&](GridSection& g) { g.brick_dims[1] += 1; })), Status::kBadGrid);
}

TEST(Reject, UnknownEncodingOrBrickSize) {
  const Bytes file = testing::smallBrickedBox();
  EXPECT_EQ(openStatus(withGrid(file, [](GridSection& g) { g.encoding = 7; })), Status::kUnsupportedEncoding);
  EXPECT_EQ(openStatus(withGrid(file, [](GridSection& g) { g.brick_log2 = 5; })), Status::kUnsupportedEncoding);
  EXPECT_EQ(openStatus(withGrid(file, [](GridSection& g) { g.brick_log2 = 1; })), Status::kUnsupportedEncoding);
}

TEST(Reject, PayloadSizesThatDoNotMatchTheGrid) {
  const Bytes bricked = testing::smallBrickedBox();
  EXPECT_EQ(openStatus(withEntry(bricked, format::kTagBrickTop, [](SectionEntry& e) { e.size -= 8; })),
            Status::kBadPayloadSize);
  EXPECT_EQ(openStatus(withEntry(bricked, format::kTagBrickPool, [](SectionEntry& e) { e.size -= 4; })),
            Status::kBadPayloadSize);
  const Bytes dense = testing::smallDensePlane();
  EXPECT_EQ(openStatus(withEntry(dense, format::kTagDense, [](SectionEntry& e) { e.size -= 16; })),
            Status::kBadPayloadSize);
  const Bytes lifted = testing::smallBrickedBoxLifted();
  ASSERT_EQ(openStatus(lifted), Status::kOk);
  EXPECT_EQ(openStatus(withEntry(lifted, format::kTagLift, [](SectionEntry& e) { e.size -= 2; })),
            Status::kBadPayloadSize);
  const Bytes graded = testing::smallBrickedBoxGraded();
  ASSERT_EQ(openStatus(graded), Status::kOk);
  EXPECT_EQ(openStatus(withEntry(graded, format::kTagGradient, [](SectionEntry& e) { e.size -= 2; })),
            Status::kBadPayloadSize);
  const Bytes shaded = testing::smallBrickedBoxShaded();
  ASSERT_EQ(openStatus(shaded), Status::kOk);
  ASSERT_EQ(openStatus(testing::smallBrickedBoxSecondPlanes()), Status::kOk);
  EXPECT_EQ(openStatus(withEntry(shaded, format::kTagShading, [](SectionEntry& e) { e.size -= 4; })),
            Status::kBadPayloadSize);
  // Dimensions whose product overflows 64 bits must not wrap around to a matching size.
  EXPECT_EQ(openStatus(withGrid(dense, [](GridSection& g) { g.dims[0] = g.dims[1] = g.dims[2] = 1u << 24; })),
            Status::kBadPayloadSize);
}

TEST(Reject, BrickIndexOutOfRangeAndBadTileBits) {
  const Bytes file = testing::smallBrickedBox();
  const auto pool = entryOf(file, format::kTagBrickPool);
  const auto pool_bricks = std::uint32_t(pool.size / (4 * 4 * 4 * 4));

  Bytes index = file;
  const std::size_t brick_at = firstTile(index, format::TileKind::kBrick);
  poke(index, brick_at, format::packBrickEntry(pool_bricks, 0, 65535));
  format::resealHashes(index);
  EXPECT_EQ(openStatus(index), Status::kBadTileEntry);

  for (float d_centre : {std::nanf(""), INFINITY, 1e30f}) {
    Bytes plane = file;
    poke(plane, firstTile(plane, format::TileKind::kPlane), format::packPlaneEntry(3, 4, d_centre));
    format::resealHashes(plane);
    EXPECT_EQ(openStatus(plane), Status::kBadTileEntry) << d_centre;
  }

  Bytes far = file;
  poke(far, firstTile(far, format::TileKind::kFarOutside), std::uint64_t(1) << 40);
  format::resealHashes(far);
  EXPECT_EQ(openStatus(far), Status::kBadTileEntry);
}

TEST(Reject, NonFiniteOrOutOfRangeDenseVoxel) {
  const Bytes file = testing::smallDensePlane();
  const std::size_t voxel7 = entryOf(file, format::kTagDense).offset + 16 * 7;
  for (auto [offset, value] : {std::pair<std::size_t, float>{voxel7, std::nanf("")},
                               {voxel7 + 8, INFINITY},
                               {voxel7, 1e30f},
                               {voxel7 + 4, 1.5f}}) {
    Bytes damaged = file;
    poke(damaged, offset, value);
    format::resealHashes(damaged);
    EXPECT_EQ(openStatus(damaged), Status::kBadValue) << value;
  }
}

TEST(Reject, MisalignedOrMissingBuffer) {
  const Bytes file = testing::smallDensePlane();
  Bytes shifted(file.size() + 1);
  std::copy(file.begin(), file.end(), shifted.begin() + 1);
  View view;
  EXPECT_EQ(View::open(shifted.data() + 1, file.size(), &view), Status::kInvalidArgument);
  EXPECT_EQ(View::open(nullptr, 0, &view), Status::kInvalidArgument);
  EXPECT_EQ(View::open(file.data(), file.size(), nullptr), Status::kInvalidArgument);
}

TEST(Verify, SectionHashesAreCheckedOnlyWhenAsked) {
  Bytes file = testing::smallBrickedBox();
  View clean;
  ASSERT_EQ(View::open(file.data(), file.size(), &clean), Status::kOk);
  EXPECT_EQ(clean.verifyHashes(), Status::kOk);

  const auto pool = entryOf(file, format::kTagBrickPool);
  file[pool.offset + 5] ^= 0x10; // one bit of one voxel word
  View damaged;
  ASSERT_EQ(View::open(file.data(), file.size(), &damaged), Status::kOk) << "open() checks structure, not payload";
  Diagnostic diag;
  EXPECT_EQ(damaged.verifyHashes(&diag), Status::kSectionHashMismatch);
  EXPECT_NE(std::string(diag.message).find("BPOL"), std::string::npos) << diag.message;
  EXPECT_EQ(View().verifyHashes(), Status::kInvalidArgument);
}

// The padding between sections is zero (FORMAT.md §2); no hash covers it, so V18 checks it byte by byte.
TEST(Verify, NonZeroPaddingIsDamage) {
  const Bytes clean = testing::smallBrickedBox();
  const auto meta = entryOf(clean, format::kTagMetadata);
  const auto top = entryOf(clean, format::kTagBrickTop);
  ASSERT_LT(meta.offset + meta.size, top.offset) << "the test needs a gap after META";
  for (std::uint64_t at : {meta.offset + meta.size, top.offset - 1}) {
    Bytes file = clean;
    file[at] = 0x20;
    View view;
    ASSERT_EQ(View::open(file.data(), file.size(), &view), Status::kOk);
    Diagnostic diag;
    EXPECT_EQ(view.verifyHashes(&diag), Status::kNonZeroPadding) << at;
    EXPECT_STREQ(diag.rule, "V18");
    EXPECT_NE(std::string(diag.message).find(std::to_string(at)), std::string::npos) << diag.message;
  }
}

// Each failure names its FORMAT.md rule in Diagnostic::rule, the same ID dngdump prints.
// V22: the second planes' section must add up (header, masks, records, first indices, slots), its first
// indices must count the planes before them, its slots name blocks it holds on tiles with band voxels,
// and dense files have none.
TEST(Reject, SecondPlanesThatDoNotAddUp) {
  const Bytes file = testing::smallBrickedBoxSecondPlanes();
  ASSERT_EQ(openStatus(file), Status::kOk);
  const auto section = entryOf(file, format::kTagSecondPlanes);
  const auto header = peek<format::SecondPlanesHeader>(file, section.offset);
  ASSERT_GT(header.blocks, 1u);
  const std::size_t masks = section.offset + 8, first = masks + header.blocks * 8 + header.planes * 8,
                    slots = first + header.blocks * 4;
  const auto reject = [&](Bytes bytes, const char* what) {
    format::resealHashes(bytes);
    View view;
    Diagnostic diag;
    EXPECT_NE(View::open(bytes.data(), bytes.size(), &view, &diag), Status::kOk) << what;
    EXPECT_STREQ(diag.rule, "V22") << what;
  };
  reject(withEntry(file, format::kTagSecondPlanes, [](SectionEntry& e) { e.size -= 8; }), "a record short");
  Bytes planes = file;
  poke(planes, section.offset + 4, header.planes + 1);
  reject(planes, "the header counts more planes than there are");
  Bytes index = file;
  poke(index, first + 4, peek<std::uint32_t>(index, first + 4) + 1);
  reject(index, "a first index that skips a plane");
  Bytes mask = file;
  poke(mask, masks, peek<std::uint64_t>(mask, masks) ^ 1u);
  reject(mask, "a mask bit that does not match the count");
  // A slot past the blocks, and a block on a far tile.
  std::size_t with_block = 0, far = 0;
  const auto top = entryOf(file, format::kTagBrickTop);
  for (std::size_t t = 0; t < top.size / 8; ++t) {
    const bool has = peek<std::uint32_t>(file, slots + 4 * t) != format::kNoSecondPlanes;
    if (has && with_block == 0) with_block = slots + 4 * t;
    if (format::entryKind(peek<std::uint64_t>(file, top.offset + 8 * t)) == format::TileKind::kFarOutside && far == 0)
      far = slots + 4 * t;
  }
  ASSERT_NE(with_block * far, 0u);
  Bytes past = file;
  poke(past, with_block, header.blocks);
  reject(past, "a slot past the blocks");
  Bytes on_far = file;
  poke(on_far, far, std::uint32_t(0));
  reject(on_far, "a block on a far tile");
  // The same section in a dense file.
  format::ContainerBuilder builder;
  const Bytes dense = testing::smallDensePlane();
  for (std::uint32_t tag : {format::kTagGrid, format::kTagMetadata, format::kTagDense}) {
    const auto e = entryOf(dense, tag);
    builder.addSection(tag, e.flags, dense.data() + e.offset, e.size);
  }
  const std::uint32_t empty[2] = {0, 0};
  builder.addSection(format::kTagSecondPlanes, 0, empty, sizeof empty);
  reject(builder.finish(), "second planes in a dense file");
}

TEST(Reject, DiagnosticsNameTheirRule) {
  const Bytes good = testing::smallBrickedBox();
  const auto ruleOf = [](const Bytes& bytes) {
    View view;
    Diagnostic diag;
    EXPECT_NE(View::open(bytes.data(), bytes.size(), &view, &diag), Status::kOk);
    return std::string(diag.rule);
  };
  Bytes magic = good;
  magic[1] = 'X';
  EXPECT_EQ(ruleOf(magic), "V4");
  EXPECT_EQ(ruleOf(Bytes(good.begin(), good.end() - 1)), "V8");
  EXPECT_EQ(ruleOf(withGrid(good, [](GridSection& g) { g.voxel_size = -1.0f; })), "V12");
  Bytes pool = good;
  pool[entryOf(pool, format::kTagBrickPool).offset] ^= 1;
  View view;
  ASSERT_EQ(View::open(pool.data(), pool.size(), &view), Status::kOk);
  Diagnostic diag;
  EXPECT_EQ(view.verifyHashes(&diag), Status::kSectionHashMismatch);
  EXPECT_STREQ(diag.rule, "V17");
  EXPECT_EQ(View::open(nullptr, 0, nullptr, &diag), Status::kInvalidArgument);
  EXPECT_STREQ(diag.rule, "") << "a bad argument breaks no file rule";
}

// A cheap deterministic fuzz pass: random byte flips with resealed hashes. Whatever open() says,
// nothing may crash, and a view that opens must answer every query with finite or "no field".
TEST(Fuzz, RandomDamageNeverBreaksQueries) {
  const Bytes pristine = testing::smallBrickedBox();
  const auto points = analytic::randomPoints({-13, -13, -13}, {13, 13, 13}, 64, 5);
  std::mt19937 rng(1234);
  int opened = 0;
  for (int round = 0; round < 3000; ++round) {
    Bytes file = pristine;
    const int flips = 1 + int(rng() % 4);
    for (int f = 0; f < flips; ++f)
      file[rng() % file.size()] ^= std::uint8_t(1u << (rng() % 8));
    format::resealHashes(file);
    View view;
    if (View::open(file.data(), file.size(), &view) != Status::kOk) continue;
    ++opened;
    for (const Vec3f& p : points) {
      for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear}) {
        const Sample s = view.sample(p, mode);
        ASSERT_TRUE(s.status == SampleStatus::kNoField || std::isfinite(s.distance));
        ASSERT_TRUE(std::isfinite(s.normal.x) && std::isfinite(s.normal.y) && std::isfinite(s.normal.z));
      }
    }
  }
  EXPECT_GT(opened, 0) << "payload flips should leave many files structurally valid";
}

} // namespace
} // namespace dng
