// Grid placement (docs/DESIGN.md §5.4): the padded bounding box, the voxel size and the band.
#include "dng/format/limits.h"
#include "stages.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace baker {

namespace {

constexpr float kHalfDiagonal = format::kHalfCubeDiagonal; // View::guaranteedReach's guard, in voxels
constexpr float kSpeedMargin = 0.5f;                       // extra voxels on top of the travel per step
// Float positions more than this many voxels apart make particles move in visibly coarse steps (a
// sixth of the runtime's 0.06-voxel walk margin; the step keeps them out even so).
constexpr float kCoarsePositionVoxels = 0.01f;
// The working store is sparse (memory follows the surface), but a dense file holds 16 bytes per voxel
// and is built in memory: refuse dense grids over 2^27 voxels (512^3, a 2 GB file) up front.
constexpr double kMaxDenseVoxels = double(1u << 27);

// Band in voxels for a voxel size: from --band, or from max speed * dt plus the guard.
float bandVoxels(const BakeOptions& o, float voxel) {
  if (o.max_speed > 0.0f && o.dt > 0.0f) return o.max_speed * o.dt / voxel + kHalfDiagonal + kSpeedMargin;
  return o.band_voxels;
}

// The refusal of a band (in voxels) wider than the largest grid.
BakeStatus bandTooWide(float band) {
  return BakeStatus::failure(BakeError::kBadOption, "--max-speed x --dt gives a band of " + shortNumber(band) +
                                                        " voxels, more than a grid of " +
                                                        std::to_string(kMaxBakeAxisVoxels) + " holds");
}

// The spacing of floats at the grid's farthest corner from the origin, in voxels: a grid far from the
// origin for its voxel size (a building baked in a city's coordinates) has fewer positions per voxel.
float positionSpacingVoxels(const format::GridGeometry& g) {
  float farthest = 0.0f;
  for (int a = 0; a < 3; ++a) {
    const float lo = component(g.origin, a);
    farthest = std::max({farthest, std::fabs(lo), std::fabs(lo + float(g.dims[a]) * g.voxel_size)});
  }
  return (std::nextafter(farthest, INFINITY) - farthest) / g.voxel_size;
}

} // namespace

BakeStatus placeGrid(const MeshReport& mesh, const BakeOptions& options, format::GridGeometry* out,
                     std::vector<std::string>* io_warnings) {
  BakeStatus status = checkBakeOptions(options); // for callers other than bake()
  if (!status.ok()) return status;
  const Vec3f extent = mesh.bounds_max - mesh.bounds_min;
  const float longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0f) || !std::isfinite(longest))
    return BakeStatus::failure(BakeError::kInvalidInput, "the mesh has no extent (all vertices coincide)");

  // The padding depends on the band, which (from a speed) depends on the voxel size: iterate; three
  // rounds settle it to within a voxel.
  float voxel = options.voxel_size > 0.0f ? options.voxel_size : longest / float(options.resolution);
  std::uint32_t pad = 0;
  for (int round = 0; round < 3; ++round) {
    const float band = bandVoxels(options, voxel);
    if (!(band <= float(kMaxBakeAxisVoxels))) return bandTooWide(band); // before it becomes an integer
    pad = std::uint32_t(std::ceil(band)) + 1;
    if (options.voxel_size > 0.0f) break;
    const float inner = float(options.resolution) - 2.0f * float(pad);
    if (inner < 4.0f)
      return BakeStatus::failure(BakeError::kBadOption, "the band (" + std::to_string(pad - 1) +
                                                            " voxels each side) leaves no room in a grid of " +
                                                            std::to_string(options.resolution) +
                                                            ": raise --resolution");
    voxel = longest / inner;
  }
  const float band = bandVoxels(options, voxel);
  if (!(voxel >= kMinVoxelSize))
    return BakeStatus::failure(BakeError::kBadOption, "the voxel size would be " + shortNumber(voxel) +
                                                          ", below OpenVDB's smallest (" + shortNumber(kMinVoxelSize) +
                                                          "): bake in smaller units (--units, --scale)");
  if (!(band <= float(kMaxBakeAxisVoxels))) return bandTooWide(band);
  format::GridGeometry g;
  g.voxel_size = voxel;
  g.band = band * voxel;
  const float axis_extent[3] = {extent.x, extent.y, extent.z};
  const float axis_min[3] = {mesh.bounds_min.x, mesh.bounds_min.y, mesh.bounds_min.z};
  float origin[3];
  for (int a = 0; a < 3; ++a) {
    const float inner = std::ceil(axis_extent[a] / voxel);
    const double dims = double(inner) + 2.0 * pad;
    if (!(dims <= kMaxBakeAxisVoxels)) // also when the mesh's extent over the voxel overflows
      return BakeStatus::failure(BakeError::kBadOption,
                                 "the grid would need " + shortNumber(dims) + " voxels along one axis (at most " +
                                     std::to_string(kMaxBakeAxisVoxels) + "): use a larger voxel size");
    g.dims[a] = std::uint32_t(dims);
    // Centre the mesh in its padded box.
    origin[a] = axis_min[a] - (float(g.dims[a]) * voxel - axis_extent[a]) * 0.5f;
    // The format's range for placements (format::kMaxMagnitude): past it the encoder would fail only
    // after the whole bake.
    if (!(std::fabs(origin[a]) + float(g.dims[a]) * voxel <= format::kMaxMagnitude) ||
        !(g.band <= format::kMaxMagnitude))
      return BakeStatus::failure(BakeError::kBadOption,
                                 "the grid would reach beyond +-1e18, the format's range: bake in larger units "
                                 "(--units, --scale) or a smaller voxel size or band");
  }
  g.origin = {origin[0], origin[1], origin[2]};
  const double voxels = double(g.dims[0]) * g.dims[1] * g.dims[2];
  if (options.encoding == format::Encoding::kDense && voxels > kMaxDenseVoxels)
    return BakeStatus::failure(BakeError::kBadOption,
                               "the grid would have " + std::to_string(std::uint64_t(voxels)) +
                                   " voxels; dense files hold at most 134,217,728 (512^3, 2 GB): use "
                                   "--encoding bricked, a larger --voxel-size or a smaller --resolution");
  if (band * 4.0f > float(std::min({g.dims[0], g.dims[1], g.dims[2]})))
    io_warnings->push_back("the band (" + shortNumber(band) + " voxels) is more than a quarter of the grid's " +
                           "thinnest side (" + std::to_string(std::min({g.dims[0], g.dims[1], g.dims[2]})) +
                           " voxels): most of the file is band (a flat mesh, or a band for particles so fast "
                           "they would be better served by a coarser grid or swept steps)");
  if (const float spacing = positionSpacingVoxels(g); spacing > kCoarsePositionVoxels)
    io_warnings->push_back("the grid lies far from the origin for its voxel size: floats there are " +
                           shortNumber(spacing) +
                           " voxels apart, so particles move and are judged in steps that "
                           "coarse; move the mesh near the origin before baking, place the body with its transform, "
                           "and keep the game's particles near the origin too (world positions that large have the "
                           "same limit)");
  *out = g;
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
