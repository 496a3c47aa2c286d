// Internal: a chunk's step slot by slot, for scenes of many bodies that share a field (a city's
// buildings). Through an index each lane lists its own bodies (near_lanes.h listEachLane), and the
// chunk's slots take them in turn: each slot the next body of every lane whose next body is of the
// slot's kind (one field, one material). Where a slot's lanes all hold one body the kernels take that
// body; where they hold different bodies of its kind, the kernels take them all at once, each lane its
// own body's numbers (body_lanes.h LaneBodies). Particles in random order, each near a different
// building on a common ground, then cost one pass per slot (a building's, the ground's) instead of one
// pass per building of the chunk.
//
// Each lane still visits its own bodies in increasing index with the scalar path's tests and operations,
// so a lane gives the scalar path's bits. A chunk whose bodies need more than ChunkSlots::kMax slots goes
// the union way (span_lanes.h).
#pragma once

#include "step_lanes.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

/// A chunk's slots: per slot, the lanes that have a body there, and the body every such lane holds
/// (`one`), or their bodies gathered (`each`), and their material.
struct ChunkSlots {
  static constexpr int kMax = 8; ///< a chunk whose lanes' bodies need more goes the union way
  int count = 0;
  LaneBits on[kMax];
  const StepBody* one[kMax]; ///< null: the slot's lanes hold different bodies, in each[k]
  std::int32_t one_index[kMax];
  const Material* material[kMax];
  LaneBodies each[kMax];
};

// The lanes of `m` whose bodies (`body`) step as body `first` (`shared`, `material`) does but for their
// own numbers: the same field and material. By the index's kinds where they hold for the call (a
// kind's bodies have both), one gather; lanes of other kinds (a kind is not always unique) compared
// one at a time.
DNG_LANE_INLINE M sameKind(const StepBatch& batch, I body, std::int32_t first, const StepBody& shared,
                           const Material& material, M m) {
  LaneBits same = 0, rest = bits(m);
  if (batch.kinds != nullptr) {
    const I kind = gather(reinterpret_cast<const std::uint32_t*>(batch.kinds), body, m);
    same = bits(m & (kind == splatI(batch.kinds[first])));
    rest &= ~same;
  }
  if (rest == 0) return laneMask(same);
  alignas(kLaneAlign) std::int32_t b[kWidth];
  std::memcpy(b, &body, sizeof b);
  for (; rest != 0; rest &= rest - 1) {
    const int lane = lowestLane(rest);
    if (batch.prepared[b[lane]].field == shared.field && sameMaterial(batch.bodies[b[lane]].material(), material))
      same |= laneBit(lane);
  }
  return laneMask(same);
}

// The next slot: the lowest of the next bodies of the lanes `left`, and the next body of every other
// lane of `left` whose next body is of the same kind, each lane's taken from its list (its position
// `next` advanced, and the lane out of *left once its list, `count` long, is done). Taking the lowest
// first lets a body that every lane lists, such as a ground, wait until each lane reaches it, so it
// takes one slot.
// One body for every lane is kept as it is; different bodies are gathered. In registers: lane by lane,
// the choice took about 7% of a city's step (bench/many_bodies_bench, perf).
DNG_LANE_INLINE void nextSlot(const StepBatch& batch, const LaneLists& lists, I count, I* next, LaneBits* left,
                              ChunkSlots* out) {
  const int k = out->count++;
  const M in = laneMask(*left);
  // lists.body[next][lane] for each lane of `left`.
  const I body =
      gather(reinterpret_cast<const std::uint32_t*>(&lists.body[0][0]), *next * splatI(kWidth) + laneNumbers(), in);
  const std::int32_t first = lowestValue(select(in, body, splatI(std::numeric_limits<std::int32_t>::max())));
  const StepBody& shared = batch.prepared[first];
  const Material& material = batch.bodies[first].material();
  const M is_first = in & (body == splatI(first));
  const M others = sameKind(batch, body, first, shared, material, andNot(in, is_first));
  const M on = is_first | others;
  *next = *next + select(on, splatI(1), splatI(0));
  *left &= ~bits(on & (*next == count));
  out->on[k] = bits(on);
  out->material[k] = &material;
  out->one[k] = any(others) ? nullptr : &shared;
  out->one_index[k] = first;
  if (!any(others)) return;
  // Lanes without a body here read the first's numbers (and stay off).
  const I index = select(on, body, splatI(first));
  gatherBodies(batch.prepared, index, shared, shared.still && allStill(batch.prepared, index, others), &out->each[k]);
}

/// The chunk's slots for the live lanes' lists. Each lane's bodies keep their order (a lane's k-th body
/// goes in a later slot than its (k-1)-th); a slot takes the lanes whose next bodies are of one kind,
/// so that a ground under every lane and the buildings of some share slots as far as they can. False
/// when the call's bodies cannot be gathered or the lists need more than ChunkSlots::kMax slots: the
/// chunk goes the union way then.
DNG_LANE_INLINE bool makeSlots(const StepBatch& batch, const LaneLists& lists, M live, ChunkSlots* out) {
  out->count = 0;
  I next = splatI(0);
  // The lanes with a body, from their counts as a register: a branch per lane here mispredicted with
  // particles in random order (bench/many_bodies_bench).
  I count;
  std::memcpy(&count, lists.count, sizeof count);
  LaneBits left = bits(andNot(live, count == splatI(0)));
  if (left != 0 && !batch.gatherable) return false;
  while (left != 0) {
    if (out->count == ChunkSlots::kMax) return false;
    nextSlot(batch, lists, count, &next, &left, out);
  }
  return true;
}

// Whether every body lane `lane` meets with its move box in `q` is one its list holds (the walks then
// visit what the scalar path visits: the lane's own tests pass the rest by).
DNG_LANE_INLINE bool keepsItsBodies(const IndexGrid& g, const LaneQuery& q, const LaneCells& c0, const LaneCells& c1,
                                    int lane, bool in_scene, const LaneLists& old) {
  LaneLists now{};
  if (!listLane(g, q, c0, c1, lane, in_scene, &now)) return false;
  for (int k = 0; k < now.count[lane]; ++k) {
    bool found = false;
    for (int j = 0; j < old.count[lane]; ++j)
      found = found || old.body[j][lane] == now.body[k][lane];
    if (!found) return false;
  }
  return true;
}

/// The lanes of `moved` (whose move boxes the responses changed, now [lo, hi]) that keep their lists.
DNG_LANE_INLINE M relisted(const IndexGrid& g, V3 lo, V3 hi, M moved, const LaneLists& lists) {
  moved = andNot(moved, notNumbers(lo, hi));
  const LaneBits scene = bits(inScene(g, lo, hi));
  const LaneQuery q = storeQuery(lo, hi, lo); // positions unused: only the moves' bodies are compared
  LaneCells c0, c1;
  storeCells(cellRange(g, lo, hi), &c0, &c1);
  LaneBits kept = 0;
  for (LaneBits on = bits(moved); on != 0; on &= on - 1) {
    const int lane = lowestLane(on);
    if (keepsItsBodies(g, q, c0, c1, lane, (scene >> lane) & 1u, lists)) kept |= laneBit(lane);
  }
  return moved & laneMask(kept);
}

/// One chunk's responses and the balls of its moves, slot by slot, for the lanes *io_live (their move
/// boxes [lo, hi], listed in `lists`). Lanes whose move boxes the responses changed and that now meet a
/// body their lists lack leave *io_live. Returns the lanes proven clear; *out_end and *out_touch get
/// every lane's end and touched body (and its distance).
DNG_LANE_INLINE M stepSlots(const StepBatch& batch, const ChunkSlots& slots, const LaneLists& lists, V3 lo, V3 hi,
                            LaneParticles* io, M* io_live, V3* out_end, TouchLanes* out_touch) {
  TouchLanes touch = noTouch();
  KeptSample kept[ChunkSlots::kMax];
  for (int k = 0; k < slots.count; ++k) {
    const M on = *io_live & laneMask(slots.on[k]);
    if (slots.one[k] != nullptr)
      respondToBody(*slots.one[k], *slots.material[k], slots.one_index[k], batch.dt, on, io, &touch, &kept[k]);
    else
      respondToBody(slots.each[k], *slots.material[k], 0, batch.dt, on, io, &touch, &kept[k]);
  }
  *out_touch = touch;
  const V3 end = io->position + io->velocity * splat(batch.dt);
  *out_end = end;
  V3 now_lo, now_hi;
  moveBox(io->position, end, &now_lo, &now_hi);
  const M moved = *io_live & boxChanged(now_lo, now_hi, lo, hi);
  if (any(moved)) *io_live = andNot(*io_live, moved) | relisted(*batch.index, now_lo, now_hi, moved, lists);
  M done = *io_live;
  for (int k = 0; k < slots.count && any(done); ++k) {
    const M on = done & laneMask(slots.on[k]);
    if (!any(on)) continue;
    const M walked = slots.one[k] != nullptr
                         ? walkThroughBody(*slots.one[k], *slots.material[k], on, *io, end, &kept[k], WalkPart::kBalls)
                         : walkThroughBody(slots.each[k], *slots.material[k], on, *io, end, &kept[k], WalkPart::kBalls);
    done = andNot(done, on) | walked;
  }
  return done;
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
