#include "table1_swarm.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace dng {
namespace table1 {

void Swarm::add(Vec3f p, Vec3f v) {
  px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
  vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
}

ParticleSpan Swarm::span() {
  ParticleSpan s;
  s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
  s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
  s.count = size();
  return s;
}

namespace {

struct Candidate {
  Vec3f p, v;
  float height = 0.0f; ///< how far out along the face normal
  bool keep = false;
};

// Cumulative triangle areas, for area-weighted picking.
std::vector<double> cumulativeAreas(const std::vector<Vec3f>& vertices,
                                    const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::vector<double> sums;
  sums.reserve(triangles.size());
  double total = 0.0;
  for (const auto& t : triangles) {
    total += 0.5 * double(length(cross(vertices[t[1]] - vertices[t[0]], vertices[t[2]] - vertices[t[0]])));
    sums.push_back(total);
  }
  return sums;
}

} // namespace

Swarm spawnNearSurface(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                       const reference::MeshReference& judge, float voxel, float outward, std::size_t count,
                       std::uint32_t seed, const Body* prover) {
  const std::vector<double> areas = cumulativeAreas(vertices, triangles);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pick(0.0, areas.back());
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss;
  Swarm out;
  while (out.size() < count) {
    std::vector<Candidate> batch(count - out.size() + count / 8 + 16);
    for (Candidate& c : batch) {
      const auto it = std::upper_bound(areas.begin(), areas.end(), pick(rng));
      const auto& t = triangles[std::size_t(std::min<std::ptrdiff_t>(it - areas.begin(), areas.size() - 1))];
      const Vec3f a = vertices[t[0]], b = vertices[t[1]], c3 = vertices[t[2]];
      const float r1 = std::sqrt(unit(rng)), r2 = unit(rng); // uniform over the triangle
      const Vec3f on_surface = a * (1.0f - r1) + b * (r1 * (1.0f - r2)) + c3 * (r1 * r2);
      c.height = voxel * (kSpawnNearVoxels + (kSpawnFarVoxels - kSpawnNearVoxels) * unit(rng));
      c.p = on_surface + normalizeOrZero(cross(b - a, c3 - a)) * (outward * c.height);
      c.v = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)}) * (kSpawnVoxelsPerStep * voxel / kDt * unit(rng));
    }
    // Nothing else of the surface may be nearer than 90% of the push: then the point lies on the
    // outer side of its face, about that far from the mesh (a concave fold would put it elsewhere).
    // And ray parity must say outside: where a mesh's parts overlap (scans decimated into
    // self-intersections), a face's outer side can lie inside another part.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size()), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t n = r.begin(); n != r.end(); ++n) {
        const reference::Closest closest = judge.closest(batch[n].p, batch[n].height);
        batch[n].keep = closest.found && closest.distance >= 0.9f * batch[n].height && !judge.inside(batch[n].p) &&
                        (prover == nullptr || prover->provesOutside(batch[n].p));
      }
    });
    for (const Candidate& c : batch)
      if (c.keep && out.size() < count) out.add(c.p, c.v);
  }
  return out;
}

void respawn(const Swarm& spawn, std::size_t step, Swarm* swarm) {
  const std::size_t n = swarm->size(), slice = step % kLifetime;
  const std::size_t begin = n * slice / kLifetime, end = n * (slice + 1) / kLifetime;
  for (auto [from, to] :
       {std::pair(&spawn.px, &swarm->px), std::pair(&spawn.py, &swarm->py), std::pair(&spawn.pz, &swarm->pz),
        std::pair(&spawn.vx, &swarm->vx), std::pair(&spawn.vy, &swarm->vy), std::pair(&spawn.vz, &swarm->vz)})
    std::copy(from->begin() + std::ptrdiff_t(begin), from->begin() + std::ptrdiff_t(end),
              to->begin() + std::ptrdiff_t(begin));
}

Vec3f gravityFor(float voxel) { return {0.0f, 0.0f, -kGravityVoxelsPerStep2 * voxel / (kDt * kDt)}; }

void integrate(Swarm* swarm, float dt) {
  const std::size_t n = swarm->size();
  float *px = swarm->px.data(), *py = swarm->py.data(), *pz = swarm->pz.data();
  const float *vx = swarm->vx.data(), *vy = swarm->vy.data(), *vz = swarm->vz.data();
  for (std::size_t i = 0; i < n; ++i) {
    px[i] += vx[i] * dt;
    py[i] += vy[i] * dt;
    pz[i] += vz[i] * dt;
  }
}

} // namespace table1
} // namespace dng
