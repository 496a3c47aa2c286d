// dngdump: inspect, validate, query and draw .dng files. It reads through the runtime, so it reads
// exactly what a game reads. Exit codes: 0 ok, 1 usage, 2 I/O, 3 invalid file or input.
#include "dump.h"

#include "command_line.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using namespace dng;
using namespace dng::dump;

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

// The stable finding ID: the FORMAT.md rule ("V8") every diagnostic starts with, or IO.
std::string findingId(const Diagnostic& diag) {
  if (diag.status == Status::kIoError) return "IO";
  const char* colon = std::strchr(diag.message, ':');
  if (diag.message[0] == 'V' && colon != nullptr && colon - diag.message <= 4)
    return std::string(diag.message, std::size_t(colon - diag.message));
  return "E" + std::to_string(int(diag.status));
}

int exitFor(Status status) { return status == Status::kIoError ? kIo : kInvalid; }

void printFinding(const CommandLine& cl, const Diagnostic& diag) {
  if (cl.json) {
    const nlohmann::ordered_json j = {
        {"format", "dngdump-check"},
        {"version", 1},
        {"file", cl.file},
        {"valid", false},
        {"findings", {{{"id", findingId(diag)}, {"status", statusString(diag.status)}, {"message", diag.message}}}}};
    std::printf("%s\n", j.dump(2).c_str());
  }
  std::fprintf(stderr, "dngdump: %s: error %s (%s): %s\n", cl.file.c_str(), findingId(diag).c_str(),
               statusString(diag.status), diag.message);
}

int runCheck(const CommandLine& cl, const View& view) {
  Diagnostic diag;
  if (view.verifyHashes(&diag) != Status::kOk) {
    printFinding(cl, diag);
    return kInvalid;
  }
  if (cl.json) {
    const nlohmann::ordered_json j = {{"format", "dngdump-check"},
                                      {"version", 1},
                                      {"file", cl.file},
                                      {"valid", true},
                                      {"findings", nlohmann::json::array()}};
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s: valid (rules V1-V17 of docs/FORMAT.md, every section hash checked)\n", cl.file.c_str());
  }
  return kOk;
}

// One point per line, "x y z"; the answers come out in the same order, one line each.
int runQuery(const CommandLine& cl, const View& view) {
  std::ifstream file;
  if (!cl.points.empty()) {
    file.open(cl.points);
    if (!file) {
      std::fprintf(stderr, "dngdump: error: cannot read points from '%s'\n", cl.points.c_str());
      return kIo;
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
  return bad_lines == 0 ? kOk : kInvalid;
}

int runSlice(const CommandLine& cl, const View& view) {
  SliceRequest request;
  const std::string& s = cl.slice;
  if (s.size() < 3 || std::strchr("xyz", s[0]) == nullptr || s[1] != '=') {
    std::fprintf(stderr, "dngdump: error: --slice takes x=VALUE, y=VALUE or z=VALUE, got \"%s\"\n", s.c_str());
    return kUsage;
  }
  try {
    std::size_t used = 0;
    request.value = std::stof(s.substr(2), &used);
    if (used != s.size() - 2) throw std::invalid_argument(s);
  } catch (const std::exception&) {
    std::fprintf(stderr, "dngdump: error: --slice value \"%s\" is not a number\n", s.substr(2).c_str());
    return kUsage;
  }
  request.axis = s[0] - 'x';
  request.scale = cl.scale;
  request.png = cl.png;
  return renderSlice(view, request);
}

void addOptions(CLI::App& app, CommandLine& cl) {
  app.add_option("file", cl.file, "the .dng file")->required();
  app.add_flag("--json", cl.json, "machine-readable output (summary, --check or --stats)");
  app.add_flag("--check", cl.check, "full validation including every section hash; exit 0 only if valid");
  app.add_flag("--query", cl.query, "read \"x y z\" lines (stdin or --points), write \"distance nx ny nz\" or none");
  app.add_option("--points", cl.points, "file of points for --query");
  app.add_flag("--trilinear", cl.trilinear, "--query with trilinear interpolation instead of nearest");
  auto* slice = app.add_option("--slice", cl.slice, "x=VALUE, y=VALUE or z=VALUE (grid-local), with --png");
  auto* png = app.add_option("--png", cl.png, "where --slice writes its picture");
  slice->needs(png);
  png->needs(slice);
  app.add_option("--scale", cl.scale, "--slice pixels per voxel (default: about 768 pixels across)")
      ->check(CLI::Range(1, 64));
  app.add_flag("--stats", cl.stats, "histograms of distance and of normal deviation, band coverage");
  app.set_version_flag("--version", DNG_TOOL_VERSION);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"dngdump: inspect, validate, query and draw .dng files", "dngdump"};
  CommandLine cl;
  addOptions(app, cl);
  if (const int code = dng::tools::parseOrExitCode(app, argc, argv); code >= 0) return code;
  File file;
  Diagnostic diag;
  if (File::open(cl.file.c_str(), &file, &diag) != Status::kOk) {
    printFinding(cl, diag);
    return exitFor(diag.status);
  }
  const View& view = file.view();
  if (cl.check) return runCheck(cl, view);
  if (cl.query) return runQuery(cl, view);
  if (!cl.slice.empty()) return runSlice(cl, view);
  if (cl.stats) {
    printStats(view, cl.json);
    return kOk;
  }
  if (cl.json) {
    printJson(cl.file, view);
  } else {
    printSummary(cl.file, view);
  }
  return kOk;
}
