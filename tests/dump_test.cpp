// dngdump as a user runs it: golden summary and JSON, --check on good and damaged files, --query
// against the runtime's own answers, and the slice picture decoded and looked at.
#include "dng/file.h"
#include "sample_files.h"

#include "run_program.h"
#include "temp_dir.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace dng {
namespace {

namespace fs = std::filesystem;

struct ProgramRun {
  int exit_code = -1;
  std::string out; // stdout (and stderr when asked)
};

// Runs dngdump in `dir` (so reports name files relatively), stderr appended to stdout when asked.
ProgramRun dngdump(const std::string& dir, const std::string& args, bool with_stderr = false) {
  const testing::ProgramRun run = testing::runProgram("cd '" + dir + "' && " + DNG_DNGDUMP_PATH + " " + args +
                                                      (with_stderr ? " 2>&1" : " 2>/dev/null"));
  return {run.exit_code, run.output};
}

void compareWithGoldenText(const std::string& name, const std::string& actual) {
  const std::string path = testing::goldenPath(name.c_str());
  if (std::getenv("DNG_UPDATE_GOLDEN") != nullptr) {
    std::ofstream(path) << actual;
    return;
  }
  EXPECT_EQ(actual, testing::readFile(path)) << "differs from " << path;
}

class DumpTest : public ::testing::Test {
protected:
  void SetUp() override {
    bytes_ = testing::smallBrickedBox();
    testing::writeFileBytes(dir_ + "/box.dng", bytes_);
  }
  testing::TempDir temp_{"dump_test"};
  const std::string dir_ = temp_.path().string();
  std::vector<std::uint8_t> bytes_;
};

TEST_F(DumpTest, SummaryAndJsonMatchGoldenFiles) {
  const ProgramRun summary = dngdump(dir_, "box.dng");
  EXPECT_EQ(summary.exit_code, 0);
  compareWithGoldenText("bricked_box.summary.txt", summary.out);
  const ProgramRun json = dngdump(dir_, "box.dng --json");
  EXPECT_EQ(json.exit_code, 0);
  compareWithGoldenText("bricked_box.summary.json", json.out);
}

TEST_F(DumpTest, CheckPassesGoodFilesAndNamesTheBrokenRule) {
  ProgramRun run = dngdump(dir_, "box.dng --check");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("valid"), std::string::npos);

  auto damaged = bytes_;
  damaged[testing::entryOf(damaged, format::kTagBrickPool).offset + 9] ^= 4;
  testing::writeFileBytes(dir_ + "/payload.dng", damaged);
  run = dngdump(dir_, "payload.dng --check", true);
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.out.find("error V17 (section hash mismatch)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("BPOL"), std::string::npos) << run.out;
  run = dngdump(dir_, "payload.dng --check --json");
  EXPECT_NE(run.out.find("\"valid\": false"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("\"id\": \"V17\""), std::string::npos) << run.out;

  auto truncated = bytes_;
  truncated.resize(truncated.size() - 100);
  testing::writeFileBytes(dir_ + "/short.dng", truncated);
  run = dngdump(dir_, "short.dng --check", true);
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.out.find("error V8 (file truncated)"), std::string::npos) << run.out;
  run = dngdump(dir_, "short.dng", true); // every command refuses a broken file the same way
  EXPECT_EQ(run.exit_code, 3);

  std::ofstream(dir_ + "/text.dng") << "hello, not a grid";
  run = dngdump(dir_, "text.dng --check", true);
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.out.find("V3"), std::string::npos) << run.out; // 17 bytes: shorter than the header

  run = dngdump(dir_, "absent.dng", true);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.out.find("error IO"), std::string::npos) << run.out;
  EXPECT_EQ(dngdump(dir_, "box.dng --no-such-option").exit_code, 1);
}

TEST_F(DumpTest, QueryAnswersWhatTheRuntimeAnswersInOrder) {
  View view;
  ASSERT_EQ(View::open(bytes_.data(), bytes_.size(), &view), Status::kOk);
  std::ostringstream points;
  std::vector<Vec3f> asked;
  for (int n = 0; n < 200; ++n) {
    const Vec3f p{-13.0f + 0.13f * float(n), 6.3f - 0.05f * float(n), 0.4f};
    asked.push_back(p);
    points << std::setprecision(9) << p.x << ' ' << p.y << ' ' << p.z << '\n'; // round-trips exactly
  }
  points << "1 2\n"; // a bad line: reported, answered "invalid" to keep the lines aligned
  std::ofstream(dir_ + "/points.txt") << points.str();
  for (const char* mode : {"", " --trilinear"}) {
    const ProgramRun run = dngdump(dir_, std::string("box.dng --query --points points.txt") + mode);
    EXPECT_EQ(run.exit_code, 3); // because of the bad line
    std::istringstream lines(run.out);
    std::string line;
    for (const Vec3f& p : asked) {
      ASSERT_TRUE(std::getline(lines, line));
      const Sample s = view.sample(p, mode[0] ? Interpolation::kTrilinear : Interpolation::kNearest);
      if (s.status == SampleStatus::kNoField) {
        ASSERT_EQ(line, "none");
        continue;
      }
      float d, nx, ny, nz;
      ASSERT_EQ(std::sscanf(line.c_str(), "%f %f %f %f", &d, &nx, &ny, &nz), 4) << line;
      ASSERT_FLOAT_EQ(d, s.distance);
      ASSERT_FLOAT_EQ(nx, s.normal.x);
    }
    ASSERT_TRUE(std::getline(lines, line));
    EXPECT_EQ(line, "invalid");
  }
  const ProgramRun reported = dngdump(dir_, "box.dng --query --points points.txt", true);
  EXPECT_NE(reported.out.find("line 201"), std::string::npos);
}

// Reads an 8-bit RGB PNG with libpng.
bool readPng(const std::string& path, int* out_width, int* out_height, std::vector<std::uint8_t>* out_rgb) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return false;
  image.format = PNG_FORMAT_RGB;
  out_rgb->resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out_rgb->data(), 0, nullptr)) return false;
  *out_width = int(image.width);
  *out_height = int(image.height);
  return true;
}

TEST_F(DumpTest, SliceIsAPictureWithTheContourWhereTheSurfaceIs) {
  const ProgramRun run = dngdump(dir_, "box.dng --slice z=0.5 --png slice.png --scale 8");
  ASSERT_EQ(run.exit_code, 0);
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(readPng(dir_ + "/slice.png", &width, &height, &rgb));
  EXPECT_EQ(width, 24 * 8);
  EXPECT_EQ(height, 24 * 8);
  auto pixel = [&](int x, int y) { return &rgb[(std::size_t(y) * width + x) * 3]; };
  auto isBlack = [&](int x, int y) { return pixel(x, y)[0] < 10 && pixel(x, y)[1] < 10 && pixel(x, y)[2] < 10; };
  // The box's +x face is at x = 6.25: column (6.25 + 12) * 8 = 146. Row of y = 2.5, between the rows
  // of arrows (one every 2 voxels from the centre of voxel 1).
  const int row = int((12.0f - 2.5f) * 8);
  bool contour = false;
  for (int x = 144; x <= 148; ++x)
    contour = contour || isBlack(x, row);
  EXPECT_TRUE(contour);
  for (int x = 8 * 8; x < 16 * 8; ++x)
    EXPECT_FALSE(isBlack(x, row)) << "no surface at column " << x;
  const std::uint8_t* inside = pixel((int)((5.5f + 12) * 8), row); // just inside the face: blue
  EXPECT_GT(inside[2], inside[0]);
  const std::uint8_t* outside = pixel((int)((7.0f + 12) * 8), row); // just outside: orange
  EXPECT_GT(outside[0], outside[2]);

  EXPECT_EQ(dngdump(dir_, "box.dng --slice z=99 --png far.png").exit_code, 1);
  EXPECT_EQ(dngdump(dir_, "box.dng --slice w=1 --png w.png").exit_code, 1);
  EXPECT_FALSE(fs::exists(dir_ + "/far.png"));
}

TEST_F(DumpTest, StatsCountTheBand) {
  const ProgramRun run = dngdump(dir_, "box.dng --stats --json");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("\"band_coverage\""), std::string::npos);
  EXPECT_NE(run.out.find("neighbour_normal_deviation_degrees"), std::string::npos);
  const ProgramRun text = dngdump(dir_, "box.dng --stats");
  EXPECT_NE(text.out.find("band coverage: "), std::string::npos) << text.out;
}

} // namespace
} // namespace dng
