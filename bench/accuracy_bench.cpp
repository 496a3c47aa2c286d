// Accuracy at arbitrary points of the band (issue #10): real closed meshes baked at resolution 64 in
// exact and normal-blur modes (bricked), read with nearest, trilinear and accurate queries, against the exact
// answer on the original triangles (closest point for distance and normal, ray parity for the sign),
// beside OpenVDB's meshToLevelSet at the same voxel size, lattice and band, sampled trilinearly. Also
// checks View::guaranteedReach(): every point that close to the surface must read in band.
//   accuracy_bench MESH_DIR [POINTS_PER_MESH]   (markdown on stdout, for docs/PERFORMANCE.md)
#include "accuracy_vdb.h"
#include "dng/file.h"
#include "mesh_reference.h"
#include "stages.h"
#include "standard_output.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace dng;

// The band dngbake --max-speed --dt gives for 3 voxels per step: travel + half diagonal + half a voxel.
constexpr float kBandVoxels = 3.0f + 0.8660254f + 0.5f;
constexpr std::uint32_t kResolution = 64;

// The exact answer at a point: signed distance (negative inside) and the outward direction from the
// closest surface point.
struct Truth {
  Vec3f p;
  float distance = 0.0f;
  Vec3f normal;
};

struct Stats {
  float median = 0.0f, p99 = 0.0f, max = 0.0f;
};

Stats summarize(std::vector<float> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, v.size() * 99 / 100)];
  s.max = v.back();
  return s;
}

// Points uniform over the mesh's box grown by `reach`, kept when their true |distance| < reach.
std::vector<Truth> bandPoints(const reference::MeshReference& mesh, Vec3f lo, Vec3f hi, float reach, float voxel,
                              std::size_t count) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Truth> kept;
  while (kept.size() < count) {
    std::vector<Truth> batch(4 * count);
    for (Truth& t : batch)
      t.p = {lo.x - reach + (hi.x - lo.x + 2 * reach) * unit(rng), lo.y - reach + (hi.y - lo.y + 2 * reach) * unit(rng),
             lo.z - reach + (hi.z - lo.z + 2 * reach) * unit(rng)};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size()), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t n = r.begin(); n != r.end(); ++n) {
        Truth& t = batch[n];
        const reference::Closest c = mesh.closest(t.p, reach);
        // Not found: beyond reach. Within a hair of the surface the direction is undefined: skip.
        if (!c.found || c.distance < 1e-4f * voxel) {
          t.distance = std::numeric_limits<float>::infinity();
          continue;
        }
        const bool inside = mesh.inside(t.p);
        t.distance = inside ? -c.distance : c.distance;
        t.normal = normalizeOrZero(inside ? c.point - t.p : t.p - c.point);
      }
    });
    for (const Truth& t : batch)
      if (std::fabs(t.distance) < reach && kept.size() < count) kept.push_back(t);
  }
  return kept;
}

struct Row {
  std::string label;
  Stats distance; ///< voxels
  Stats normal;   ///< degrees
  std::size_t outside_flipped = 0;
  std::size_t medial_flipped = 0; ///< of those, points on a medial axis where the read normal is valid too
  std::size_t points = 0;
  /// Where the reader says outside (d >= 0): the largest min(d, reach) - true distance, voxels.
  float overestimate = 0.0f;
  std::size_t over_promise = 0; ///< points where that exceeds a hundredth of a voxel
};

// On a medial axis the surface is as close on two sides and the true normal is not unique: the
// reference picks one closest point, and a normal away from the other is as valid. A field sampled a
// voxel apart cannot tell which of two sides is nearer when they differ by a few hundredths of a voxel,
// so this also accepts points that near a medial axis. Judged on the triangles: the point a tenth of a
// voxel behind p along `normal` finds its closest surface point q; the normal is valid when q lies on
// another side (at least the distance away from p's closest point, so not on the same patch), at most
// kMedialTolerance voxels farther from p than the closest point, and p lies less than 90 degrees off
// `normal` as seen from q (a step along the normal moves away from q).
constexpr float kMedialTolerance = 0.05f;

bool validOnMedialAxis(const reference::MeshReference& mesh, const Truth& t, Vec3f normal, float voxel) {
  const float tolerance = kMedialTolerance * voxel;
  const reference::Closest behind = mesh.closest(t.p - normal * (2.0f * tolerance), t.distance + 4.0f * tolerance);
  if (!behind.found) return false;
  const Vec3f from_q = t.p - behind.point;
  const Vec3f closest = t.p - t.normal * t.distance;
  return length(behind.point - closest) >= t.distance && length(from_q) <= t.distance + tolerance &&
         dot(from_q, normal) > 0.0f;
}

// Errors of one reader over the points; `read(n, &distance, &normal)` returns false where it has no
// normal (outside its band), which counts as a distance error only.
template <class Read>
Row measure(const std::string& label, const std::vector<Truth>& truth, const reference::MeshReference& mesh,
            float voxel, float reach, Read read) {
  Row row;
  row.label = label;
  row.points = truth.size();
  std::vector<float> distance_errors, angles;
  for (std::size_t n = 0; n < truth.size(); ++n) {
    float d = 0.0f;
    Vec3f normal;
    const bool has_normal = read(n, &d, &normal);
    distance_errors.push_back(std::fabs(d - truth[n].distance) / voxel);
    if (d >= 0.0f) {
      const float excess = (std::min(d, reach) - truth[n].distance) / voxel;
      row.overestimate = std::max(row.overestimate, excess);
      row.over_promise += excess > 0.01f ? 1 : 0;
    }
    if (!has_normal) continue;
    const float angle = float(angleDegrees(normal, truth[n].normal));
    angles.push_back(angle);
    if (truth[n].distance > 0.0f && angle > 90.0f) {
      ++row.outside_flipped;
      row.medial_flipped += validOnMedialAxis(mesh, truth[n], normal, voxel) ? 1 : 0;
    }
  }
  row.distance = summarize(distance_errors);
  row.normal = summarize(angles);
  return row;
}

void printRow(const char* mesh, const Row& r) {
  std::printf("| %s | %s | %.3f | %.3f | %.3f | %.3f (%zu) | %.2f | %.2f | %.2f | %zu (%zu) |\n", mesh, r.label.c_str(),
              double(r.distance.median), double(r.distance.p99), double(r.distance.max), double(r.overestimate),
              r.over_promise, double(r.normal.median), double(r.normal.p99), double(r.normal.max), r.outside_flipped,
              r.medial_flipped);
}

struct MeshResult {
  std::vector<Row> rows; ///< per mode: nearest, trilinear; then OpenVDB last
  std::vector<std::string> reach_lines;
};

// Issue #10's accuracy goals for one dngrid reader against OpenVDB on the same points.
std::string goalLine(const char* mesh, const Row& r, const Row& vdb) {
  std::string misses;
  const auto check = [&](bool ok, const char* what) {
    if (!ok) misses += std::string(misses.empty() ? "" : "; ") + what;
  };
  check(r.distance.max <= vdb.distance.max, "distance max above OpenVDB's");
  check(r.distance.p99 <= vdb.distance.p99, "distance p99 above OpenVDB's");
  check(2.0f * r.distance.median <= vdb.distance.median, "distance median not 2x below OpenVDB's");
  check(r.normal.p99 <= vdb.normal.p99, "normal p99 above OpenVDB's");
  check(r.outside_flipped == r.medial_flipped, "outside points away from medial axes with normals over 90 degrees off");
  return std::string(mesh) + ", " + r.label + ": " + (misses.empty() ? "reached" : "not reached (" + misses + ")");
}

bool bakeField(const std::string& path, baker::NormalMode mode, const std::string& out, File* file) {
  baker::BakeOptions options;
  options.mode = mode;
  options.resolution = kResolution;
  options.band_voxels = kBandVoxels;
  baker::BakeReport report;
  const baker::BakeStatus status = baker::bake(path, {out, {}}, options, nullptr, nullptr, &report);
  if (!status.ok()) {
    std::fprintf(stderr, "accuracy_bench: %s: %s\n", path.c_str(), status.message.c_str());
    return false;
  }
  return File::open(out.c_str(), file) == Status::kOk;
}

// Nearest queries that do not read in band although the point is within guaranteedReach().
std::string reachLine(const char* mesh, const char* mode, const View& view, const std::vector<Truth>& truth) {
  const float reach = view.guaranteedReach(), voxel = view.grid().voxel_size;
  std::size_t within = 0, missed = 0;
  float closest_miss = std::numeric_limits<float>::infinity();
  for (const Truth& t : truth) {
    if (std::fabs(t.distance) >= reach) continue;
    ++within;
    if (view.sample(t.p).status != SampleStatus::kInBand) {
      ++missed;
      closest_miss = std::min(closest_miss, std::fabs(t.distance));
    }
  }
  char line[256];
  if (missed == 0)
    std::snprintf(line, sizeof line, "%s, %s: all %zu points within the reach (%.2f voxels) read in band.", mesh, mode,
                  within, double(reach / voxel));
  else
    std::snprintf(line, sizeof line,
                  "%s, %s: **%zu of %zu** points within the reach (%.2f voxels) read far; the nearest of them %.2f "
                  "voxels from the surface.",
                  mesh, mode, missed, within, double(reach / voxel), double(closest_miss / voxel));
  return line;
}

bool runMesh(const std::string& path, const char* name, std::size_t count, MeshResult* out) {
  baker::TriangleSoup soup;
  if (!baker::loadMesh(path, &soup).ok()) return false;
  reference::MeshReference mesh;
  if (!mesh.build(soup.vertices, soup.triangles)) return false;
  const baker::MeshReport report = baker::checkMesh(soup);
  const std::string dng_path = (std::filesystem::temp_directory_path() / "dng_accuracy_bench.dng").string();
  std::vector<Truth> truth;
  for (const baker::NormalMode mode : {baker::NormalMode::kExact, baker::NormalMode::kNormalBlur}) {
    File file;
    if (!bakeField(path, mode, dng_path, &file)) return false;
    const View& view = file.view();
    const float voxel = view.grid().voxel_size;
    if (truth.empty()) {
      truth = bandPoints(mesh, report.bounds_min, report.bounds_max, view.guaranteedReach(), voxel, count);
      const std::vector<Vec3f> points = [&] {
        std::vector<Vec3f> p;
        for (const Truth& t : truth)
          p.push_back(t.p);
        return p;
      }();
      const std::vector<bench::VdbReading> vdb = bench::meshToLevelSetReadings(
          soup.vertices, soup.triangles, view.grid().origin, voxel, view.grid().band, points);
      out->rows.push_back(measure("OpenVDB meshToLevelSet, trilinear", truth, mesh, voxel, view.guaranteedReach(),
                                  [&](std::size_t n, float* d, Vec3f* nrm) {
                                    *d = vdb[n].distance;
                                    *nrm = vdb[n].normal;
                                    return length(vdb[n].normal) > 0.0f;
                                  }));
    }
    const std::string mode_name = baker::normalModeName(mode);
    for (const Interpolation interpolation :
         {Interpolation::kNearest, Interpolation::kTrilinear, Interpolation::kAccurate}) {
      const char* query = interpolation == Interpolation::kNearest     ? "nearest"
                          : interpolation == Interpolation::kTrilinear ? "trilinear"
                                                                       : "accurate";
      out->rows.push_back(measure("dngrid " + mode_name + ", " + query, truth, mesh, voxel, view.guaranteedReach(),
                                  [&](std::size_t n, float* d, Vec3f* nrm) {
                                    const Sample s = view.sample(truth[n].p, interpolation);
                                    *d = s.distance;
                                    *nrm = s.normal;
                                    return s.status == SampleStatus::kInBand;
                                  }));
    }
    out->reach_lines.push_back(reachLine(name, mode_name.c_str(), view, truth));
  }
  std::filesystem::remove(dng_path);
  return true;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: accuracy_bench MESH_DIR [POINTS_PER_MESH]\n");
    return 1;
  }
  const std::size_t count = argc > 2 ? std::size_t(std::stoul(argv[2])) : 100000;
  const std::string dir = argv[1];
  const char* names[] = {"bunny00", "fandisk"};
  MeshResult results[2];
  for (int m = 0; m < 2; ++m) {
    if (!runMesh(dir + "/" + names[m] + ".off", names[m], count, &results[m])) {
      std::fprintf(stderr, "accuracy_bench: cannot bake or load %s/%s.off\n", dir.c_str(), names[m]);
      return 1;
    }
  }
  std::printf("\n## Accuracy in the band (bench/accuracy_bench.cpp)\n\n");
  std::printf("`bunny00.off` and `fandisk.off` baked at resolution 64 with the band of a 3-voxel-per-step design "
              "speed (%.2f voxels), bricked. %zu points per mesh, uniform over the box, kept where the true distance "
              "is within the guaranteed reach of the surface. Truth: the closest point on the original triangles "
              "(Embree) for distance and normal (the direction from the closest point, outwards), ray parity for "
              "the sign. OpenVDB: `tools::meshToLevelSet` on the same lattice, voxel size and band, read with "
              "`tools::BoxSampler`, its normal the normalized gradient of that trilinear field. Errors in voxels and "
              "degrees. *Largest overestimate*: how far the field's distance rises above the true one (a field "
              "that never overestimates cannot let a step walk through the surface). The last column counts points "
              "outside the mesh whose normal is more than 90 degrees off (it would push a particle into the surface); "
              "in brackets, how many of them lie on or within a twentieth of a voxel of a medial axis, where the "
              "surface is about as close on two sides and the normal is not unique: judged on the triangles, the "
              "closest surface point to a point a tenth of a voxel behind along the read normal lies on another side "
              "(at least the distance away from the closest point), at most a twentieth of a voxel farther than the "
              "closest one, and the read normal points away from it, so it is the other side's normal, as valid as "
              "the reference's up to that tolerance.\n\n",
              double(kBandVoxels), count);
  std::printf(
      "| mesh | field | distance median | p99 | max | largest overestimate | normal median | p99 | max | outside, > "
      "90 deg |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int m = 0; m < 2; ++m)
    for (const Row& r : results[m].rows)
      printRow(names[m], r);
  std::printf("\n**Goals (issue #10), for the accurate query: distance max and p99 no worse than OpenVDB "
              "trilinear, median at least 2x better; normal p99 no worse than its gradient's; no outside point with "
              "a normal more than 90 degrees off (farther than a twentieth of a voxel from a medial axis, where the "
              "normal is not unique).** The nearest "
              "query is the step's lower bound and is judged by "
              "its largest overestimate instead: the lowering that makes it one costs it accuracy on purpose.\n\n");
  for (int m = 0; m < 2; ++m)
    for (const Row& r : results[m].rows)
      if (r.label.find("accurate") != std::string::npos)
        std::printf("- %s\n", goalLine(names[m], r, results[m].rows.front()).c_str());
  std::printf("\n**Guaranteed reach** (nearest queries):\n\n");
  for (int m = 0; m < 2; ++m)
    for (const std::string& line : results[m].reach_lines)
      std::printf("- %s\n", line.c_str());
  return dng::tools::finishStandardOutput("accuracy_bench", 0); // docs/PERFORMANCE.md must not be cut quietly
}
