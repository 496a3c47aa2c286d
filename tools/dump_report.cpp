// dngdump's reports: what is in a file, for people (summary) and programs (--json), and --stats.
#include "dump.h"
#include "dump_json.h"
#include "terminal.h"

#include <algorithm>

#include <cmath>
#include <cstdio>

namespace dng {
namespace dump {

namespace {

// A progress line on stderr while a report reads every voxel of a large grid (a 2048^3 grid takes
// about a minute), for a person at a terminal only: never in a pipe, a log or the fuzzer.
class SliceProgress {
public:
  SliceProgress(const char* what, const GridInfo& g)
      : what_(what), slices_(g.dims[2]),
        draw_(double(g.dims[0]) * g.dims[1] * g.dims[2] >= 1e8 && tools::stderrIsTerminal()) {}
  SliceProgress(const SliceProgress&) = delete;
  SliceProgress& operator=(const SliceProgress&) = delete;
  ~SliceProgress() {
    if (draw_) std::fprintf(stderr, "\r\033[K");
  }
  void at(std::uint32_t slice) const {
    if (draw_ && slice % 16 == 0) {
      std::fprintf(stderr, "\r\033[Kdngdump: %s %3d%%", what_, int(100.0 * slice / slices_));
      std::fflush(stderr);
    }
  }

private:
  const char* what_;
  std::uint32_t slices_;
  bool draw_;
};

const char* encodingName(const GridInfo& g) { return g.encoding == format::Encoding::kDense ? "dense" : "bricked"; }

// Voxels whose centre is within the band, counted through the runtime's own queries.
std::uint64_t bandVoxels(const View& view) {
  const GridInfo& g = view.grid();
  std::uint64_t count = 0;
  const SliceProgress progress("counting band voxels", g);
  for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
    progress.at(k);
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        const Vec3f c = g.origin + Vec3f{float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f} * g.voxel_size;
        count += view.sample(c).status == SampleStatus::kInBand ? 1 : 0;
      }
  }
  return count;
}

std::string describeUnits(const Json& meta) {
  std::string line = meta["units"].value("field", "unknown");
  const Json files = meta.contains("source") ? meta["source"].value("files", Json::array()) : Json::array();
  for (std::size_t i = 0; i < files.size(); ++i) {
    const Json& f = files[i];
    char scale[32];
    std::snprintf(scale, sizeof scale, "%g", f.value("scale", 1.0));
    line += std::string(i == 0 ? " (from " : "; ") + f.value("format", "?") + " in " + f.value("units", "unknown") +
            ", scale " + scale;
  }
  return files.empty() ? line : line + ")";
}

// "m (from glb in m, scale 1)": the field's unit and how each source file got there, from the META
// section dngbake writes. Empty when the file does not record units (older bakes, other writers).
std::string unitsLine(const Json& meta) {
  if (!meta.is_object() || !meta.contains("units") || !meta["units"].is_object()) return "";
  try { // the metadata is the file's: a field of the wrong type must not end dngdump
    return describeUnits(meta);
  } catch (const nlohmann::json::exception&) {
    return "";
  }
}

Json reportJson(const std::string& path, const View& view) {
  const GridInfo& g = view.grid();
  const double voxels = double(g.dims[0]) * g.dims[1] * g.dims[2];
  const std::uint64_t band = bandVoxels(view);
  Json j;
  j["format"] = "dngdump-report";
  j["version"] = 1;
  j["file"] = path;
  j["format_version"] = std::to_string(view.versionMajor()) + "." + std::to_string(view.versionMinor());
  j["encoding"] = encodingName(g);
  j["brick_size"] = g.brick_size;
  j["dims"] = {g.dims[0], g.dims[1], g.dims[2]};
  j["voxel_size"] = g.voxel_size;
  j["bounds_min"] = {g.origin.x, g.origin.y, g.origin.z};
  j["bounds_max"] = {g.origin.x + float(g.dims[0]) * g.voxel_size, g.origin.y + float(g.dims[1]) * g.voxel_size,
                     g.origin.z + float(g.dims[2]) * g.voxel_size};
  j["band"] = g.band;
  j["band_voxels"] = g.band / g.voxel_size;
  j["guaranteed_reach"] = view.guaranteedReach();
  j["conservative_planes"] = view.conservativePlanes();
  j["lift"] = view.hasLift();
  j["gradient"] = view.hasGradient();
  j["shading"] = view.hasShading();
  j["second_planes"] = view.secondPlaneCount();
  const TileCounts& t = view.tileCounts();
  j["tiles"] = {{"far_outside", t.far_outside}, {"far_inside", t.far_inside}, {"plane", t.plane}, {"brick", t.brick}};
  j["voxels_in_band"] = band;
  j["file_bytes"] = view.sizeBytes();
  j["bytes_per_voxel"] = double(view.sizeBytes()) / voxels;
  j["bytes_per_band_voxel"] = band > 0 ? double(view.sizeBytes()) / double(band) : 0.0;
  j["metadata"] = metadataJson(view.metadata());
  if (const std::string units = unitsLine(j["metadata"]); !units.empty()) j["units"] = units;
  return j;
}

} // namespace

void printJson(std::FILE* out, const std::string& path, const View& view) {
  std::fprintf(out, "%s\n", toText(reportJson(path, view)).c_str());
}

void printSummary(std::FILE* out, const std::string& path, const View& view) {
  const Json j = reportJson(path, view);
  const GridInfo& g = view.grid();
  std::fprintf(out, "%s: .dng version %s, %s", path.c_str(), j["format_version"].get<std::string>().c_str(),
               encodingName(g));
  if (g.encoding == format::Encoding::kBricked) std::fprintf(out, " (bricks of %u)", g.brick_size);
  std::fprintf(out, "\n  grid       %u x %u x %u voxels of %g\n", g.dims[0], g.dims[1], g.dims[2],
               double(g.voxel_size));
  std::fprintf(out, "  bounds     (%g, %g, %g) .. (%g, %g, %g)\n", double(g.origin.x), double(g.origin.y),
               double(g.origin.z), j["bounds_max"][0].get<double>(), j["bounds_max"][1].get<double>(),
               j["bounds_max"][2].get<double>());
  std::fprintf(out, "  band       %g (%.3g voxels); guaranteed reach %g\n", double(g.band),
               double(g.band / g.voxel_size), double(view.guaranteedReach()));
  std::fprintf(out, "  planes     %s\n",
               view.conservativePlanes() ? "conservative (a lower bound of the distance over each voxel)"
                                         : "as written (no conservative-plane promise)");
  std::fprintf(out, "  lift       %s\n",
               view.hasLift() ? "yes (accurate queries read the distances from before any lowering)"
                              : "none (accurate queries read the stored distances)");
  std::fprintf(out, "  gradient   %s\n",
               view.hasGradient() ? "yes (accurate queries use the distance's own gradient, not the blurred normals)"
                                  : "none (accurate queries use the stored normals)");
  std::fprintf(out, "  shading    %s\n",
               view.hasShading() ? "yes (queries and responses read the mode's normals; the walk reads the planes')"
                                 : "none (queries and responses read the planes' normals)");
  if (view.hasSecondPlanes()) {
    std::fprintf(
        out, "  second     %u voxels with a second bound (the walk reads it where their own plane proves nothing)\n",
        view.secondPlaneCount());
  } else {
    std::fprintf(out, "  second     none (the walk reads the voxels' own planes, then their neighbours')\n");
  }
  if (g.encoding == format::Encoding::kBricked) {
    const TileCounts& t = view.tileCounts();
    std::fprintf(out, "  tiles      %llu far outside, %llu far inside, %llu plane, %llu brick\n",
                 (unsigned long long)t.far_outside, (unsigned long long)t.far_inside, (unsigned long long)t.plane,
                 (unsigned long long)t.brick);
  }
  std::fprintf(out, "  size       %zu bytes: %.3g per voxel, %.3g per band voxel (%llu voxels in band)\n",
               view.sizeBytes(), j["bytes_per_voxel"].get<double>(), j["bytes_per_band_voxel"].get<double>(),
               (unsigned long long)j["voxels_in_band"].get<std::uint64_t>());
  if (j.contains("units")) std::fprintf(out, "  units      %s\n", j["units"].get<std::string>().c_str());
  const Json& meta = j["metadata"];
  if (meta.is_null()) {
    std::fprintf(out, "  metadata   none\n");
  } else {
    std::fprintf(out, "  metadata   %s\n", toText(meta, -1).c_str());
  }
}

void printStats(std::FILE* out, const View& view, bool json) {
  const GridInfo& g = view.grid();
  constexpr int kBins = 10;
  std::uint64_t distance_bins[kBins] = {}, angle_bins[kBins] = {}, band = 0, total = 0;
  const float angle_edges[kBins] = {0.5f, 1, 2, 5, 10, 20, 45, 90, 135, 180};
  const SliceProgress progress("reading every voxel", g);
  for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
    progress.at(k);
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        const auto centre = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
          return g.origin + Vec3f{float(a) + 0.5f, float(b) + 0.5f, float(c) + 0.5f} * g.voxel_size;
        };
        const Sample s = view.sample(centre(i, j, k));
        ++total;
        if (s.status != SampleStatus::kInBand) continue;
        ++band;
        const int bin = std::min(kBins - 1, int((s.distance + g.band) / (2.0f * g.band) * kBins));
        ++distance_bins[std::max(0, bin)];
        // Deviation from the +x, +y and +z neighbours that are in band too.
        const std::uint32_t next[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
        for (int axis = 0; axis < 3; ++axis) {
          if (next[axis][axis] >= g.dims[axis]) continue;
          const Sample n = view.sample(centre(next[axis][0], next[axis][1], next[axis][2]));
          if (n.status != SampleStatus::kInBand) continue;
          const double angle = angleDegrees(s.normal, n.normal);
          int a = 0;
          while (a + 1 < kBins && angle > angle_edges[a])
            ++a;
          ++angle_bins[a];
        }
      }
  }
  Json j;
  j["format"] = "dngdump-stats";
  j["version"] = 1;
  j["band_coverage"] = total ? double(band) / double(total) : 0.0;
  j["distance_histogram"] = {{"from", -g.band}, {"to", g.band}, {"counts", distance_bins}};
  j["neighbour_normal_deviation_degrees"] = {{"upper_edges", angle_edges}, {"counts", angle_bins}};
  if (json) {
    std::fprintf(out, "%s\n", toText(j).c_str());
    return;
  }
  std::fprintf(out, "band coverage: %.4g%% of %llu voxels\n", 100.0 * j["band_coverage"].get<double>(),
               (unsigned long long)total);
  std::fprintf(out, "distance (voxel centres in band), %d bins from %g to %g:\n", kBins, double(-g.band),
               double(g.band));
  for (int b = 0; b < kBins; ++b)
    std::fprintf(out, "  [%8.4g, %8.4g) %llu\n", -double(g.band) + 2.0 * g.band * b / kBins,
                 -double(g.band) + 2.0 * g.band * (b + 1) / kBins, (unsigned long long)distance_bins[b]);
  std::fprintf(out, "normal deviation between neighbouring voxels in band (x, y and z), degrees:\n");
  for (int b = 0; b < kBins; ++b)
    std::fprintf(out, "  <= %5g %llu\n", double(angle_edges[b]), (unsigned long long)angle_bins[b]);
}

std::string findingId(const Diagnostic& diag) {
  if (diag.rule[0] != '\0') return diag.rule;
  if (diag.status == Status::kIoError) return "IO";
  return "E" + std::to_string(int(diag.status));
}

void printFindingJson(std::FILE* out, const std::string& path, const Diagnostic& diag) {
  const Json j = {
      {"format", "dngdump-check"},
      {"version", 1},
      {"file", path},
      {"valid", false},
      {"findings", {{{"id", findingId(diag)}, {"status", statusString(diag.status)}, {"message", diag.message}}}}};
  std::fprintf(out, "%s\n", toText(j).c_str());
}

} // namespace dump
} // namespace dng
