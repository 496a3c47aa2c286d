// Table 1's particles (bench/table1_bench.cpp): a swarm kept near a mesh's surface by a fixed respawn
// cycle, so that the paper's condition "all particles close to the object" holds at every step, and
// the plain gravity + integration loop every method is measured against.
#pragma once

#include "dng/body.h"
#include "dng/particles.h"
#include "mesh_reference.h"

#include <array>
#include <cstdint>
#include <vector>

namespace dng {
namespace table1 {

/// The time step of every method: 1/60 s, as in the earlier measurement the table repeats.
constexpr float kDt = 1.0f / 60.0f;
/// Every particle lives this many steps and then starts again from its spawn state, so 1/kLifetime
/// of the swarm respawns each step and no particle ever gets more than ~kLifetime voxels away.
constexpr std::size_t kLifetime = 8;
/// Spawn speeds are uniform up to this many voxels per step, in random directions.
constexpr float kSpawnVoxelsPerStep = 1.0f;
/// Spawn points are this far (in voxels) outside the surface, uniformly.
constexpr float kSpawnNearVoxels = 0.1f;
constexpr float kSpawnFarVoxels = 2.0f;
/// Gravity in voxels per step squared: meshes come in any unit, so gravity follows the voxel.
constexpr float kGravityVoxelsPerStep2 = 0.02f;

/// Particles as structure-of-arrays (stride 4 bytes): the layout every method reads.
struct Swarm {
  std::vector<float> px, py, pz, vx, vy, vz;

  std::size_t size() const { return px.size(); }
  Vec3f position(std::size_t n) const { return {px[n], py[n], pz[n]}; }
  Vec3f velocity(std::size_t n) const { return {vx[n], vy[n], vz[n]}; }
  void add(Vec3f p, Vec3f v);
  /// Positions and velocities only: no per-particle outputs (they would cost every method a store).
  ParticleSpan span();
};

/// `count` spawn states near the surface of a mesh: a point on a random triangle (area-weighted)
/// pushed out along the face normal (times `outward`: +1 when the faces point outwards, -1 when the
/// mesh is wound inside out) by kSpawnNearVoxels..kSpawnFarVoxels,
/// kept only where no other part of the surface is nearer (so the point is really that far from the
/// mesh) and ray parity says outside, with a random velocity of up to kSpawnVoxelsPerStep. In random order, as an
/// emitter produces them. With `prover` set, only points its field proves outside (Body::provesOutside)
/// are kept as well, as an emitter that asks spawns. Deterministic for a given seed.
Swarm spawnNearSurface(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                       const reference::MeshReference& judge, float voxel, float outward, std::size_t count,
                       std::uint32_t seed, const Body* prover = nullptr);

/// Step `step`'s respawn: the slice (step mod kLifetime) of the swarm goes back to its spawn states.
/// Part of every method's timed step (the plain loop's too), so it costs all of them the same.
void respawn(const Swarm& spawn, std::size_t step, Swarm* swarm);

/// Gravity for a field of this voxel size (kGravityVoxelsPerStep2 at kDt).
Vec3f gravityFor(float voxel);

/// The "no collision" method: p += v dt for every particle.
void integrate(Swarm* swarm, float dt);

} // namespace table1
} // namespace dng
