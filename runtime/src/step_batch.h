// Internal: what stepParticles prepares once per call for the SIMD batch kernels (step_lanes.h), and
// the kernels' table. ISA-neutral: included by step.cpp and by each kernel translation unit.
#pragma once

#include "broadphase.h"
#include "dng/particles.h"
#include "pose.h"
#include "walk.h"

#include <cstddef>
#include <cstdint>

namespace dng {

/// Without a broadphase the batch kernels take calls with at most this many bodies, and test every
/// one for every lane; more go through the scalar loop. With one (dng/body_index.h), any number.
constexpr std::size_t kMaxBatchBodies = 8;

/// Walk samples per body and step: enough for a design-speed step along a surface; swept bodies afford
/// any speed. A walk out of samples stops the particle early (docs/RUNTIME.md), it never crosses.
inline int walkSamples(const Material& material) { return material.swept ? 256 : 24; }
/// Whether the move is walked through the body (its response is not kNone).
inline bool collides(const Material& material) { return material.response != Response::kNone; }

/// The bodies one chunk of lanes meets in one phase of the step (the responses, or the move), in
/// increasing body index: the order the scalar path visits them in, so that ties between bodies
/// resolve the same way. Each lane tests every listed body itself, with the scalar path's own tests,
/// so a list may hold bodies a lane is nowhere near; it holds every body the scalar path would visit
/// for each lane it is for.
struct NearList {
  static constexpr std::size_t kCapacity = 16;
  std::size_t count = 0;
  std::int32_t index[kCapacity];       ///< into the call's bodies
  const StepBody* body[kCapacity];     ///< its numbers: the index's, or in `storage`
  const Material* material[kCapacity]; ///< the body's, as it is now
  /// A move's list: each body's place in the chunk's response list, -1 when it is not there (the
  /// walk then takes a new sample at the start instead of the response's).
  std::int32_t kept[kCapacity];
  StepBody storage[kCapacity];
};
static_assert(kMaxBatchBodies <= NearList::kCapacity, "a call without a broadphase lists every body");

/// The broadphase's grid as the kernels read it: BodyIndex::Impl's arrays and numbers, copied out so
/// that the kernels call none of its functions (broadphase.h says what each one is).
struct IndexGrid {
  const BodyBoxes* boxes = nullptr;
  const std::uint32_t* cell_start = nullptr;
  const std::uint32_t* cell_bodies = nullptr;
  const std::uint32_t* cell_boxes = nullptr;
  const std::uint32_t* everywhere = nullptr;
  std::size_t everywhere_count = 0;
  float origin[3] = {0, 0, 0};
  float inv_cell = 1.0f;
  float last_cell[3] = {0, 0, 0};
  std::uint32_t dims[3] = {0, 0, 0};
  Vec3f scene_lo, scene_hi;
};

/// One stepParticles call. `scalar` steps particle n alone with the reference path; a kernel calls
/// it for every particle its lanes cannot finish (a walk that needs more than one ball, bodies that do
/// not fit a NearList).
struct StepBatch {
  const ParticleSpan* particles = nullptr;
  float dt = 0.0f;
  /// Every body (1..kMaxBatchBodies), for every chunk and both phases; null when `index` is set.
  const NearList* all = nullptr;
  /// Else the broadphase the chunks find their bodies with, the index's numbers of every body, and the
  /// call's bodies (for their materials).
  const IndexGrid* index = nullptr;
  const StepBody* prepared = nullptr;
  const Body* bodies = nullptr;
  /// Whether the kernels may gather `prepared`'s numbers: 32-bit lane offsets reach every body's.
  bool gatherable = false;
  /// The index's kinds of the bodies (BodyIndex::Impl::kinds) when they hold for this call, else null:
  /// bodies of one kind step as one.
  const std::int32_t* kinds = nullptr;
  void (*scalar)(const void* context, std::size_t n) = nullptr;
  /// The scalar path's move alone for particle n, after responses that left it `velocity` and touched
  /// `touch_body` at `touch_distance` (-1 and +infinity: none): what a lane whose walk needs more than
  /// the lanes do hands over, without the responses done again.
  /// `start_bound`, when not null, is the neighbour bound at the start of its walk through body
  /// `bound_body` (walk.h StartBound).
  void (*scalar_move)(const void* context, std::size_t n, Vec3f velocity, std::int32_t touch_body, float touch_distance,
                      const StartBound* start_bound, std::size_t bound_body) = nullptr;
  /// scalar_move for a particle whose walk through body `body`, the only one its move meets, is blocked
  /// at its start (walk.h: the field cannot prove the start outside, walkSegment's kReverse at t = 0):
  /// the same stop, settled without the walk.
  void (*scalar_block)(const void* context, std::size_t n, Vec3f velocity, std::int32_t touch_body,
                       float touch_distance, std::size_t body) = nullptr;
  const void* context = nullptr; ///< for `scalar`, `scalar_move` and `scalar_block`
};

/// The kernels of one instruction set.
struct BatchKernels {
  const char* name;
  void (*sample_nearest)(const View& view, const float* points, std::size_t stride, std::size_t count,
                         Sample* out_samples);
  void (*sample_trilinear)(const View& view, const float* points, std::size_t stride, std::size_t count,
                           Sample* out_samples);
  void (*sample_accurate)(const View& view, const float* points, std::size_t stride, std::size_t count,
                          Sample* out_samples);
  void (*step)(const StepBatch& batch);
  /// walk.cpp's neighbour bound over the points `axes` make: max(-reach, value - gap) over the 26,
  /// where a cell's value is its sample's distance capped at reach (reach where there is no field), far
  /// inside cells left out. Writes the points to out_points and each one's own term, value - gap
  /// (-infinity for far inside cells), to out_terms[0..kPadded).
  float (*neighbour_bound)(const View& view, const NeighbourAxes& axes, float reach, NeighbourPoints* out_points,
                           float* out_terms);
};

/// Whether the kernels may take a view: their 32-bit lane indices reach every byte of one under 8 GiB.
inline bool batchIndexable(const View& view) { return view.sizeBytes() < (std::size_t(1) << 33); }

/// The kernels chosen for this process (dng/instruction_set.h), or null for the scalar path.
const BatchKernels* activeBatchKernels();

} // namespace dng
