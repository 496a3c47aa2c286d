// Internal: what stepParticles prepares once per call for the SIMD batch kernels (step_lanes.h), and
// the kernels' table. ISA-neutral: included by step.cpp and by each kernel translation unit.
#pragma once

#include "dng/particles.h"
#include "pose.h"

#include <cstddef>

namespace dng {

/// The batch kernels take calls with at most this many bodies; more go through the scalar loop.
constexpr std::size_t kMaxBatchBodies = 8;

/// One body as the step sees it: both poses and the walk's constants, computed once per call with
/// the same expressions the scalar path uses, so both paths compare the same numbers.
struct StepBody {
  const Body* body = nullptr;
  bool dense = false;    ///< the field's encoding
  bool collides = false; ///< material response is not kNone: the move is walked through it
  Pose start, end;       ///< the body's pose at the start and at the end of the step
  float travel = 0.0f;   ///< how far any point of its box moves in dt
  float band_world = 0.0f;
  // The walk's constants, local units (walk.h).
  float margin = 0.0f, reach = 0.0f, roomy = 0.0f, proof_level = 0.0f;
  int max_samples = 0;
};

/// One stepParticles call. `scalar` steps particle n alone with the reference path; a kernel calls
/// it for every particle its lanes cannot finish (a walk that needs more than one ball).
struct StepBatch {
  const ParticleSpan* particles = nullptr;
  float dt = 0.0f;
  const StepBody* bodies = nullptr;
  std::size_t body_count = 0; ///< 1..kMaxBatchBodies
  void (*scalar)(const void* context, std::size_t n) = nullptr;
  const void* context = nullptr;
};

/// The kernels of one instruction set.
struct BatchKernels {
  const char* name;
  void (*sample_nearest)(const View& view, const float* points, std::size_t stride, std::size_t count,
                         Sample* out_samples);
  void (*step)(const StepBatch& batch);
};

/// Whether the kernels may take a view: their 32-bit lane indices reach every byte of one under 8 GiB.
inline bool batchIndexable(const View& view) { return view.sizeBytes() < (std::size_t(1) << 33); }

/// The kernels chosen for this process (dng/instruction_set.h), or null for the scalar path.
const BatchKernels* activeBatchKernels();

} // namespace dng
