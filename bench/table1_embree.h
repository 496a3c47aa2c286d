// Table 1's exact peer: Embree 3 ray casting of each step's segment against the original triangles,
// as a particle system without a distance field would collide (bench/table1_bench.cpp).
#pragma once

#include "table1_swarm.h"

#include <memory>

namespace dng {
namespace table1 {

/// A plain Embree scene (default flags and build quality: what a game would build) over a triangle
/// soup, and the stepper that casts each particle's move through it.
class EmbreeCaster {
public:
  EmbreeCaster();
  ~EmbreeCaster();
  EmbreeCaster(const EmbreeCaster&) = delete;
  EmbreeCaster& operator=(const EmbreeCaster&) = delete;

  /// Builds the BVH; false when Embree fails. `voxel` sets the stand-off (see step()). `device_config`
  /// is Embree's device configuration string (null: its defaults, the best kernels this CPU has;
  /// "max_isa=avx2": no AVX-512, what a CPU without it runs).
  bool build(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
             float voxel, const char* device_config = nullptr);

  /// Whether build() succeeded.
  bool built() const;

  /// Bytes Embree holds for the scene (vertex and index buffers, BVH), as its memory monitor
  /// callback reported them while building: Embree has no query for a scene's size.
  std::size_t bytes() const;

  /// One step of dt: each particle's segment p -> p + v dt is cast with rtcIntersect1 (`packet` 1) or
  /// in packets of 4, 8 or 16 rays (rtcIntersect4/8/16). On a hit the particle stops 0.001 voxel in
  /// front of the hit face, on the side it came from, and its velocity reflects off the face with
  /// the impact rule (paper §3.4, restitution beta); otherwise it moves the whole segment.
  /// Single-threaded. `packet` must be 1, 4, 8 or 16.
  void step(int packet, float restitution, float dt, Swarm* swarm) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace table1
} // namespace dng
