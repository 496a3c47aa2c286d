#include "ray_caster.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <vector>

namespace dng {
namespace leak {

namespace {

// How far short of the surface a stopped particle waits, in voxels: far above float rounding of the
// world <-> body round trip (~1e-6 voxel), far below anything the judge calls deep.
constexpr float kStandOffVoxels = 1e-3f;

} // namespace

std::uint64_t rayCastStep(const reference::MeshReference& mesh, float voxel, float restitution, float dt,
                          const Body& before, const Body& after, testing::Swarm* swarm) {
  tbb::combinable<std::uint64_t> hits([] { return std::uint64_t(0); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, swarm->size()), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<reference::Crossing> crossings;
    for (std::size_t n = r.begin(); n != r.end(); ++n) {
      const Vec3f p = swarm->position(n), v = swarm->velocity(n);
      const Vec3f a = before.toLocal(p), b = after.toLocal(p + v * dt);
      mesh.crossings(a, b, &crossings);
      Vec3f end = p + v * dt, velocity = v;
      if (!crossings.empty()) {
        const reference::Crossing& first = crossings.front();
        Vec3f n_local = mesh.faceNormal(first.triangle);
        const Vec3f hit = a + (b - a) * first.t;
        if (dot(a - hit, n_local) < 0.0f) n_local = n_local * -1.0f; // the side the particle came from
        Vec3f stop = hit + n_local * (kStandOffVoxels * voxel);
        // In a concave corner the stand-off from one face can land a rounding error past the other:
        // then the particle keeps its place on the body for this step, which is known to be clear.
        mesh.crossings(a, stop, &crossings);
        if (!crossings.empty() || mesh.closest(stop).distance < 0.5f * kStandOffVoxels * voxel) stop = a;
        end = after.toWorld(stop);
        const Vec3f normal = after.rotateToWorld(n_local);
        const Vec3f surface = before.surfaceVelocity(p);
        const Vec3f relative = v - surface;
        const float vn = dot(relative, normal);
        if (vn < 0.0f) velocity = surface + relative - normal * ((1.0f + restitution) * vn);
        ++hits.local();
      }
      swarm->px[n] = end.x, swarm->py[n] = end.y, swarm->pz[n] = end.z;
      swarm->vx[n] = velocity.x, swarm->vy[n] = velocity.y, swarm->vz[n] = velocity.z;
    }
  });
  return hits.combine([](std::uint64_t x, std::uint64_t y) { return x + y; });
}

} // namespace leak
} // namespace dng
