// Field checks shared by both encoders, the GRID section, and the dense encoding.
#include "dng/format/writer.h"
#include "grid_section.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

namespace dng {
namespace format {

std::string checkGeometry(const GridGeometry& g) {
  if (!isLittleEndianHost()) return "this host is big-endian; .dng files are little-endian only";
  if (!std::isfinite(g.origin.x) || !std::isfinite(g.origin.y) || !std::isfinite(g.origin.z))
    return "grid origin is not finite";
  if (!(g.voxel_size > 0.0f) || !std::isfinite(g.voxel_size)) return "voxel size must be finite and > 0";
  if (!(g.band > 0.0f) || !std::isfinite(g.band)) return "band must be finite and > 0";
  for (std::uint32_t d : g.dims) {
    if (d == 0) return "every grid dimension must be at least 1";
  }
  if (std::fabs(g.origin.x) > kMaxMagnitude || std::fabs(g.origin.y) > kMaxMagnitude ||
      std::fabs(g.origin.z) > kMaxMagnitude || g.voxel_size > kMaxMagnitude || g.voxel_size < 1.0f / kMaxMagnitude ||
      g.band > kMaxMagnitude)
    return "grid origin, voxel size or band is outside [1e-18, 1e18]";
  for (std::uint32_t d : g.dims) {
    if (d > kMaxAxisVoxels) return "a grid dimension exceeds 2^24 voxels";
  }
  return {};
}

namespace {

// "voxel (i, j, k)" for the v-th voxel of a box read x fastest.
std::string voxelName(const VoxelBox& box, std::size_t v) {
  const std::size_t nx = box.hi[0] - box.lo[0], ny = box.hi[1] - box.lo[1];
  return "voxel (" + std::to_string(box.lo[0] + v % nx) + ", " + std::to_string(box.lo[1] + v / nx % ny) + ", " +
         std::to_string(box.lo[2] + v / (nx * ny)) + ")";
}

} // namespace

std::string checkVoxels(const VoxelBox& box, const float* distance, const Vec3f* normal) {
  for (std::size_t v = 0; v < box.count(); ++v) {
    const Vec3f n = normal[v];
    if (!(std::fabs(distance[v]) <= kMaxMagnitude) || !std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      return voxelName(box, v) + " holds a non-finite distance or normal";
  }
  return {};
}

std::string checkAccurate(const VoxelBox& box, const float* accurate) {
  for (std::size_t v = 0; v < box.count(); ++v) {
    if (!(std::fabs(accurate[v]) <= kMaxMagnitude)) return voxelName(box, v) + " holds a non-finite accurate distance";
  }
  return {};
}

std::string checkField(const DenseField& field) {
  std::string error = checkGeometry(field.grid);
  if (!error.empty()) return error;
  if (field.distance.size() != field.grid.voxelCount() || field.normal.size() != field.grid.voxelCount())
    return "distance and normal arrays must hold one entry per voxel";
  if (!field.accurate.empty() && field.accurate.size() != field.grid.voxelCount())
    return "the accurate array must be empty or hold one entry per voxel";
  if (!field.gradient.empty() && field.gradient.size() != field.grid.voxelCount())
    return "the gradient array must be empty or hold one entry per voxel";
  if (!field.shading.empty() && field.shading.size() != field.grid.voxelCount())
    return "the shading array must be empty or hold one entry per voxel";
  if (field.second_distance.size() != field.second_normal.size() ||
      field.second_distance.size() != field.second_raise.size() ||
      (!field.second_distance.empty() && field.second_distance.size() != field.grid.voxelCount()))
    return "the second-plane arrays must all be empty or all hold one entry per voxel";
  VoxelBox all;
  for (int a = 0; a < 3; ++a)
    all.hi[a] = field.grid.dims[a];
  error = checkVoxels(all, field.distance.data(), field.normal.data());
  if (error.empty() && !field.accurate.empty()) error = checkAccurate(all, field.accurate.data());
  return error;
}

bool runPieces(const EncodeHooks& hooks, std::size_t count, const std::function<void(std::size_t)>& piece) {
  std::mutex reporting;
  std::size_t done = 0;
  std::atomic<bool> stop{false};
  const std::function<void(std::size_t)> task = [&](std::size_t i) {
    if (stop.load()) return;
    piece(i);
    const std::lock_guard<std::mutex> lock(reporting);
    if (!hooks.progress(double(++done) / double(count))) stop = true;
  };
  if (hooks.parallel_for) {
    hooks.parallel_for(count, task);
  } else {
    for (std::size_t i = 0; i < count; ++i)
      task(i);
  }
  return !stop.load();
}

GridSection makeGridSection(const GridGeometry& g, Encoding encoding) {
  GridSection s{};
  s.origin[0] = g.origin.x;
  s.origin[1] = g.origin.y;
  s.origin[2] = g.origin.z;
  s.voxel_size = g.voxel_size;
  for (int a = 0; a < 3; ++a)
    s.dims[a] = g.dims[a];
  s.band = g.band;
  s.encoding = std::uint32_t(encoding);
  s.flags = g.flags;
  return s;
}

void addCommonSections(ContainerBuilder& builder, const GridSection& grid, std::string_view metadata_json) {
  builder.addSection(kTagGrid, kSectionRequired, &grid, sizeof grid);
  if (!metadata_json.empty()) builder.addSection(kTagMetadata, 0, metadata_json.data(), metadata_json.size());
}

namespace {

// One GRAD or SHAD word per voxel of a slice, from normals `read` writes (readGradient, readShading).
template <class Read> void sliceWords(std::size_t per_slice, Read read, std::uint16_t* out) {
  std::vector<Vec3f> normals(per_slice);
  read(normals.data());
  for (std::size_t v = 0; v < per_slice; ++v)
    out[v] = gradientWord(normals[v]);
}

} // namespace

EncodeResult encodeDense(const FieldSource& source, std::string_view metadata_json, const EncodeHooks& hooks) {
  EncodeResult result;
  const GridGeometry& g = source.grid();
  result.fail(EncodeError::kInvalidGeometry, checkGeometry(g));
  if (!result.ok()) return result;

  // One piece per z slice, each writing its own part of `voxels` (and of `lifts`, `gradients` and
  // `shadings`).
  const std::size_t per_slice = std::size_t(g.dims[0]) * g.dims[1];
  const bool lifted = source.hasAccurate();
  const bool graded = source.hasGradient();
  const bool shaded = source.hasShading();
  std::vector<DenseVoxel> voxels(g.voxelCount());
  std::vector<std::int16_t> lifts(lifted ? g.voxelCount() : 0);
  std::vector<std::uint16_t> gradients(graded ? g.voxelCount() : 0);
  // SHAD pads to a whole number of 32-bit words (docs/FORMAT.md §5.4).
  std::vector<std::uint16_t> shadings(shaded ? (g.voxelCount() + 1) / 2 * 2 : 0, 0);
  std::vector<std::uint64_t> band_voxels(g.dims[2], 0);
  std::vector<float> lift_errors(g.dims[2], 0.0f);
  std::vector<std::string> errors(g.dims[2]);
  const bool finished = runPieces(hooks, g.dims[2], [&](std::size_t k) {
    VoxelBox slice;
    slice.hi[0] = g.dims[0];
    slice.hi[1] = g.dims[1];
    slice.lo[2] = std::uint32_t(k);
    slice.hi[2] = std::uint32_t(k + 1);
    std::vector<float> distance(per_slice), accurate(lifted ? per_slice : 0);
    std::vector<Vec3f> normal(per_slice);
    source.read(slice, distance.data(), normal.data());
    if (!(errors[k] = checkVoxels(slice, distance.data(), normal.data())).empty()) return;
    if (lifted) source.readAccurate(slice, accurate.data());
    if (lifted && !(errors[k] = checkAccurate(slice, accurate.data())).empty()) return;
    if (graded)
      sliceWords(
          per_slice, [&](Vec3f* out) { source.readGradient(slice, out); }, &gradients[k * per_slice]);
    if (shaded)
      sliceWords(
          per_slice, [&](Vec3f* out) { source.readShading(slice, out); }, &shadings[k * per_slice]);
    for (std::size_t v = 0; v < per_slice; ++v) {
      const Vec3f n = normalizeOrZero(normal[v]); // readers rely on unit-or-zero normals
      voxels[k * per_slice + v] = {distance[v], {n.x, n.y, n.z}};
      const bool in_band = std::fabs(distance[v]) < g.band;
      if (in_band) ++band_voxels[k];
      if (!lifted) continue;
      const std::int16_t lift = voxelLift(accurate[v], distance[v], g.band);
      lifts[k * per_slice + v] = lift;
      if (in_band) lift_errors[k] = std::max(lift_errors[k], liftedError(accurate[v], distance[v], lift, g));
    }
  });
  if (!finished) result.fail(EncodeError::kCancelled, "cancelled");
  for (const std::string& error : errors)
    result.fail(EncodeError::kInvalidField, error); // the first bad slice, whatever the threads
  if (!result.ok()) return result;
  for (std::size_t k = 0; k < band_voxels.size(); ++k) {
    result.stats.band_voxels += band_voxels[k];
    result.stats.max_lifted_error_voxels = std::max(result.stats.max_lifted_error_voxels, lift_errors[k]);
  }
  ContainerBuilder builder;
  addCommonSections(builder, makeGridSection(g, Encoding::kDense), metadata_json);
  builder.addSection(kTagDense, kSectionRequired, voxels.data(), voxels.size() * sizeof(DenseVoxel));
  if (lifted) builder.addSection(kTagLift, 0, lifts.data(), lifts.size() * sizeof(std::int16_t));
  if (graded) builder.addSection(kTagGradient, 0, gradients.data(), gradients.size() * sizeof(std::uint16_t));
  if (shaded) builder.addSection(kTagShading, 0, shadings.data(), shadings.size() * sizeof(std::uint16_t));
  result.stats.payload_bytes = voxels.size() * sizeof(DenseVoxel) + lifts.size() * sizeof(std::int16_t) +
                               (gradients.size() + shadings.size()) * sizeof(std::uint16_t);
  result.bytes = builder.finish();
  return result;
}

EncodeResult encodeDense(const DenseField& field, std::string_view metadata_json) {
  EncodeResult result;
  result.fail(EncodeError::kInvalidField, checkField(field));
  return result.ok() ? encodeDense(DenseSource(field), metadata_json) : result;
}

} // namespace format
} // namespace dng
