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

// The `count` consecutive StepBody floats from `offset` bytes, of the bodies at `body`
// (prepared[body[lane]]), two at a time (lanes.h gatherPair).
template <int count>
DNG_LANE_INLINE void gatherBodyFloats(const StepBody* prepared, I body, std::size_t offset, F* out) {
  constexpr auto stride = std::int32_t(sizeof(StepBody) / sizeof(float));
  static_assert(sizeof(StepBody) % sizeof(float) == 0, "bodies are gathered a float at a time");
  const float* base = reinterpret_cast<const float*>(reinterpret_cast<const char*>(prepared) + offset);
  const I at = body * splatI(stride);
  for (int n = 0; n + 1 < count; n += 2)
    gatherPair(base, at + splatI(n), allTrue(), &out[n], &out[n + 1]);
  if (count % 2 != 0) out[count - 1] = gather(base, at + splatI(count - 1), allTrue());
}

// The floats of a Pose, in the order they lie in it, and of a StepBody's lo and hi, and of its linear
// and angular velocities: gathered as runs.
static_assert(sizeof(Pose) == 14 * sizeof(float) && offsetof(Pose, t) == 9 * sizeof(float) &&
                  offsetof(Pose, scale) == 12 * sizeof(float) && offsetof(Pose, inv_scale) == 13 * sizeof(float),
              "a Pose is 14 floats in a row");
static_assert(offsetof(StepBody, hi) == offsetof(StepBody, lo) + sizeof(Vec3f) &&
                  offsetof(StepBody, angular) == offsetof(StepBody, linear) + sizeof(Vec3f) &&
                  sizeof(Vec3f) == 3 * sizeof(float),
              "lo and hi, and linear and angular, are 6 floats in a row");
static_assert(offsetof(StepBody, band_world) == offsetof(StepBody, travel) + sizeof(float),
              "travel and band_world are neighbours");

DNG_LANE_INLINE LanePose gatherPose(const StepBody* prepared, I body, std::size_t offset) {
  F f[14];
  gatherBodyFloats<14>(prepared, body, offset, f);
  LanePose p;
  for (int n = 0; n < 9; ++n)
    p.r[n] = f[n];
  p.t = {f[9], f[10], f[11]};
  p.scale = f[12], p.inv_scale = f[13];
  return p;
}

// Two V3s lying one after the other from `offset`.
DNG_LANE_INLINE void gatherBodyVecs(const StepBody* prepared, I body, std::size_t offset, V3* first, V3* second) {
  F f[6];
  gatherBodyFloats<6>(prepared, body, offset, f);
  *first = {f[0], f[1], f[2]}, *second = {f[3], f[4], f[5]};
}

/// Whether the bodies at `body` (indices into `prepared`) are all still (StepBody::still) in the lanes of
/// `m`: the flag's byte taken from one gather of the 32-bit word that holds it.
DNG_LANE_INLINE bool allStill(const StepBody* prepared, I body, M m) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the flag's byte is found by its address");
  static_assert(sizeof(bool) == 1 && sizeof(StepBody) % sizeof(std::uint32_t) == 0, "whole words per body");
  constexpr std::size_t word = offsetof(StepBody, still) / sizeof(std::uint32_t) * sizeof(std::uint32_t);
  constexpr int shift = int(offsetof(StepBody, still) - word) * 8;
  const auto* base = reinterpret_cast<const std::uint32_t*>(reinterpret_cast<const char*>(prepared) + word);
  const I flag =
      shiftRight(gather(base, body * splatI(std::int32_t(sizeof(StepBody) / sizeof(std::uint32_t))), m), shift) &
      splatI(0xFF);
  return !any(m & (flag == splatI(0)));
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
  gatherBodyVecs(prepared, body, offsetof(StepBody, lo), &b.lo, &b.hi);
  F travel_band[2];
  gatherBodyFloats<2>(prepared, body, offsetof(StepBody, travel), travel_band);
  b.travel = travel_band[0], b.band_world = travel_band[1];
  b.index = body;
  if (still) {
    b.end = b.start;
    b.linear = b.angular = splat(0.0f, 0.0f, 0.0f);
  } else {
    b.end = gatherPose(prepared, body, offsetof(StepBody, end));
    gatherBodyVecs(prepared, body, offsetof(StepBody, linear), &b.linear, &b.angular);
  }
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
