// Distance, sign and exact normals (docs/DESIGN.md §5.6-5.7, "exact" mode) in the sparse band.
//
// 1. Topology: every 8^3 block that a triangle comes within a band of (a triangle/box test against
//    the block grown by the band) is allocated; nothing else ever is.
// 2. Every voxel of those blocks asks Embree for the closest surface point within the band; the
//    radius bound makes far voxels cheap. Band voxels get their sign from the fast winding number
//    (inside where w > 0.5, robust on open meshes and soups) or from pseudonormals.
// 3. BandGrid::finishBand drops blocks with no band voxel and signs everything else by flood fill,
//    so the winding number is evaluated only near the surface.
// Each voxel is a pure function of the mesh, so the result does not depend on how TBB splits the work.
#include "parallel_blocks.h"
#include "stages.h"
#include "triangle_box.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dng {
namespace baker {

namespace {

Vec3f faceNormal(const TriangleSoup& soup, std::uint32_t t) {
  const auto& tri = soup.triangles[t];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  return normalizeOrZero(cross(b - a, c - a));
}

// Appends the blocks holding a voxel centre within the band of triangle t.
void addTriangleBlocks(const TriangleSoup& soup, const format::GridGeometry& g, std::uint32_t t,
                       std::vector<BlockKey>* out) {
  const auto& tri = soup.triangles[t];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  const int dim = VoxelBlock::kDim;
  const float h = g.voxel_size;
  int lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    const float low = std::min({component(a, axis), component(b, axis), component(c, axis)});
    const float high = std::max({component(a, axis), component(b, axis), component(c, axis)});
    const float origin = component(g.origin, axis);
    const float last = float(g.dims[axis] - 1);
    // Voxel centres within the band of the triangle's box, clamped to the grid, in blocks.
    lo[axis] = int(std::clamp(std::floor((low - g.band - origin) / h - 0.5f), 0.0f, last)) / dim;
    hi[axis] = int(std::clamp(std::ceil((high + g.band - origin) / h - 0.5f), 0.0f, last)) / dim;
  }
  // A voxel centre within the band lies in the block's box of centres grown by the band.
  const float half = (0.5f * float(dim - 1) * h + g.band) * (1.0f + 1e-4f);
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const Vec3f centre = g.origin + Vec3f{float(x * dim), float(y * dim), float(z * dim)} * h +
                             Vec3f{1.0f, 1.0f, 1.0f} * (0.5f * float(dim) * h);
        if (triangleOverlapsBox(a, b, c, centre, half)) out->push_back({x, y, z});
      }
}

// The blocks near the surface, sorted and unique (so the same whatever the thread count). Each run of
// triangles drops its repeats first: neighbouring triangles share most of their blocks, and sorting
// every triangle's blocks at the end had been a tenth of the bunny's distance stage, on one thread.
std::vector<BlockKey> bandBlocks(const TriangleSoup& soup, const format::GridGeometry& g) {
  tbb::enumerable_thread_specific<std::vector<BlockKey>> found;
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(soup.triangles.size()), 1024),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      std::vector<BlockKey> run;
                      for (std::uint32_t t = r.begin(); t != r.end(); ++t)
                        addTriangleBlocks(soup, g, t, &run);
                      std::sort(run.begin(), run.end());
                      run.erase(std::unique(run.begin(), run.end()), run.end());
                      std::vector<BlockKey>& local = found.local();
                      local.insert(local.end(), run.begin(), run.end());
                    });
  std::vector<BlockKey> keys;
  for (const std::vector<BlockKey>& local : found)
    keys.insert(keys.end(), local.begin(), local.end());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

struct SignSource {
  const WindingNumber* winding;
  const PseudonormalSign* pseudonormals; // used instead of the winding number when set
  bool inside(Vec3f p, const ClosestPointIndex::Hit& hit) const {
    return pseudonormals ? pseudonormals->inside(p, hit.point, hit.triangle) : winding->evaluate(p) > 0.5;
  }
};

// Distance, exact normal (away from the surface) and sign for every band voxel of one block.
void computeBlock(const TriangleSoup& soup, const ClosestPointIndex& index, const SignSource& sign,
                  const format::GridGeometry& g, const VoxelBlock& block) {
  const int dim = VoxelBlock::kDim;
  for (int x = 0; x < dim; ++x)
    for (int y = 0; y < dim; ++y)
      for (int z = 0; z < dim; ++z) {
        const std::int64_t i = block.origin[0] + x, j = block.origin[1] + y, k = block.origin[2] + z;
        if (i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) continue; // past the grid's edge
        const Vec3f c = g.voxelCentre(std::uint32_t(i), std::uint32_t(j), std::uint32_t(k));
        const ClosestPointIndex::Hit hit = index.query(c, g.band);
        if (!hit.found || hit.distance >= g.band) continue; // far: signed later by flood fill
        const bool inside = sign.inside(c, hit);
        const Vec3f away = c - hit.point;
        // On the surface itself the direction is undefined: use the face normal there.
        const Vec3f n = length(away) > 1e-6f * g.voxel_size ? normalizeOrZero(away) : faceNormal(soup, hit.triangle);
        const int v = VoxelBlock::offset(x, y, z);
        block.distance[v] = inside ? -hit.distance : hit.distance;
        block.setNormal(v, inside ? n * -1.0f : n);
      }
}

} // namespace

BakeStatus computeDistanceField(const TriangleSoup& soup, const PseudonormalSign* pseudonormals, ProgressFn progress,
                                void* progress_user, BandGrid* out) {
  ClosestPointIndex index;
  BakeStatus status = index.build(soup);
  if (!status.ok()) return status;
  WindingNumber winding;
  if (pseudonormals == nullptr && !(status = winding.build(soup)).ok()) return status;
  const SignSource sign{&winding, pseudonormals};

  out->addBlocks(bandBlocks(soup, out->grid()));
  const std::vector<VoxelBlock> blocks = out->blocks();
  const bool finished = forEachBlockInParallel(blocks.size(), "distance", progress, progress_user, [&](std::size_t b) {
    computeBlock(soup, index, sign, out->grid(), blocks[b]);
  });
  if (!finished) return BakeStatus::cancelled();
  out->finishBand();
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
