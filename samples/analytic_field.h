// The figures' objects are analytic shapes, turned into DN fields in memory with the std-only writer
// (dng/format/writer.h) instead of baked from meshes: the exact signed distance and normal at every
// voxel centre, bricked (paper §3.2) as dngbake would write them. Header-only, no baker library.
#pragma once

#include "dng/format/writer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dng {
namespace samples {

/// A .dng file, in memory, of the field `distance(p, &normal)` (signed, negative inside; the unit
/// outward normal at the nearest surface point) over the grid of `voxel`-sized cells that covers
/// [lo, hi], with a band of `band_voxels`.
template <class Distance>
std::vector<std::uint8_t> encodeAnalytic(Vec3f lo, Vec3f hi, float voxel, float band_voxels, Distance&& distance) {
  format::GridGeometry grid;
  grid.origin = lo;
  grid.voxel_size = voxel;
  grid.dims[0] = std::uint32_t(std::ceil((hi.x - lo.x) / voxel));
  grid.dims[1] = std::uint32_t(std::ceil((hi.y - lo.y) / voxel));
  grid.dims[2] = std::uint32_t(std::ceil((hi.z - lo.z) / voxel));
  grid.band = band_voxels * voxel;
  format::DenseField field;
  field.reset(grid);
  for (std::uint32_t k = 0; k < grid.dims[2]; ++k)
    for (std::uint32_t j = 0; j < grid.dims[1]; ++j)
      for (std::uint32_t i = 0; i < grid.dims[0]; ++i) {
        const std::size_t v = grid.index(i, j, k);
        field.distance[v] = distance(grid.voxelCentre(i, j, k), &field.normal[v]);
      }
  return format::encodeBricked(field, {}, "{\"source\":\"analytic\"}").bytes;
}

/// Exact signed distance from p to a solid axis-aligned box (negative inside), and in *normal the
/// outward normal at the nearest point of its surface.
inline float boxDistance(Vec3f p, Vec3f centre, Vec3f half, Vec3f* normal) {
  const Vec3f r = p - centre;
  const Vec3f q{std::fabs(r.x) - half.x, std::fabs(r.y) - half.y, std::fabs(r.z) - half.z};
  const Vec3f sign{r.x < 0 ? -1.0f : 1.0f, r.y < 0 ? -1.0f : 1.0f, r.z < 0 ? -1.0f : 1.0f};
  const Vec3f outside{std::max(q.x, 0.0f) * sign.x, std::max(q.y, 0.0f) * sign.y, std::max(q.z, 0.0f) * sign.z};
  const float inner = std::max(q.x, std::max(q.y, q.z));
  if (inner > 0.0f) {
    *normal = normalizeOrZero(outside);
    return length(outside);
  }
  *normal = {}; // inside: the nearest face is the axis with the largest q
  if (q.x >= q.y && q.x >= q.z)
    normal->x = sign.x;
  else if (q.y >= q.z)
    normal->y = sign.y;
  else
    normal->z = sign.z;
  return inner;
}

} // namespace samples
} // namespace dng
