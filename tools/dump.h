// Internal to dngdump: the pieces of the program, each in its own file.
//   dngdump.cpp      options, --check, --query, dispatch
//   dump_report.cpp  the summary, --json and --stats
//   dump_slice.cpp   --slice as a PNG: the paper's Figure 1
//   dump_json.cpp    JSON holding untrusted text, printed without throwing
// Every function here takes any View that View::open accepted: the file's contents are untrusted.
#pragma once

#include "dng/file.h"
#include "exit_codes.h"

#include <cstdint>
#include <cstdio>
#include <string>

namespace dng {
namespace dump {

/// Human summary.
void printSummary(std::FILE* out, const std::string& path, const View& view);
/// The same as a versioned JSON document.
void printJson(std::FILE* out, const std::string& path, const View& view);
/// Histograms of distance and of normal deviation between neighbours, band coverage.
void printStats(std::FILE* out, const View& view, bool json);

/// The stable ID of a finding: the FORMAT.md rule ("V8"), "IO" when the file could not be read, or
/// "E<status number>" for a failure that breaks no rule.
std::string findingId(const Diagnostic& diag);
/// A finding as a "dngdump-check" JSON document.
void printFindingJson(std::FILE* out, const std::string& path, const Diagnostic& diag);

struct SliceRequest {
  int axis = 2;       ///< 0 x, 1 y, 2 z
  float value = 0.0f; ///< position along the axis, grid-local units
  int scale = 0;      ///< pixels per voxel; 0 = automatic (about 768 pixels on the long side)
  std::string png;
};
/// Largest picture --slice draws, in pixels per side (a grid may have 2^24 voxels on an axis).
inline constexpr int kMaxSlicePixels = 16384;
/// Renders a slice: distance as colour (darker closer, blue inside, orange outside), the zero contour
/// in black, normals as arrows. Returns an exit code and prints a message on failure.
int renderSlice(const View& view, const SliceRequest& request);

} // namespace dump
} // namespace dng
