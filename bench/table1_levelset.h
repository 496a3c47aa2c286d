// Table 1's level-set peer: OpenVDB's meshToLevelSet of the same mesh on the same lattice, voxel size
// and band as the baked field, converted to NanoVDB, and stepped with gradient normals and the same
// impact rule (bench/table1_bench.cpp). Building it is the only OpenVDB translation unit of the
// benchmark (table1_levelset.cpp, slow to compile); stepping needs NanoVDB's headers only.
#pragma once

#include "table1_swarm.h"

#include <nanovdb/util/GridHandle.h>
#include <nanovdb/util/HostBuffer.h>

namespace dng {
namespace table1 {

/// The narrow-band level set with voxel centres at origin + (i + 1/2) * voxel (the .dng lattice),
/// half-width band / voxel, as a NanoVDB float grid (distances in world units, negative inside).
nanovdb::GridHandle<nanovdb::HostBuffer> meshToNanoLevelSet(const std::vector<Vec3f>& vertices,
                                                            const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                            Vec3f origin, float voxel, float band);

/// How a step reads the level set.
enum class LevelSetRead {
  kNearest,   ///< the nearest voxel's value; normal from central differences of its 6 neighbours
  kTrilinear, ///< trilinear value and the gradient of that trilinear field (nanovdb::SampleFromVoxels)
};

/// One step of dt: read distance d and normal N at each particle, apply the impact rule (paper §3.4,
/// dng::applyImpact: the rule every dngrid body uses) with restitution and collision distance, then
/// p += v dt. Where the gradient is zero (outside the narrow band) the particle just moves.
/// Single-threaded, one ReadAccessor per call (as a particle loop would hold one).
void stepLevelSet(const nanovdb::GridHandle<nanovdb::HostBuffer>& levelset, LevelSetRead read, float restitution,
                  float collision_distance, float dt, Swarm* swarm);

} // namespace table1
} // namespace dng
