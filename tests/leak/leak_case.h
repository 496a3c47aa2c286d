// One leak case: particles thrown at a baked subject under one motion and one material, stepped for a
// number of steps, every step judged against the original triangles in the body's frame.
//
// Moving bodies: before step k the body is placed at pose(t_k) with its velocity; with constant
// velocities its pose after the step is exactly pose(t_k + dt). A step's path is judged in the mesh's
// own frame, from pose(t_k)^-1(p_k) to pose(t_k+1)^-1(p_k+1): what the particle did relative to the surface.
#pragma once

#include "leak_subject.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace dng {
namespace leak {

enum class Motion {
  kStatic,
  kTranslating, ///< at half the design speed
  kSpinning,    ///< about a tilted axis through the mesh centre; its farthest vertex at half the design speed
  kScaled,      ///< static, uniformly scaled by 2.5 (the design speed scales with it)
};
enum class Responses {
  kImpact,         ///< beta 0.5, L = 0.1 voxel
  kImpactDragFlow, ///< the same plus drag 2/s within 1 voxel and surface flow 3 design speeds/s within 2
  kSpring,         ///< stiff enough to stop a design-speed particle within the band
  kNone,           ///< no response at all: the negative control, every particle that meets the body leaks
};
enum class Start {
  kAround,  ///< outside (any side of a sheet) within reach of the surface, random velocities
  kResting, ///< at rest just above upward-facing surface, under gravity
};
enum class Stepper {
  kDngrid,    ///< dng::stepParticles
  kRayCaster, ///< the control: each step's segment cast at the triangles, stopped and reflected at the hit
};

struct CaseSpec {
  std::string name;
  Motion motion = Motion::kStatic;
  Responses responses = Responses::kImpact;
  bool swept = false;
  float speed_factor = 1.0f; ///< largest speed relative to the surface, in design speeds
  Start start = Start::kAround;
  Stepper stepper = Stepper::kDngrid;
  std::size_t particles = 20000;
  int steps = 120;
  std::uint32_t seed = 1;
};

/// What the judge saw. Depths in voxels of the subject's grid.
struct CaseResult {
  std::uint64_t particle_steps = 0;
  std::uint64_t contacts = 0;       ///< particle-steps in which the body acted (the caster: a hit)
  std::uint64_t fast_steps = 0;     ///< steps begun near the body faster than the case's limit
  std::uint64_t crossing_steps = 0; ///< paths that meet the surface, of any depth
  std::uint64_t entered = 0, left = 0, through = 0, within = 0;
  std::uint64_t visible_leaks = 0;   ///< PathJudge's definition
  std::uint64_t thin_passes = 0;     ///< closed: through opposite faces; open: every crossing
  float deepest = 0.0f;              ///< the deepest point of any crossing path
  float median_depth = 0.0f;         ///< median over crossing paths of their deepest point
  std::size_t inside_at_end = 0;     ///< closed: particles ending deeper than kVisibleEndDepth
  std::size_t other_side_at_end = 0; ///< open: particles on the other side of the sheet from their start
  double seconds = 0.0;
};

/// Adds `from`'s counts to *to and keeps the deeper `deepest`; the median and the seconds stay as they are.
void addCounts(const CaseResult& from, CaseResult* to);

/// Runs one case. Deterministic for a given spec (the caster and the judge are order-independent).
CaseResult runCase(const Subject& subject, const CaseSpec& spec);

} // namespace leak
} // namespace dng
