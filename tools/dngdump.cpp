// dngdump: inspect, validate, query and draw .dng files. It reads through the runtime, so it reads
// exactly what a game reads. Exit codes: exit_codes.h (docs/BAKING.md).
#include "dump.h"
#include "dump_json.h"

#include "command_line.h"
#include "standard_output.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using namespace dng;
using namespace dng::dump;
using namespace dng::tools;

struct CommandLine {
  std::string file;
  bool json = false;
  bool check = false;
  bool query = false;
  std::string points;
  bool trilinear = false;
  std::string slice;
  std::string png;
  int scale = 0;
  bool stats = false;
};

int exitFor(Status status) { return status == Status::kIoError ? kExitIo : kExitInvalid; }

// The rule ID once, then the sentence: "error V8 (file truncated): file is truncated: ...".
void printFinding(const CommandLine& cl, const Diagnostic& diag) {
  if (cl.json) printFindingJson(stdout, cl.file, diag);
  std::fprintf(stderr, "dngdump: %s: error %s (%s): %s\n", cl.file.c_str(), findingId(diag).c_str(),
               statusString(diag.status), diag.message);
}

int runCheck(const CommandLine& cl, const View& view) {
  Diagnostic diag;
  if (view.verifyHashes(&diag) != Status::kOk) {
    printFinding(cl, diag);
    return kExitInvalid;
  }
  if (cl.json) {
    const Json j = {
        {"format", "dngdump-check"}, {"version", 1}, {"file", cl.file}, {"valid", true}, {"findings", Json::array()}};
    std::printf("%s\n", toText(j).c_str());
  } else {
    std::printf("%s: valid (rules V1-V22 of docs/FORMAT.md: every section hash and the padding checked)\n",
                cl.file.c_str());
  }
  return kExitOk;
}

// One point per line, "x y z"; the answers come out in the same order, one line each.
int runQuery(const CommandLine& cl, const View& view) {
  std::ifstream file;
  if (!cl.points.empty()) {
    std::error_code error;
    if (!std::filesystem::is_directory(cl.points, error)) file.open(cl.points); // a pipe is fine
    if (!file.is_open()) {
      std::fprintf(stderr, "dngdump: error: cannot read points from '%s'\n", cl.points.c_str());
      return kExitIo;
    }
  }
  std::istream& in = cl.points.empty() ? std::cin : file;
  const Interpolation mode = cl.trilinear ? Interpolation::kTrilinear : Interpolation::kNearest;
  int bad_lines = 0;
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    float x, y, z;
    std::string extra;
    if (!(words >> x >> y >> z) || (words >> extra)) {
      std::fprintf(stderr, "dngdump: line %ld: expected three numbers \"x y z\", got \"%s\"\n", number, line.c_str());
      std::printf("invalid\n");
      ++bad_lines;
      continue;
    }
    const Sample s = view.sample({x, y, z}, mode);
    if (s.status == SampleStatus::kNoField) {
      std::printf("none\n");
    } else {
      std::printf("%.9g %.9g %.9g %.9g\n", double(s.distance), double(s.normal.x), double(s.normal.y),
                  double(s.normal.z));
    }
  }
  if (in.bad()) {
    std::fprintf(stderr, "dngdump: error: reading points failed\n");
    return kExitIo;
  }
  return bad_lines == 0 ? kExitOk : kExitInvalid;
}

// --png must not replace the file being read, nor anything that is not a regular file (a rename over
// /dev/null replaces the device).
int checkPicturePath(const CommandLine& cl) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(cl.png, error) && fs::equivalent(cl.png, cl.file, error)) {
    std::fprintf(stderr, "dngdump: error: --png '%s' is the file being read: refusing to write over it\n",
                 cl.png.c_str());
    return kExitUsage;
  }
  const fs::file_status status = fs::status(cl.png, error);
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    std::fprintf(stderr, "dngdump: error: --png '%s' exists and is not a regular file\n", cl.png.c_str());
    return kExitIo;
  }
  return kExitOk;
}

int runSlice(const CommandLine& cl, const View& view) {
  SliceRequest request;
  const std::string& s = cl.slice;
  if (s.size() < 3 || std::strchr("xyz", s[0]) == nullptr || s[1] != '=') {
    std::fprintf(stderr, "dngdump: error: --slice takes x=VALUE, y=VALUE or z=VALUE, got \"%s\"\n", s.c_str());
    return kExitUsage;
  }
  try {
    std::size_t used = 0;
    request.value = std::stof(s.substr(2), &used);
    if (used != s.size() - 2) throw std::invalid_argument(s);
  } catch (const std::exception&) {
    std::fprintf(stderr, "dngdump: error: --slice value \"%s\" is not a number\n", s.substr(2).c_str());
    return kExitUsage;
  }
  request.axis = s[0] - 'x';
  request.scale = cl.scale;
  request.png = cl.png;
  if (const int refused = checkPicturePath(cl); refused != kExitOk) return refused;
  return renderSlice(view, request);
}

// Exactly one mode runs: the summary (no mode option), --check, --query, --slice or --stats. The
// options that only make sense with one mode need it, so nothing given is ever silently ignored.
void addOptions(CLI::App& app, CommandLine& cl) {
  app.add_option("file", cl.file, "the .dng file")->required();
  auto* json = app.add_flag("--json", cl.json, "machine-readable output (summary, --check or --stats)");
  auto* check = app.add_flag("--check", cl.check, "full validation including every section hash; exit 0 only if valid");
  auto* query = app.add_flag("--query", cl.query,
                             "read \"x y z\" lines (stdin or --points), write \"distance nx ny nz\" or none");
  app.add_option("--points", cl.points, "file of points for --query")->needs(query);
  app.add_flag("--trilinear", cl.trilinear, "--query with trilinear interpolation instead of nearest")->needs(query);
  auto* slice = app.add_option("--slice", cl.slice, "x=VALUE, y=VALUE or z=VALUE (grid-local), with --png");
  auto* png = app.add_option("--png", cl.png, "where --slice writes its picture");
  slice->needs(png);
  png->needs(slice);
  app.add_option("--scale", cl.scale, "--slice pixels per voxel (default: about 768 pixels across)")
      ->check(CLI::Range(1, 64))
      ->needs(slice);
  auto* stats = app.add_flag("--stats", cl.stats, "histograms of distance and of normal deviation, band coverage");
  check->excludes(query)->excludes(slice)->excludes(stats);
  query->excludes(slice)->excludes(stats)->excludes(json);
  slice->excludes(stats)->excludes(json);
  app.set_version_flag("--version", DNG_TOOL_VERSION);
}

int run(const CommandLine& cl, const View& view) {
  if (cl.check) return runCheck(cl, view);
  if (cl.query) return runQuery(cl, view);
  if (!cl.slice.empty()) return runSlice(cl, view);
  if (cl.stats) {
    printStats(stdout, view, cl.json);
  } else if (cl.json) {
    printJson(stdout, cl.file, view);
  } else {
    printSummary(stdout, cl.file, view);
  }
  return kExitOk;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"dngdump: inspect, validate, query and draw .dng files", "dngdump"};
  CommandLine cl;
  addOptions(app, cl);
  if (const int code = dng::tools::parseOrExitCode(app, argc, argv); code >= 0)
    return finishStandardOutput("dngdump", code); // --help and --version print there
  File file;
  Diagnostic diag;
  if (File::open(cl.file.c_str(), &file, &diag) != Status::kOk) {
    printFinding(cl, diag);
    return finishStandardOutput("dngdump", exitFor(diag.status));
  }
  // The reports allocate (the slice picture, JSON); running out of memory is an error, not an abort.
  try {
    return finishStandardOutput("dngdump", run(cl, file.view()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dngdump: %s: internal error: %s\n", cl.file.c_str(), e.what());
    return kExitInternal;
  }
}
