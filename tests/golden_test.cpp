// Byte-for-byte pins of the writer's output. A change here is a format change: bump the version
// per docs/FORMAT.md, note it in docs/CHANGELOG.md, then regenerate with DNG_UPDATE_GOLDEN=1 (which
// rewrites a differing file and still fails: review and commit it, then run again).
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

} // namespace
} // namespace dng
