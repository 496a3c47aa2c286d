// The outside baseline of the accuracy comparison: OpenVDB's meshToLevelSet on the same mesh, voxel
// size, lattice and band as a baked field, sampled trilinearly. The only OpenVDB translation unit of
// accuracy_bench (each one costs ~30 s and over 1 GB to compile).
#pragma once

#include "dng/format/vec3.h"

#include <array>
#include <cstdint>
#include <vector>

namespace dng {
namespace bench {

/// OpenVDB's answer at one point: the trilinear distance (tools::BoxSampler) and the normalized
/// gradient of that trilinear field (zero where it is flat).
struct VdbReading {
  float distance = 0.0f;
  Vec3f normal;
};

/// Builds the level set with voxel centres at origin + (i + 1/2) * voxel (the .dng lattice) and a
/// half-width of band / voxel, then reads it at every point. Thread-safe reads over TBB.
std::vector<VdbReading> meshToLevelSetReadings(const std::vector<Vec3f>& vertices,
                                               const std::vector<std::array<std::uint32_t, 3>>& triangles, Vec3f origin,
                                               float voxel, float band, const std::vector<Vec3f>& points);

} // namespace bench
} // namespace dng
