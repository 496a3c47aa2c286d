// Internal to dngdump: the pieces of the program, each in its own file.
//   dngdump.cpp      options, --check, --query, dispatch
//   dump_report.cpp  the summary, --json and --stats
//   dump_slice.cpp   --slice as a PNG: the paper's Figure 1
#pragma once

#include "dng/file.h"

#include <cstdint>
#include <string>

namespace dng {
namespace dump {

/// Exit codes, as dngbake's (docs/BAKING.md): 0 ok, 1 usage, 2 I/O, 3 invalid input.
enum Exit : int { kOk = 0, kUsage = 1, kIo = 2, kInvalid = 3 };

/// Human summary on stdout.
void printSummary(const std::string& path, const View& view);
/// The same as a versioned JSON document on stdout.
void printJson(const std::string& path, const View& view);
/// Histograms of distance and of normal deviation between neighbours, band coverage.
void printStats(const View& view, bool json);

struct SliceRequest {
  int axis = 2;       ///< 0 x, 1 y, 2 z
  float value = 0.0f; ///< position along the axis, grid-local units
  int scale = 0;      ///< pixels per voxel; 0 = automatic (about 768 pixels on the long side)
  std::string png;
};
/// Renders a slice: distance as colour (darker closer, blue inside, orange outside), the zero contour
/// in black, normals as arrows. Returns an exit code and prints a message on failure.
int renderSlice(const View& view, const SliceRequest& request);

} // namespace dump
} // namespace dng
