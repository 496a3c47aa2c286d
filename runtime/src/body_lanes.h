// Internal: a body's numbers as the lanes read them. The kernels (step_lanes.h) take either kind:
//   - a StepBody: one body for every lane, its numbers splatted where they are used;
//   - LaneBodies: each lane its own body, all of one field and one material, its numbers gathered
//     lane by lane. A chunk whose particles are near different buildings of a city (which share one
//     field) then samples them all in one pass instead of one pass per building (slot_lanes.h).
// perLane() reads a number of either kind as lanes, so one kernel serves both; a splatted number and
// the same number gathered are the same bits, so a lane gives the same result either way.
#pragma once

#include "lanes.h"
#include "step_batch.h"

#include <cstddef>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

/// Pose (pose.h) with a pose per lane.
struct LanePose {
  F r[9];
  V3 t;
  F scale, inv_scale;
};

/// One body per lane, all of one field and one material. Lanes without a body of their own hold
/// another lane's numbers (the kernels' masks leave them out).
struct LaneBodies {
  // The field's, shared by every lane (prepareStep derives them from the field alone).
  const View* field = nullptr;
  bool dense = false;
  float margin = 0.0f, reach = 0.0f, roomy = 0.0f, proof_level = 0.0f;
  // Each lane's body's.
  LanePose start, end;
  V3 lo, hi, linear, angular;
  F travel, band_world;
  I index; ///< into the call's bodies
};

DNG_LANE_INLINE F perLane(float x) { return splat(x); }
DNG_LANE_INLINE F perLane(F x) { return x; }
DNG_LANE_INLINE V3 perLane(Vec3f v) { return splat(v.x, v.y, v.z); }
DNG_LANE_INLINE V3 perLane(V3 v) { return v; }

/// A pose's world -> local map (Pose::toLocal and Body::toLocal are the same expression).
template <class P> DNG_LANE_INLINE V3 toLocal(const P& pose, V3 world) {
  const V3 d = world - perLane(pose.t);
  const auto& r = pose.r;
  const F s = perLane(pose.inv_scale);
  return V3{perLane(r[0]) * d.x + perLane(r[3]) * d.y + perLane(r[6]) * d.z,
            perLane(r[1]) * d.x + perLane(r[4]) * d.y + perLane(r[7]) * d.z,
            perLane(r[2]) * d.x + perLane(r[5]) * d.y + perLane(r[8]) * d.z} *
         s;
}

template <class P> DNG_LANE_INLINE V3 rotateToWorld(const P& pose, V3 v) {
  const auto& r = pose.r;
  return {perLane(r[0]) * v.x + perLane(r[1]) * v.y + perLane(r[2]) * v.z,
          perLane(r[3]) * v.x + perLane(r[4]) * v.y + perLane(r[5]) * v.z,
          perLane(r[6]) * v.x + perLane(r[7]) * v.y + perLane(r[8]) * v.z};
}

/// The body index of each lane: a StepBody's is the list's, the same in every lane.
DNG_LANE_INLINE I bodyIndex(const StepBody&, std::int32_t listed) { return splatI(listed); }
DNG_LANE_INLINE I bodyIndex(const LaneBodies& b, std::int32_t) { return b.index; }

// The StepBody floats at `offset` bytes, of the bodies at `body` (prepared[body[lane]]).
DNG_LANE_INLINE F gatherBodyFloat(const StepBody* prepared, I body, std::size_t offset) {
  constexpr auto stride = std::int32_t(sizeof(StepBody) / sizeof(float));
  static_assert(sizeof(StepBody) % sizeof(float) == 0, "bodies are gathered a float at a time");
  const float* base = reinterpret_cast<const float*>(reinterpret_cast<const char*>(prepared) + offset);
  return gather(base, body * splatI(stride), allTrue());
}

DNG_LANE_INLINE V3 gatherBodyVec(const StepBody* prepared, I body, std::size_t offset) {
  return {gatherBodyFloat(prepared, body, offset), gatherBodyFloat(prepared, body, offset + sizeof(float)),
          gatherBodyFloat(prepared, body, offset + 2 * sizeof(float))};
}

DNG_LANE_INLINE LanePose gatherPose(const StepBody* prepared, I body, std::size_t offset) {
  LanePose p;
  for (int n = 0; n < 9; ++n)
    p.r[n] = gatherBodyFloat(prepared, body, offset + offsetof(Pose, r) + std::size_t(n) * sizeof(float));
  p.t = gatherBodyVec(prepared, body, offset + offsetof(Pose, t));
  p.scale = gatherBodyFloat(prepared, body, offset + offsetof(Pose, scale));
  p.inv_scale = gatherBodyFloat(prepared, body, offset + offsetof(Pose, inv_scale));
  return p;
}

/// The bodies `body` (one per lane, indices into `prepared`), which share `shared`'s field, into *out.
/// Bodies all `still` (StepBody::still) skip gathering what they share: the end pose is the start pose,
/// and the velocities are +0, the same bits gathered or splatted.
DNG_LANE_INLINE void gatherBodies(const StepBody* prepared, I body, const StepBody& shared, bool still,
                                  LaneBodies* out) {
  LaneBodies& b = *out;
  b.field = shared.field;
  b.dense = shared.dense;
  b.margin = shared.margin, b.reach = shared.reach, b.roomy = shared.roomy, b.proof_level = shared.proof_level;
  b.start = gatherPose(prepared, body, offsetof(StepBody, start));
  b.lo = gatherBodyVec(prepared, body, offsetof(StepBody, lo));
  b.hi = gatherBodyVec(prepared, body, offsetof(StepBody, hi));
  b.travel = gatherBodyFloat(prepared, body, offsetof(StepBody, travel));
  b.band_world = gatherBodyFloat(prepared, body, offsetof(StepBody, band_world));
  b.index = body;
  if (still) {
    b.end = b.start;
    b.linear = b.angular = splat(0.0f, 0.0f, 0.0f);
  } else {
    b.end = gatherPose(prepared, body, offsetof(StepBody, end));
    b.linear = gatherBodyVec(prepared, body, offsetof(StepBody, linear));
    b.angular = gatherBodyVec(prepared, body, offsetof(StepBody, angular));
  }
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
