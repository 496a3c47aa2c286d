// libFuzzer target for dngdump's report path: every file View::open accepts goes through the summary,
// the --json report and --stats (text and JSON), and every refusal through the --check findings, as
// dngdump prints them. A .dng's metadata and section tags are untrusted bytes: nothing here may throw,
// abort or trip a sanitizer. Seeds: tests/golden/*.dng and tests/fuzz/dump_regressions/*.
//
// Hashes are resealed first, as in fuzz_open.cpp, so mutations reach the rules behind them.
#include "dump.h"

#include "dng/format/writer.h"

#include <cstdint>
#include <cstdio>
#include <vector>

namespace {

// The reports walk every voxel; past this many a run would take seconds and the fuzzer would stall.
constexpr std::uint64_t kMaxReportedVoxels = std::uint64_t(1) << 22;

std::FILE* sink() {
  static std::FILE* null = std::fopen("/dev/null", "w");
  return null;
}

std::uint64_t voxelCount(const dng::View& view) {
  const dng::GridInfo& g = view.grid();
  return std::uint64_t(g.dims[0]) * g.dims[1] * g.dims[2]; // each <= 2^24: no overflow
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size); // operator new: 8-byte aligned, as open() needs
  dng::format::resealHashes(bytes);
  dng::View view;
  dng::Diagnostic diag;
  if (dng::View::open(bytes.data(), bytes.size(), &view, &diag) != dng::Status::kOk) {
    dng::dump::printFindingJson(sink(), "fuzz.dng", diag);
    return 0;
  }
  if (view.verifyHashes(&diag) != dng::Status::kOk) dng::dump::printFindingJson(sink(), "fuzz.dng", diag);
  if (voxelCount(view) > kMaxReportedVoxels) return 0;
  dng::dump::printSummary(sink(), "fuzz.dng", view);
  dng::dump::printJson(sink(), "fuzz.dng", view);
  dng::dump::printStats(sink(), view, false);
  dng::dump::printStats(sink(), view, true);
  return 0;
}
