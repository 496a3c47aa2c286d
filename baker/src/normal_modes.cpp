// The paper's two ways to make normals (§3.1), on top of the exact distances:
//   normal-blur (method 1): rasterize triangle normals into the voxels they overlap, average them per
//     voxel, blur the vector grid with a linearly attenuated kernel for K rounds, after each round put
//     the surface voxels back to their rasterized normals, finally normalize;
//   potential (method 2): rasterize occupancy, blur it the same way, normal = normalized gradient by
//     central differences (pointing down the potential, away from the surface), so a zero-thickness
//     sheet repels from both sides.
// This file rasterizes; the blur and what each method makes of it work on OpenVDB grids in
// blurred_normals.cpp.
#include "stages.h"
#include "triangle_box.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dng {
namespace baker {

namespace {

// A voxel a triangle overlaps, with the triangle's normal.
struct Hit {
  std::uint64_t key; // k, j, i: sorting by it orders voxels z-major
  // The hit's place in triangle order, which breaks ties between equal keys (4 billion hits would
  // have taken 96 GB first).
  std::uint32_t order;
  Vec3f normal;
};

// Appends the voxels triangle `t` overlaps (touching counts, with a little slack so rounding cannot
// break the symmetry).
void hitsOf(const TriangleSoup& soup, const format::GridGeometry& g, std::size_t t, std::vector<Hit>* out) {
  const float h = g.voxel_size;
  const float half = 0.5f * h * (1.0f + 1e-4f);
  const auto& tri = soup.triangles[t];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  const Vec3f n = normalizeOrZero(cross(b - a, c - a));
  std::uint32_t lo[3], hi[3];
  // One voxel of slack around the bounding box: a face lying exactly on a voxel boundary touches the
  // layers on both sides, and floor() alone would test only one of them.
  for (int axis = 0; axis < 3; ++axis) {
    const float low = std::min({component(a, axis), component(b, axis), component(c, axis)});
    const float high = std::max({component(a, axis), component(b, axis), component(c, axis)});
    const float origin = component(g.origin, axis), last = float(g.dims[axis] - 1);
    lo[axis] = std::uint32_t(std::clamp(std::floor((low - origin) / h) - 1.0f, 0.0f, last));
    hi[axis] = std::uint32_t(std::clamp(std::floor((high - origin) / h) + 1.0f, 0.0f, last));
  }
  for (std::uint32_t k = lo[2]; k <= hi[2]; ++k)
    for (std::uint32_t j = lo[1]; j <= hi[1]; ++j)
      for (std::uint32_t i = lo[0]; i <= hi[0]; ++i)
        if (triangleOverlapsBox(a, b, c, g.voxelCentre(i, j, k), half))
          out->push_back({(std::uint64_t(k) << 42) | (std::uint64_t(j) << 21) | i, 0, n});
}

// Every voxel a triangle overlaps, with the average of the normals of the triangles overlapping it
// (summed in file order, so the result never depends on threads), sorted by voxel. Triangles are
// rasterized in parallel runs, joined in file order; the sort breaks ties by that order.
std::vector<SurfaceVoxel> rasterize(const TriangleSoup& soup, const format::GridGeometry& g) {
  constexpr std::size_t kRun = 2048; // triangles per task
  const std::size_t count = soup.triangles.size();
  std::vector<std::vector<Hit>> runs((count + kRun - 1) / kRun);
  tbb::parallel_for(std::size_t(0), runs.size(), [&](std::size_t r) {
    for (std::size_t t = r * kRun; t < std::min(count, (r + 1) * kRun); ++t)
      hitsOf(soup, g, t, &runs[r]);
  });
  std::vector<Hit> hits;
  for (std::vector<Hit>& run : runs)
    hits.insert(hits.end(), run.begin(), run.end());
  for (std::size_t n = 0; n < hits.size(); ++n)
    hits[n].order = std::uint32_t(n);
  tbb::parallel_sort(hits.begin(), hits.end(),
                     [](const Hit& x, const Hit& y) { return x.key < y.key || (x.key == y.key && x.order < y.order); });
  std::vector<SurfaceVoxel> surface;
  for (std::size_t first = 0; first < hits.size();) {
    Vec3f sum;
    std::size_t last = first;
    for (; last < hits.size() && hits[last].key == hits[first].key; ++last)
      sum = sum + hits[last].normal;
    const std::uint64_t key = hits[first].key, mask = (1u << 21) - 1;
    surface.push_back(
        {{std::int32_t(key & mask), std::int32_t((key >> 21) & mask), std::int32_t(key >> 42)}, normalizeOrZero(sum)});
    first = last;
  }
  return surface;
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

BakeStatus applyNormalMode(const TriangleSoup& soup, const BakeOptions& options, ProgressFn progress,
                           void* progress_user, BandGrid* io) {
  const BakeStatus checked = checkBakeOptions(options); // for callers other than bake()
  if (!checked.ok() || options.mode == NormalMode::kExact) return checked;
  const std::vector<SurfaceVoxel> surface = rasterize(soup, io->grid());
  return options.mode == NormalMode::kNormalBlur
             ? blurNormals(surface, options.blur_radius, options.blur_rounds, io, progress, progress_user)
             : potentialNormals(surface, options.blur_radius, options.blur_rounds, io, progress, progress_user);
}

} // namespace baker
} // namespace dng
