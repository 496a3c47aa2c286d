// dngdump as a user runs it: golden summary and JSON, --check on good and damaged files, --query
// against the runtime's own answers, and the slice picture decoded and looked at.
#include "dng/file.h"
#include "sample_files.h"

#include "run_program.h"
#include "temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <png.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
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
  const testing::ProgramRun run = testing::runProgram("cd '" + dir + "' && " + testing::shellQuoted(DNG_DNGDUMP_PATH) +
                                                      " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null"));
  return {run.exit_code, run.output};
}

// DNG_UPDATE_GOLDEN=1 rewrites a golden file that differs, and the test still fails: a rewritten
// golden is a change to review and commit, never a pass.
void compareWithGoldenText(const std::string& name, const std::string& actual) {
  const std::string path = testing::goldenPath(name.c_str());
  const std::string expected = testing::readFile(path);
  EXPECT_EQ(actual, expected) << "differs from " << path;
  if (actual != expected && std::getenv("DNG_UPDATE_GOLDEN") != nullptr) {
    std::ofstream(path) << actual;
    ADD_FAILURE() << "rewrote " << path << ": review it, commit it and run the test again";
  }
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
  EXPECT_NE(run.out.find("error V8 (file truncated): file is truncated: header says"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("V8:"), std::string::npos) << "the rule ID is printed once: " << run.out;
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
  // The picture never replaces the file being read, nor anything but a regular file.
  const ProgramRun over_input = dngdump(dir_, "box.dng --slice z=0.5 --png ./box.dng", true);
  EXPECT_EQ(over_input.exit_code, 1) << over_input.out;
  EXPECT_NE(over_input.out.find("is the file being read"), std::string::npos) << over_input.out;
  EXPECT_EQ(testing::readFileBytes(dir_ + "/box.dng"), bytes_);
  fs::create_directory(dir_ + "/pictures");
  EXPECT_EQ(dngdump(dir_, "box.dng --slice z=0.5 --png pictures").exit_code, 2);
  EXPECT_TRUE(fs::is_directory(dir_ + "/pictures"));
}

// Output that could not be written (here /dev/full, as on a full disk) is an I/O error in every mode
// that writes to standard output, not a success with a cut or empty report.
TEST_F(DumpTest, LostStandardOutputIsAnIoError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  for (const char* args :
       {"box.dng", "box.dng --json", "box.dng --stats", "box.dng --check", "box.dng --query", "--help", "--version"}) {
    SCOPED_TRACE(args);
    const testing::ProgramRun run =
        testing::runProgram("cd '" + dir_ + "' && echo 0 0 0 | " + testing::shellQuoted(DNG_DNGDUMP_PATH) + " " + args +
                            " 2>&1 >/dev/full");
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("dngdump: error: cannot write to standard output"), std::string::npos) << run.output;
  }
  EXPECT_EQ(dngdump(dir_, "box.dng").exit_code, 0); // and where it can write, nothing changes
}

// --points names a file of points: a folder is an I/O error (it had read as no points at all).
TEST_F(DumpTest, QueryPointsFromAFolderAreAnIoError) {
  fs::create_directory(dir_ + "/points");
  const ProgramRun run = dngdump(dir_, "box.dng --query --points points", true);
  EXPECT_EQ(run.exit_code, 2) << run.out;
  EXPECT_NE(run.out.find("cannot read points"), std::string::npos) << run.out;
}

TEST_F(DumpTest, StatsCountTheBand) {
  View view;
  ASSERT_EQ(View::open(bytes_.data(), bytes_.size(), &view), Status::kOk);
  const GridInfo& g = view.grid();
  std::uint64_t band = 0, total = 0;
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i, ++total) {
        const Vec3f centre = g.origin + Vec3f{float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f} * g.voxel_size;
        band += view.sample(centre).status == SampleStatus::kInBand ? 1 : 0;
      }
  ASSERT_GT(band, 0u);
  ASSERT_LT(band, total);

  const ProgramRun run = dngdump(dir_, "box.dng --stats --json");
  ASSERT_EQ(run.exit_code, 0);
  const nlohmann::json stats = nlohmann::json::parse(run.out);
  EXPECT_EQ(stats["format"], "dngdump-stats");
  EXPECT_DOUBLE_EQ(stats["band_coverage"].get<double>(), double(band) / double(total));
  EXPECT_FLOAT_EQ(stats["distance_histogram"]["from"].get<float>(), -g.band);
  EXPECT_FLOAT_EQ(stats["distance_histogram"]["to"].get<float>(), g.band);
  std::uint64_t histogram_total = 0; // every voxel centre in band lands in exactly one bin
  for (const auto& count : stats["distance_histogram"]["counts"])
    histogram_total += count.get<std::uint64_t>();
  EXPECT_EQ(histogram_total, band);
  std::uint64_t pairs = 0;
  for (const auto& count : stats["neighbour_normal_deviation_degrees"]["counts"])
    pairs += count.get<std::uint64_t>();
  EXPECT_GT(pairs, 0u);
  EXPECT_LE(pairs, 3 * band); // at most one pair per axis per band voxel

  const ProgramRun text = dngdump(dir_, "box.dng --stats");
  EXPECT_NE(text.out.find("of " + std::to_string(total) + " voxels"), std::string::npos) << text.out;
}

// The summary's JSON twin holds the runtime's numbers, not only the right key names.
TEST_F(DumpTest, JsonReportHoldsTheFilesNumbers) {
  View view;
  ASSERT_EQ(View::open(bytes_.data(), bytes_.size(), &view), Status::kOk);
  const ProgramRun run = dngdump(dir_, "box.dng --json");
  ASSERT_EQ(run.exit_code, 0);
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["encoding"], "bricked");
  EXPECT_EQ(report["dims"], nlohmann::json::array({24, 24, 24}));
  EXPECT_EQ(report["file_bytes"].get<std::size_t>(), bytes_.size());
  EXPECT_EQ(report["tiles"]["brick"].get<std::uint64_t>(), view.tileCounts().brick);
  EXPECT_EQ(report["tiles"]["plane"].get<std::uint64_t>(), view.tileCounts().plane);
  EXPECT_FLOAT_EQ(report["guaranteed_reach"].get<float>(), view.guaranteedReach());
  EXPECT_EQ(report["metadata"]["test"], "small bricked box");
}

// Exactly one mode runs; an option that belongs to a mode is refused without it.
TEST_F(DumpTest, ModesExcludeEachOtherAndTheirOptionsNeedThem) {
  std::ofstream(dir_ + "/points.txt") << "0 0 0\n";
  for (const char* args : {"--check --query --stats", "--check --stats", "--query --stats", "--check --query",
                           "--stats --slice z=0 --png s.png", "--query --json", "--slice z=0 --png s.png --json",
                           "--points points.txt", "--trilinear", "--scale 4", "--png s.png"}) {
    const ProgramRun run = dngdump(dir_, std::string("box.dng ") + args, true);
    EXPECT_EQ(run.exit_code, 1) << args << ": " << run.out;
  }
  EXPECT_FALSE(fs::exists(dir_ + "/s.png"));
  EXPECT_EQ(dngdump(dir_, "box.dng --query --points points.txt --trilinear").exit_code, 0);
  EXPECT_EQ(dngdump(dir_, "box.dng --check --json").exit_code, 0);
  EXPECT_EQ(dngdump(dir_, "box.dng --stats --json").exit_code, 0);
}

// Metadata is untrusted text: not UTF-8, nested deeper than any serializer's stack, or terminal
// escapes. Every mode handles every file View::open accepts (these once aborted dngdump).
TEST_F(DumpTest, EveryModeSurvivesUntrustedMetadata) {
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  const struct {
    const char* name;
    std::string metadata;
  } files[] = {{"not_utf8.dng", "{\"tool\":\"\xff\xfe\xc3(\"}"},
               {"not_json_not_utf8.dng", "\x80\x81 plain bytes \xff"},
               {"deep.dng", deep},
               {"escape.dng", "\x1b[2J\x1b]0;title\x07"}};
  std::ofstream(dir_ + "/points.txt") << "0 0 0\n1 2 3\n";
  for (const auto& file : files) {
    SCOPED_TRACE(file.name);
    testing::writeFileBytes(dir_ + "/" + file.name, testing::smallBrickedBox(file.metadata));
    for (const char* mode : {"", "--json", "--stats", "--stats --json", "--check", "--check --json",
                             "--query --points points.txt", "--slice z=0.5 --png slice.png"}) {
      const ProgramRun run = dngdump(dir_, std::string(file.name) + " " + mode, true);
      EXPECT_EQ(run.exit_code, 0) << mode << ": " << run.out;
    }
    const ProgramRun summary = dngdump(dir_, file.name);
    EXPECT_NE(summary.out.find("  metadata   \""), std::string::npos) << "kept as a quoted string: " << summary.out;
    EXPECT_EQ(summary.out.find('\x1b'), std::string::npos) << "escapes reach the terminal";
    const ProgramRun json = dngdump(dir_, std::string(file.name) + " --json");
    const nlohmann::json report = nlohmann::json::parse(json.out, nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << json.out.substr(0, 200);
    EXPECT_TRUE(report["metadata"].is_string());
  }
}

// A finding quotes the file's bytes (here a section tag): --json must still print valid JSON.
TEST_F(DumpTest, FindingsQuotingUntrustedBytesStayValidJson) {
  auto damaged = bytes_;
  const std::size_t at = testing::entryOffset(damaged, format::kTagBrickPool);
  const std::uint8_t tag[4] = {0xff, 0xfe, 0x80, 0x81}; // unknown, required, not UTF-8
  std::memcpy(damaged.data() + at, tag, 4);
  format::resealHashes(damaged);
  testing::writeFileBytes(dir_ + "/tag.dng", damaged);
  for (const char* mode : {"--json", "--check --json", "--stats --json"}) {
    const ProgramRun run = dngdump(dir_, std::string("tag.dng ") + mode);
    EXPECT_EQ(run.exit_code, 3) << mode;
    const nlohmann::json finding = nlohmann::json::parse(run.out, nullptr, false);
    ASSERT_FALSE(finding.is_discarded()) << run.out;
    EXPECT_EQ(finding["valid"], false);
    EXPECT_EQ(finding["findings"][0]["id"], "V11");
  }
}

// A grid may be 2^24 voxels long: the slice it would need is refused, not allocated.
TEST_F(DumpTest, SliceOfAHugeGridIsRefusedNotAllocated) {
  format::GridGeometry grid;
  grid.origin = {0, 0, 0};
  grid.voxel_size = 1.0f;
  grid.dims[0] = 1u << 16;
  grid.dims[1] = 16;
  grid.dims[2] = 1;
  grid.band = 2.0f;
  format::DenseField far;
  far.grid = grid;
  far.distance.assign(grid.voxelCount(), 5.0f);
  far.normal.assign(grid.voxelCount(), Vec3f{});
  const format::EncodeResult encoded = format::encodeBricked(far, {}, "");
  ASSERT_TRUE(encoded.ok()) << encoded.error;
  testing::writeFileBytes(dir_ + "/long.dng", encoded.bytes);
  const ProgramRun run = dngdump(dir_, "long.dng --slice z=0.5 --png long.png", true);
  EXPECT_EQ(run.exit_code, 5) << run.out;
  EXPECT_NE(run.out.find("exceeds 16384 pixels"), std::string::npos) << run.out;
  EXPECT_FALSE(fs::exists(dir_ + "/long.png"));
}

} // namespace
} // namespace dng
