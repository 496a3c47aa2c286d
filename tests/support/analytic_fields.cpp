#include "analytic_fields.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace analytic {

AnalyticField planeField(Vec3f normal, float offset) {
  const Vec3f n = normalizeOrZero(normal);
  return [n, offset](Vec3f p) { return Exact{dot(n, p) - offset, n}; };
}

AnalyticField sphereField(Vec3f centre, float radius) {
  return [centre, radius](Vec3f p) {
    const Vec3f r = p - centre;
    const float len = length(r);
    return Exact{len - radius, len > 0.0f ? r * (1.0f / len) : Vec3f{0, 0, 1}};
  };
}

AnalyticField boxField(Vec3f centre, Vec3f half) {
  return [centre, half](Vec3f p) {
    const Vec3f r = p - centre;
    const Vec3f q{std::fabs(r.x) - half.x, std::fabs(r.y) - half.y, std::fabs(r.z) - half.z};
    const Vec3f sign{r.x < 0 ? -1.0f : 1.0f, r.y < 0 ? -1.0f : 1.0f, r.z < 0 ? -1.0f : 1.0f};
    const Vec3f outside{std::max(q.x, 0.0f) * sign.x, std::max(q.y, 0.0f) * sign.y, std::max(q.z, 0.0f) * sign.z};
    const float inner = std::max(q.x, std::max(q.y, q.z));
    if (inner > 0.0f) return Exact{length(outside), normalizeOrZero(outside)};
    // Inside: the nearest face is the axis with the largest q.
    Vec3f n;
    if (q.x >= q.y && q.x >= q.z)
      n.x = sign.x;
    else if (q.y >= q.z)
      n.y = sign.y;
    else
      n.z = sign.z;
    return Exact{inner, n};
  };
}

AnalyticField cylinderField(Vec3f centre, float radius, float half_height) {
  return [centre, radius, half_height](Vec3f p) {
    const Vec3f r = p - centre;
    const float radial = std::sqrt(r.x * r.x + r.y * r.y);
    const float side = radial - radius, cap = std::fabs(r.z) - half_height;
    const Vec3f radial_dir = radial > 0.0f ? Vec3f{r.x / radial, r.y / radial, 0.0f} : Vec3f{1, 0, 0};
    const Vec3f cap_dir{0, 0, r.z < 0 ? -1.0f : 1.0f};
    if (side > 0.0f && cap > 0.0f) { // outside the rim: distance to the circle
      const Vec3f d = radial_dir * side + cap_dir * cap;
      return Exact{length(d), normalizeOrZero(d)};
    }
    if (side > cap) return Exact{side, radial_dir};
    return Exact{cap, cap_dir};
  };
}

format::GridGeometry cubeGrid(Vec3f lo, float voxel_size, std::uint32_t n, float band_voxels) {
  format::GridGeometry g;
  g.origin = lo;
  g.voxel_size = voxel_size;
  g.dims[0] = g.dims[1] = g.dims[2] = n;
  g.band = band_voxels * voxel_size;
  return g;
}

format::DenseField sampleField(const format::GridGeometry& grid, const AnalyticField& field) {
  format::DenseField out;
  out.reset(grid);
  for (std::uint32_t k = 0; k < grid.dims[2]; ++k)
    for (std::uint32_t j = 0; j < grid.dims[1]; ++j)
      for (std::uint32_t i = 0; i < grid.dims[0]; ++i) {
        const Exact e = field(grid.voxelCentre(i, j, k));
        const std::size_t v = grid.index(i, j, k);
        out.distance[v] = e.distance;
        out.normal[v] = e.normal;
      }
  return out;
}

std::vector<Vec3f> randomPoints(Vec3f lo, Vec3f hi, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Vec3f> points(count);
  for (Vec3f& p : points) {
    p = {lo.x + (hi.x - lo.x) * unit(rng), lo.y + (hi.y - lo.y) * unit(rng), lo.z + (hi.z - lo.z) * unit(rng)};
  }
  return points;
}
} // namespace analytic
} // namespace dng
