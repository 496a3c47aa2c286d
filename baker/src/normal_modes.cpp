// The paper's two ways to make normals (§3.1), on top of the exact distances:
//   normal-blur (method 1): rasterize triangle normals into the voxels they overlap, average them per
//     voxel, blur the vector grid with a linearly attenuated kernel for K rounds, after each round put
//     the surface voxels back to their rasterized normals, finally normalize;
//   potential (method 2): rasterize occupancy, blur it the same way, normal = normalized gradient by
//     central differences (pointing down the potential, away from the surface), so a zero-thickness
//     sheet repels from both sides.
// The kernel is the separable tent t(i) = 1 - |i| / (R + 1), |i| <= R, applied along x, y and z: a
// linear attenuation that costs 3 (2R + 1) taps per voxel instead of (2R + 1)^3.
#include "baker.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dng {
namespace baker {

namespace {

// Separating-axis test of a triangle against an axis-aligned box (centre c, half size h): the 13
// axes of Akenine-Moeller, "Fast 3D Triangle-Box Overlap Testing", 2001.
bool triangleOverlapsBox(Vec3f a, Vec3f b, Vec3f c, Vec3f centre, float half) {
  const Vec3f v[3] = {a - centre, b - centre, c - centre};
  const Vec3f e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  auto separated = [&](Vec3f axis) {
    const float p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
    const float r = half * (std::fabs(axis.x) + std::fabs(axis.y) + std::fabs(axis.z));
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (const Vec3f& axis : axes) {
    if (separated(axis)) return false;
  }
  if (separated(cross(e[0], e[1]))) return false;
  for (const Vec3f& edge : e) {
    for (const Vec3f& axis : axes) {
      const Vec3f n = cross(edge, axis);
      if (dot(n, n) > 0.0f && separated(n)) return false;
    }
  }
  return true;
}

// Calls visit(voxel index, face normal) for every voxel a triangle overlaps, triangles in file order.
template <class Visit> void rasterize(const TriangleSoup& soup, const format::GridGeometry& g, Visit visit) {
  const float h = g.voxel_size;
  for (const auto& t : soup.triangles) {
    const Vec3f a = soup.vertices[t[0]], b = soup.vertices[t[1]], c = soup.vertices[t[2]];
    const Vec3f n = normalizeOrZero(cross(b - a, c - a));
    std::uint32_t lo[3], hi[3];
    const float mins[3] = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
    const float maxs[3] = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
    const float origin[3] = {g.origin.x, g.origin.y, g.origin.z};
    // One voxel of slack around the bounding box: a face lying exactly on a voxel boundary touches the
    // layers on both sides, and floor() alone would test only one of them.
    for (int ax = 0; ax < 3; ++ax) {
      lo[ax] = std::uint32_t(std::clamp(std::floor((mins[ax] - origin[ax]) / h) - 1.0f, 0.0f, float(g.dims[ax] - 1)));
      hi[ax] = std::uint32_t(std::clamp(std::floor((maxs[ax] - origin[ax]) / h) + 1.0f, 0.0f, float(g.dims[ax] - 1)));
    }
    // Touching counts as overlapping, with a little slack so rounding cannot break the symmetry.
    const float half = 0.5f * h * (1.0f + 1e-4f);
    for (std::uint32_t k = lo[2]; k <= hi[2]; ++k)
      for (std::uint32_t j = lo[1]; j <= hi[1]; ++j)
        for (std::uint32_t i = lo[0]; i <= hi[0]; ++i) {
          if (triangleOverlapsBox(a, b, c, g.voxelCentre(i, j, k), half)) visit(g.index(i, j, k), n);
        }
  }
}

// One pass of the tent kernel along `axis` (0, 1, 2) over a grid of T (float or Vec3f).
template <class T>
void blurAxis(const format::GridGeometry& g, int axis, std::uint32_t radius, const std::vector<T>& in,
              std::vector<T>* out) {
  const std::size_t stride = axis == 0 ? 1 : axis == 1 ? g.dims[0] : std::size_t(g.dims[0]) * g.dims[1];
  const auto n = std::int64_t(g.dims[axis]);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, g.dims[2]), [&](const tbb::blocked_range<std::uint32_t>& r) {
    for (std::uint32_t k = r.begin(); k != r.end(); ++k)
      for (std::uint32_t j = 0; j < g.dims[1]; ++j)
        for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
          const std::size_t v = g.index(i, j, k);
          const std::int64_t at = axis == 0 ? i : axis == 1 ? j : k;
          // Normalized by the weights inside the grid: a blur must not grow values (the surface
          // voxels, reset each round, must stay the potential's maximum).
          T sum{};
          float weights = 0.0f;
          for (std::int64_t o = -std::int64_t(radius); o <= std::int64_t(radius); ++o) {
            if (at + o < 0 || at + o >= n) continue;
            const float w = 1.0f - float(std::llabs(o)) / float(radius + 1);
            sum = sum + in[std::size_t(std::int64_t(v) + o * std::int64_t(stride))] * w;
            weights += w;
          }
          (*out)[v] = sum * (1.0f / weights);
        }
  });
}

template <class T>
void blurRounds(const format::GridGeometry& g, const BakeOptions& o, const std::vector<std::uint8_t>& surface,
                const std::vector<T>& surface_values, std::vector<T>* io) {
  std::vector<T> scratch(io->size());
  for (std::uint32_t round = 0; round < o.blur_rounds; ++round) {
    blurAxis(g, 0, o.blur_radius, *io, &scratch);
    blurAxis(g, 1, o.blur_radius, scratch, io);
    blurAxis(g, 2, o.blur_radius, *io, &scratch);
    io->swap(scratch);
    for (std::size_t v = 0; v < io->size(); ++v) {
      if (surface[v]) (*io)[v] = surface_values[v]; // the paper: surface voxels return to their initial value
    }
  }
}

void normalBlur(const TriangleSoup& soup, const BakeOptions& o, DistanceResult* io) {
  const format::GridGeometry& g = io->field.grid;
  std::vector<Vec3f> raster(g.voxelCount());
  std::vector<std::uint8_t> surface(g.voxelCount(), 0);
  rasterize(soup, g, [&](std::size_t v, Vec3f n) {
    raster[v] = raster[v] + n;
    surface[v] = 1;
  });
  for (Vec3f& n : raster)
    n = normalizeOrZero(n); // average of the normals that hit the voxel
  std::vector<Vec3f> field = raster;
  blurRounds(g, o, surface, raster, &field);
  for (std::size_t v = 0; v < field.size(); ++v) {
    const Vec3f n = normalizeOrZero(field[v]);
    if (dot(n, n) > 0.0f) io->field.normal[v] = n; // beyond the blur's reach the exact normal stays
  }
}

void potentialGradient(const TriangleSoup& soup, const BakeOptions& o, DistanceResult* io) {
  const format::GridGeometry& g = io->field.grid;
  std::vector<float> potential(g.voxelCount(), 0.0f);
  std::vector<std::uint8_t> surface(g.voxelCount(), 0);
  rasterize(soup, g, [&](std::size_t v, Vec3f) {
    potential[v] = 1.0f;
    surface[v] = 1;
  });
  const std::vector<float> occupied = potential;
  blurRounds(g, o, surface, occupied, &potential);
  auto at = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return potential[g.index(i, j, k)]; };
  for (std::uint32_t k = 1; k + 1 < g.dims[2]; ++k)
    for (std::uint32_t j = 1; j + 1 < g.dims[1]; ++j)
      for (std::uint32_t i = 1; i + 1 < g.dims[0]; ++i) {
        const Vec3f downhill{at(i - 1, j, k) - at(i + 1, j, k), at(i, j - 1, k) - at(i, j + 1, k),
                             at(i, j, k - 1) - at(i, j, k + 1)};
        // Where the potential is flat (a sheet's own voxels, or beyond the blur) keep the exact normal
        // rather than normalizing rounding noise.
        const Vec3f n = length(downhill) > 1e-4f ? normalizeOrZero(downhill) : Vec3f{};
        const std::size_t v = g.index(i, j, k);
        if (dot(n, n) == 0.0f) continue;
        // Down the potential is away from the surface outside, deeper inside a solid: orient it into
        // the exact normal's hemisphere (reliable in the band even in voxels the surface cuts), else
        // by the side of the surface.
        const Vec3f exact = io->field.normal[v];
        const bool flip = dot(exact, exact) > 0.0f ? dot(n, exact) < 0.0f : io->field.distance[v] < 0.0f;
        io->field.normal[v] = flip ? n * -1.0f : n;
      }
}

} // namespace

const char* normalModeName(NormalMode mode) {
  switch (mode) {
  case NormalMode::kNormalBlur: return "normal-blur";
  case NormalMode::kPotential: return "potential";
  case NormalMode::kExact: return "exact";
  }
  return "?";
}

BakeStatus applyNormalMode(const TriangleSoup& soup, const BakeOptions& options, DistanceResult* io) {
  if (options.mode != NormalMode::kExact && (options.blur_radius < 1 || options.blur_radius > 8))
    return BakeStatus::failure(ExitCode::kUsage, "--blur-radius must be between 1 and 8 (the paper uses 2-4)");
  if (options.mode == NormalMode::kNormalBlur) normalBlur(soup, options, io);
  if (options.mode == NormalMode::kPotential) potentialGradient(soup, options, io);
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
