// Distance, sign and exact normals (DESIGN.md §4.4-4.6, "exact" mode).
//
// Every voxel asks Embree for the closest surface point within the band (the radius bound makes far
// voxels cheap: the BVH walk stops at the root's children). Band voxels get their sign from the
// fast winding number (inside where w > 0.5), robust on open meshes and soups; far voxels take the
// sign of the band voxels around their region (a flood fill), so the winding number is evaluated
// only near the surface. Each voxel is a pure function of the mesh, so the result does not depend on
// how TBB splits the work.
#include "baker.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <deque>
#include <mutex>

namespace dng {
namespace baker {

namespace {

Vec3f faceNormal(const TriangleSoup& soup, std::uint32_t t) {
  const auto& tri = soup.triangles[t];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  return normalizeOrZero(cross(b - a, c - a));
}

// Unsigned distance, exact normal direction (away from the surface) and sign, for one z slice.
void computeSlice(const TriangleSoup& soup, const ClosestPointIndex& index, const WindingNumber& winding,
                  const PseudonormalSign* pseudonormals, std::uint32_t k, DistanceResult* out) {
  const format::GridGeometry& g = out->field.grid;
  for (std::uint32_t j = 0; j < g.dims[1]; ++j) {
    for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
      const std::size_t v = g.index(i, j, k);
      const Vec3f c = g.voxelCentre(i, j, k);
      const ClosestPointIndex::Hit hit = index.query(c, g.band);
      if (!hit.found) continue; // far: sign filled in later, no normal
      const bool inside = pseudonormals ? pseudonormals->inside(c, hit.point, hit.triangle) : winding.evaluate(c) > 0.5;
      const Vec3f away = c - hit.point;
      // On the surface itself the direction is undefined: use the face normal there.
      const Vec3f n = length(away) > 1e-6f * g.voxel_size ? normalizeOrZero(away) : faceNormal(soup, hit.triangle);
      out->field.distance[v] = inside ? -hit.distance : hit.distance;
      out->field.normal[v] = inside ? n * -1.0f : n;
      out->in_band[v] = 1;
    }
  }
}

// Far voxels: each 6-connected region of far voxels takes the majority sign of the band voxels that
// touch it (ties and untouched regions: outside). Sequential and in index order: deterministic.
void fillFarSigns(DistanceResult* io) {
  const format::GridGeometry& g = io->field.grid;
  std::vector<std::uint8_t> seen(io->in_band);
  std::deque<std::size_t> queue;
  std::vector<std::size_t> region;
  const long long step[3] = {1, (long long)g.dims[0], (long long)g.dims[0] * g.dims[1]};
  for (std::size_t start = 0; start < seen.size(); ++start) {
    if (seen[start]) continue;
    long long votes = 0;
    region.clear();
    queue.push_back(start);
    seen[start] = 1;
    while (!queue.empty()) {
      const std::size_t v = queue.front();
      queue.pop_front();
      region.push_back(v);
      const std::uint32_t coord[3] = {std::uint32_t(v % g.dims[0]), std::uint32_t(v / g.dims[0] % g.dims[1]),
                                      std::uint32_t(v / (std::size_t(g.dims[0]) * g.dims[1]))};
      for (int a = 0; a < 3; ++a) {
        for (int dir = -1; dir <= 1; dir += 2) {
          if ((dir < 0 && coord[a] == 0) || (dir > 0 && coord[a] + 1 == g.dims[a])) continue;
          const std::size_t w = std::size_t((long long)v + dir * step[a]);
          if (io->in_band[w]) {
            votes += io->field.distance[w] < 0.0f ? 1 : -1;
          } else if (!seen[w]) {
            seen[w] = 1;
            queue.push_back(w);
          }
        }
      }
    }
    const float far = votes > 0 ? -g.band : g.band;
    for (std::size_t v : region)
      io->field.distance[v] = far;
  }
}

} // namespace

BakeStatus computeDistanceField(const TriangleSoup& soup, const format::GridGeometry& grid,
                                const PseudonormalSign* pseudonormals, ProgressFn progress, void* progress_user,
                                DistanceResult* out) {
  ClosestPointIndex index;
  BakeStatus status = index.build(soup);
  if (!status.ok()) return status;
  WindingNumber winding;
  if (pseudonormals == nullptr && !(status = winding.build(soup)).ok()) return status;

  out->field.reset(grid);
  out->in_band.assign(grid.voxelCount(), 0);
  std::atomic<std::uint32_t> slices_done{0};
  std::atomic<bool> cancelled{false};
  std::mutex reporting; // one callback at a time, from whichever worker gets it: callbacks need no locks
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, grid.dims[2], 1),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      for (std::uint32_t k = r.begin(); k != r.end() && !cancelled.load(); ++k) {
                        computeSlice(soup, index, winding, pseudonormals, k, out);
                        const double fraction = double(++slices_done) / grid.dims[2];
                        if (progress != nullptr && reporting.try_lock()) {
                          if (!progress(progress_user, "distance", fraction)) cancelled = true;
                          reporting.unlock();
                        }
                      }
                    });
  if (cancelled) return BakeStatus::failure(ExitCode::kInternal, "cancelled");
  fillFarSigns(out);
  out->band_voxels = 0;
  for (std::uint8_t b : out->in_band)
    out->band_voxels += b;
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
