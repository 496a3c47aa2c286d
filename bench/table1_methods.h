// The methods of Table 1 (bench/table1_bench.cpp): what each does per step, what memory it holds, and
// the untimed judge that counts its particles' crossings of the mesh.
#pragma once

#include "dng/instruction_set.h"
#include "table1_scene.h"

#include <functional>
#include <string>

namespace dng {
namespace table1 {

/// The same response rule everywhere: impact (paper §3.4) with this restitution...
constexpr float kRestitution = 0.5f;
/// ...and, for the field methods, this collision distance L in voxels (dngrid and NanoVDB alike).
constexpr float kCollisionVoxels = 0.1f;

enum class Method {
  kPlain,               ///< no collision: p += v dt
  kNoBody,              ///< dng::stepParticles with no body: the call's own cost
  kImpact,              ///< dngrid, impact
  kImpactDragFlow,      ///< dngrid, impact + drag + surface flow (§3.5-3.6)
  kImpactDragFlowSwept, ///< the same with Material::swept
  kEmbree1,             ///< Embree rtcIntersect1 per particle
  kEmbree4,             ///< Embree rtcIntersect4 packets
  kEmbree8,
  kEmbree16,
  kLevelSetNearest,   ///< NanoVDB, nearest voxel + central differences
  kLevelSetTrilinear, ///< NanoVDB, trilinear value and gradient
};

/// A method, and for dngrid the field's encoding and normal mode.
struct Case {
  Method method = Method::kPlain;
  bool dense = false; ///< dngrid only: the dense field instead of the bricked one
  bool exact = false; ///< dngrid only: a bricked field baked in exact mode instead of the default normal-blur
  /// dngrid: the AVX2 kernels instead of the best this CPU has (where that is AVX-512); Embree: a
  /// device limited to AVX2 (Embree's max_isa=avx2).
  bool avx2 = false;
  /// dngrid only: spawn points limited to those the field proves outside (Body::provesOutside), as an
  /// emitter that asks spawns; every other case keeps the spawn points the mesh alone chose.
  bool proven = false;

  bool usesEmbree() const {
    return method == Method::kEmbree1 || method == Method::kEmbree4 || method == Method::kEmbree8 ||
           method == Method::kEmbree16;
  }
  bool usesField() const {
    return method == Method::kImpact || method == Method::kImpactDragFlow || method == Method::kImpactDragFlowSwept;
  }
};

/// Short identifier for benchmark names, e.g. "dngrid_bricked_impact", "embree_rtcIntersect16".
std::string caseId(const Case& c);
/// Words for the table, e.g. "dngrid bricked, impact+drag+flow".
std::string caseLabel(const Case& c);

/// A case's work per step, after the respawn and gravity every method shares.
using Stepper = std::function<void(Swarm*)>;
Stepper stepperFor(const MeshScene& scene, const Case& c);

/// Bytes the method keeps for the mesh: the mapped .dng, Embree's scene, the NanoVDB grid; 0 for the
/// plain loop and the call without a body. The particles themselves (24 bytes each) come on top for
/// every method alike.
std::size_t caseBytes(const MeshScene& scene, const Case& c);

/// One step of the table's loop: respawn (table1_swarm.h), gravity, then the case's step.
struct Simulation {
  Simulation(const MeshScene& scene, const Case& c, std::size_t particles);
  void step() {
    prepare();
    stepper(&swarm);
  }
  /// The part every method shares: this step's respawn, then gravity.
  void prepare();
  /// The respawn cycle's warm-up: kLifetime steps, after which every particle's age is spread evenly.
  void warmUp();

  const Swarm& spawn;
  Swarm swarm;
  Stepper stepper;
  Vec3f gravity;
  std::size_t steps = 0;
};

/// Crossings counted outside the timed region: the same simulation replayed (at least
/// `particle_steps` particle-steps), every step's segment from the position before to the position
/// after tested against the original triangles (Embree, all hits). A segment with any hit counts.
struct Judgement {
  std::uint64_t crossings = 0;
  std::uint64_t segments = 0;
};
/// Starts from `sim` as it is (warmed up: the timed runs start from the same state).
Judgement judgeCase(const MeshScene& scene, Simulation sim, std::uint64_t particle_steps);

} // namespace table1
} // namespace dng
