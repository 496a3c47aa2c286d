// Byte-for-byte pins of the writer's output. A change here is a format change: bump the version
// per docs/FORMAT.md, note it in docs/CHANGELOG.md, then regenerate with DNG_UPDATE_GOLDEN=1 (which
// rewrites a differing file and still fails: review and commit it, then run again).
#include "analytic_fields.h"
#include "dng/view.h"
#include "sample_files.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace dng {
namespace {

void compareWithGolden(const char* name, const std::vector<std::uint8_t>& bytes) {
  const std::string path = testing::goldenPath(name);
  const std::vector<std::uint8_t> golden = testing::readFileBytes(path);
  if (golden != bytes && std::getenv("DNG_UPDATE_GOLDEN") != nullptr) {
    testing::writeFileBytes(path, bytes);
    FAIL() << "rewrote " << path << ": review it, commit it and run the test again";
  }
  ASSERT_EQ(golden.size(), bytes.size()) << path;
  for (std::size_t i = 0; i < golden.size(); ++i) {
    ASSERT_EQ(golden[i], bytes[i]) << path << " differs first at byte " << i;
  }
  // The pinned files must also stay readable by this runtime.
  View view;
  Diagnostic diag;
  EXPECT_EQ(View::open(golden.data(), golden.size(), &view, &diag), Status::kOk) << diag.message;
  EXPECT_EQ(view.verifyHashes(), Status::kOk);
}

TEST(Golden, DensePlane) { compareWithGolden("dense_plane.dng", testing::smallDensePlane()); }
TEST(Golden, BrickedBox) { compareWithGolden("bricked_box.dng", testing::smallBrickedBox()); }
TEST(Golden, BrickedBoxLifted) { compareWithGolden("bricked_box_lifted.dng", testing::smallBrickedBoxLifted()); }
TEST(Golden, BrickedBoxGraded) { compareWithGolden("bricked_box_graded.dng", testing::smallBrickedBoxGraded()); }
TEST(Golden, BrickedBoxShaded) { compareWithGolden("bricked_box_shaded.dng", testing::smallBrickedBoxShaded()); }
TEST(Golden, BrickedBoxSecondPlanes) {
  compareWithGolden("bricked_box_second_planes.dng", testing::smallBrickedBoxSecondPlanes());
}

// Files an older writer made (kept in golden/v1_<minor>) still open, and read exactly as the same
// fields written by this writer: 1.2 added optional sections (LIFT, GRAD) and 1.3 another (SHAD), so
// the bytes of a field that has none of the newer ones differ only in the version.
void expectOldFilesReadAsBefore(int minor, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    SCOPED_TRACE(name);
    const std::string folder = "v1_" + std::to_string(minor) + "/";
    const std::vector<std::uint8_t> old_bytes = testing::readFileBytes(testing::goldenPath(folder.c_str()) + name);
    const std::vector<std::uint8_t> new_bytes = testing::readFileBytes(testing::goldenPath(name));
    View old_view, new_view;
    ASSERT_EQ(View::open(old_bytes.data(), old_bytes.size(), &old_view), Status::kOk);
    ASSERT_EQ(View::open(new_bytes.data(), new_bytes.size(), &new_view), Status::kOk);
    EXPECT_EQ(old_view.versionMinor(), minor);
    EXPECT_EQ(new_view.versionMinor(), format::kVersionMinor);
    EXPECT_EQ(old_view.hasLift(), new_view.hasLift());
    EXPECT_EQ(old_view.hasGradient(), new_view.hasGradient());
    EXPECT_FALSE(old_view.hasShading());
    const GridInfo& g = old_view.grid();
    const Vec3f hi = g.origin + Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
    for (const Vec3f& p : analytic::randomPoints(g.origin, hi, 500, 7)) {
      for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear, Interpolation::kAccurate}) {
        const Sample a = old_view.sample(p, mode), b = new_view.sample(p, mode);
        ASSERT_EQ(a.status, b.status);
        ASSERT_EQ(a.distance, b.distance);
        ASSERT_EQ(a.normal.x, b.normal.x);
      }
    }
  }
}

TEST(Golden, Version11FilesReadAsBefore) { expectOldFilesReadAsBefore(1, {"dense_plane.dng", "bricked_box.dng"}); }

TEST(Golden, Version12FilesReadAsBefore) {
  expectOldFilesReadAsBefore(
      2, {"dense_plane.dng", "bricked_box.dng", "bricked_box_lifted.dng", "bricked_box_graded.dng"});
}

} // namespace
} // namespace dng
