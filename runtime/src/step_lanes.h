// Internal: stepParticles' kernels for a lane of particles at once, the cases that only advance.
//
// Most particle-steps, even near a surface, are settled by the walk's balls (walk.cpp): the
// particle's own sample proves a ball around it clear and the ball holds the whole move, or a second
// ball around the end covers the rest. Most others are settled cell by cell, each cell's plane proving
// the way to its wall. Lanes do exactly that, with every operation the scalar step.cpp and walk.cpp do
// in the same order, so a lane's result is bit for bit the scalar one. A particle that needs anything
// more (a bounce off a plane during the move, a slide, a neighbour bound) goes to the scalar path:
// whole, from its original state, or, once the lanes' responses have acted, to its move alone.
// span_lanes.h runs these kernels over a whole span.
#pragma once

#include "body_lanes.h"
#include "dng/responses.h"
#include "near_lanes.h"
#include "neighbour_lanes.h"
#include "sample_lanes.h"
#include "step_batch.h"
#include "strided.h"

#include <cstring>
#include <limits>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

struct LaneParticles {
  V3 position, velocity;
};

/// The walk's sample: the plane (ViewInternals::planeSample). `Body`: StepBody or LaneBodies.
template <class Body> DNG_LANE_INLINE LaneSample sampleBody(const Body& b, V3 local, M active) {
  return b.dense ? nearestLanes<true>(*b.field, local, active) : nearestLanes<false>(*b.field, local, active);
}

/// The responses' sample: the plane, which the walk keeps, and the shading normal the rules read.
template <class Body> DNG_LANE_INLINE LaneSample sampleBody(const Body& b, V3 local, M active, V3* out_shading) {
  return b.dense ? nearestLanes<true, true>(*b.field, local, active, out_shading)
                 : nearestLanes<false, true>(*b.field, local, active, out_shading);
}

/// dng::respond (responses.h) on lanes of relative velocity, where `contact` holds. Returns the lanes
/// where a rule acted.
DNG_LANE_INLINE M applyMaterial(const Material& m, M contact, F d, V3 n, F band, float dt, V3* io_v) {
  const F zero = splat(0.0f), step = splat(dt);
  M acted = andNot(contact, contact); // none
  if (m.response == Response::kImpact) {
    const F vn = dot(*io_v, n);
    const M act = contact & (vn < zero) & ~(d > splat(m.collision_distance) - vn * step);
    *io_v = select(act, *io_v - n * (splat(1.0f + m.restitution) * vn), *io_v);
    acted = acted | act;
  } else if (m.response == Response::kSpring) {
    const F reach = m.spring_distance > 0.0f ? splat(m.spring_distance) : band;
    const M act = contact & (d < reach);
    *io_v = select(act, *io_v + n * (splat(m.spring_stiffness) * (reach - d) * step), *io_v);
    acted = acted | act;
  }
  if (m.drag > 0.0f) {
    const M act = contact & (d < splat(m.contact_distance));
    const V3 normal_part = n * dot(*io_v, n);
    const V3 tangential = *io_v - normal_part;
    *io_v = select(act, normal_part + tangential * splat(1.0f / (1.0f + m.drag * dt)), *io_v);
    acted = acted | act;
  }
  if (m.flow_in != 0.0f || m.flow_out != 0.0f) {
    const V3 v = *io_v;
    const F gamma = dot(n, v);
    const V3 e = cross(cross(v, n), v);
    const F e_length = length(e);
    const M act = contact & (d < splat(m.flow_distance)) & (e_length > splat(1e-20f));
    const F rho = select(gamma < zero, splat(m.flow_in), splat(m.flow_out));
    *io_v = select(act, v + e * (rho * step / e_length), v);
    acted = acted | act;
  }
  return acted;
}

/// What the move needs from a body's response: the start point in the body's frame and the sample
/// there, valid in the lanes the body's box holds (none: valid is all false, the rest never written).
struct KeptSample {
  LaneSample sample;
  V3 local;
  M valid;
};

/// The body a particle's responses touched, and its distance: the nearest body that acted.
struct TouchLanes {
  F distance;
  I body;
};

// The sample a body's response reads, for the lanes `live` its box holds: it depends on the positions
// alone, so a chunk's samples can be taken before the rules of an earlier chunk or body act. The
// shading normal goes to *out_shading.
template <class Body>
DNG_LANE_INLINE void sampleForResponse(const Body& b, M live, V3 p, KeptSample* kept, V3* out_shading) {
  const V3 lo = perLane(b.lo), hi = perLane(b.hi);
  const M in = live & (p.x >= lo.x) & (p.y >= lo.y) & (p.z >= lo.z) & (p.x <= hi.x) & (p.y <= hi.y) & (p.z <= hi.z);
  kept->valid = in;
  if (!any(in)) return;
  kept->local = toLocal(b.start, p);
  kept->sample = sampleBody(b, kept->local, in, out_shading);
}

// step.cpp respondToBody's rules, on the sample `kept` (sampleForResponse) with its shading normal:
// updates the velocities and the touch (`listed`: the body's index when `b` is a StepBody).
template <class Body>
DNG_LANE_INLINE void applyResponse(const Body& b, const Material& material, std::int32_t listed, float dt,
                                   const KeptSample& kept, const V3& shading, LaneParticles* io, TouchLanes* io_touch) {
  if (!any(kept.valid)) return;
  const LaneSample& s = kept.sample;
  const M contact = kept.valid & s.in_band;
  if (!any(contact)) return;
  const V3 p = io->position;
  const F d = s.distance * perLane(b.start.scale);
  const V3 n = rotateToWorld(b.start, shading);
  const V3 surface = perLane(b.linear) + cross(perLane(b.angular), p - perLane(b.start.t));
  V3 relative = io->velocity - surface;
  const M acted = applyMaterial(material, contact, d, n, perLane(b.band_world), dt, &relative);
  io->velocity = select(acted, relative + surface, io->velocity);
  const M nearer = acted & (d < io_touch->distance);
  io_touch->distance = select(nearer, d, io_touch->distance);
  io_touch->body = select(nearer, bodyIndex(b, listed), io_touch->body);
}

// step.cpp respondToBody for the lanes `live`: sample, then the rules. Updates the velocities and the
// touch, and keeps the sample.
template <class Body>
DNG_LANE_INLINE void respondToBody(const Body& b, const Material& material, std::int32_t listed, float dt, M live,
                                   LaneParticles* io, TouchLanes* io_touch, KeptSample* kept) {
  V3 shading = splat(0.0f, 0.0f, 0.0f); // written only where the body's box holds a lane
  sampleForResponse(b, live, io->position, kept, &shading);
  applyResponse(b, material, listed, dt, *kept, shading, io, io_touch);
}

DNG_LANE_INLINE TouchLanes noTouch() { return {splat(std::numeric_limits<float>::infinity()), splatI(-1)}; }

/// The responses' samples of every body of a call without an index (sampleResponses; at most
/// kMaxBatchBodies), per body, and their shading normals: span_lanes.h stepEveryBody keeps two.
struct ResponseSamples {
  KeptSample kept[kMaxBatchBodies];
  V3 shading[kMaxBatchBodies];
};

// The samples every listed body's response reads, for the lanes `live` at `p`. `list` holds at most
// kMaxBatchBodies bodies.
DNG_LANE_INLINE void sampleResponses(const NearList& list, M live, V3 p, ResponseSamples* out) {
  for (std::size_t k = 0; k < list.count; ++k)
    sampleForResponse(*list.body[k], live, p, &out->kept[k], &out->shading[k]);
}

// The responses of the listed bodies, in body order, on their samples (sampleResponses). Fills the
// touched body.
DNG_LANE_INLINE void applyResponses(const StepBatch& batch, const NearList& list, const ResponseSamples& samples,
                                    LaneParticles* io, TouchLanes* out_touch) {
  *out_touch = noTouch();
  for (std::size_t k = 0; k < list.count; ++k)
    applyResponse(*list.body[k], *list.material[k], list.index[k], batch.dt, samples.kept[k], samples.shading[k], io,
                  out_touch);
}

// The responses of the listed bodies, in body order, for the lanes `live`, each body sampled just
// before its rules act. Fills the touched body and keeps each body's sample in kept[k].
DNG_LANE_INLINE void respondLanes(const StepBatch& batch, const NearList& list, M live, LaneParticles* io,
                                  TouchLanes* out_touch, KeptSample* kept) {
  *out_touch = noTouch();
  for (std::size_t k = 0; k < list.count; ++k)
    respondToBody(*list.body[k], *list.material[k], list.index[k], batch.dt, live, io, out_touch, &kept[k]);
}

// step.cpp segmentNearBounds.
template <class Body> DNG_LANE_INLINE M nearBounds(const Body& b, V3 a, V3 e) {
  const V3 lo = perLane(b.lo), hi = perLane(b.hi);
  const F tr = perLane(b.travel);
  return ~((maxOf(a.x, e.x) < lo.x - tr) | (minOf(a.x, e.x) > hi.x + tr) | (maxOf(a.y, e.y) < lo.y - tr) |
           (minOf(a.y, e.y) > hi.y + tr) | (maxOf(a.z, e.z) < lo.z - tr) | (minOf(a.z, e.z) > hi.z + tr));
}

// walk.cpp insideGrid.
DNG_LANE_INLINE M insideGrid(const GridInfo& g, V3 p) {
  M in = allTrue();
  const F c[3] = {p.x, p.y, p.z};
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = component(g.origin, axis);
    in = in & (c[axis] >= splat(lo)) & (c[axis] < splat(lo + float(g.dims[axis]) * g.voxel_size));
  }
  return in;
}

// walk.cpp clipToGrid for segments a + t d, t in [0, 1], with an end outside the grid: the part
// [*t0, *t1] inside it, and the lanes whose segment misses the grid's box, which the scalar walk calls
// clear. A body's box is the box of its turned grid, so many particles in a building's box are beside
// its grid, not in it; near a grid's faces, moves leave it.
DNG_LANE_INLINE M clipToGrid(const GridInfo& g, V3 a, V3 d, F* t0, F* t1) {
  const F av[3] = {a.x, a.y, a.z}, dv[3] = {d.x, d.y, d.z};
  const F zero = splat(0.0f);
  M miss = andNot(allTrue(), allTrue());
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = component(g.origin, axis);
    const F lo_f = splat(lo), hi_f = splat(lo + float(g.dims[axis]) * g.voxel_size);
    const M flat = ~(dv[axis] != zero); // dir == 0: the axis's slab holds the start or nothing
    miss = miss | (flat & ~((av[axis] >= lo_f) & (av[axis] < hi_f)));
    const F ta = (lo_f - av[axis]) / dv[axis], tb = (hi_f - av[axis]) / dv[axis];
    const M swap = ta > tb;
    // std::max(t0, x) is (t0 < x ? x : t0), which is maxOf(x, t0); std::min(t1, x) likewise.
    *t0 = select(flat, *t0, maxOf(select(swap, tb, ta), *t0));
    *t1 = select(flat, *t1, minOf(select(swap, ta, tb), *t1));
  }
  return miss | ~(*t0 <= *t1);
}

DNG_LANE_INLINE LaneSample merge(M m, const LaneSample& a, const LaneSample& b) {
  return {select(m, a.distance, b.distance),
          select(m, a.normal, b.normal),
          (m & a.in_band) | andNot(b.in_band, m),
          (m & a.far_outside) | andNot(b.far_outside, m),
          (m & a.far_inside) | andNot(b.far_inside, m),
          (m & a.no_field) | andNot(b.no_field, m)};
}

// The walk's first sample: the start's, except in the lanes `entered` whose segment enters the grid
// from outside, which sample where it enters (p).
template <class Body> DNG_LANE_INLINE LaneSample firstSample(const Body& sb, V3 p, const LaneSample& start, M entered) {
  return any(entered) ? merge(entered, sampleBody(sb, p, entered), start) : start;
}

// walk.cpp cellExit: where the segment a + t d leaves the cell that holds a + t d.
DNG_LANE_INLINE F cellExit(const GridInfo& g, float inv_h, V3 a, V3 d, F t) {
  const F av[3] = {a.x, a.y, a.z}, dv[3] = {d.x, d.y, d.z};
  const F inv = splat(inv_h), zero = splat(0.0f);
  F exit = splat(2.0f);
  for (int axis = 0; axis < 3; ++axis) {
    const F du = dv[axis] * inv;
    const F u = (av[axis] + dv[axis] * t - splat(component(g.origin, axis))) * inv;
    const F wall = select(du > zero, floor(u) + splat(1.0f), floor(u));
    exit = select(du != zero, minOf(t + (wall - u) / du, exit), exit);
  }
  return exit;
}

/// Which of the walk's cases walkLanes tries: the balls (the first ball and the two-ball test), or the
/// cells (the first ball, then cell by cell) for lanes whose balls could not prove them.
enum class WalkPart { kBalls, kCells };

/// The other plane of a second bound that is a pair of planes (ViewInternals::OtherPlane), per lane:
/// beside a concave crease the smaller of the two bounds the distance, so a walk stops where the first
/// of them reaches the margin. Present in the lanes of `present` only.
struct OtherLanes {
  M present;
  F distance;
  V3 normal;
};

// ViewInternals::secondBound for the lanes of `m` (the rest keep `s`): one lane at a time, the scalar
// function itself, since second bounds are read only where a cell's own plane stops or fails a walk.
// The other plane of the lanes whose bound is a pair goes to *out_other.
DNG_LANE_INLINE LaneSample secondBoundLanes(const View& field, V3 p, const LaneSample& s, M m, OtherLanes* out_other) {
  alignas(kLaneAlign) float px[kWidth], py[kWidth], pz[kWidth], d[kWidth], nx[kWidth], ny[kWidth], nz[kWidth];
  alignas(kLaneAlign) float od[kWidth] = {}, onx[kWidth] = {}, ony[kWidth] = {}, onz[kWidth] = {};
  store(px, p.x), store(py, p.y), store(pz, p.z), store(d, s.distance);
  store(nx, s.normal.x), store(ny, s.normal.y), store(nz, s.normal.z);
  LaneBits in_band = 0, far_outside = 0, far_inside = 0, pairs = 0;
  const LaneBits band_bits = bits(s.in_band);
  for (LaneBits on = bits(m); on != 0; on &= on - 1) {
    const int lane = lowestLane(on);
    const Sample first{d[lane],
                       {nx[lane], ny[lane], nz[lane]},
                       (band_bits >> lane) & 1u ? SampleStatus::kInBand : SampleStatus::kNoField};
    ViewInternals::OtherPlane other;
    const Sample better = ViewInternals::secondBound(field, {px[lane], py[lane], pz[lane]}, first, &other);
    d[lane] = better.distance, nx[lane] = better.normal.x, ny[lane] = better.normal.y, nz[lane] = better.normal.z;
    od[lane] = other.distance, onx[lane] = other.normal.x, ony[lane] = other.normal.y, onz[lane] = other.normal.z;
    pairs |= LaneBits(other.present) << lane;
    in_band |= LaneBits(better.status == SampleStatus::kInBand) << lane;
    far_outside |= LaneBits(better.status == SampleStatus::kFarOutside) << lane;
    far_inside |= LaneBits(better.status == SampleStatus::kFarInside) << lane;
  }
  const M on = m & ~(s.no_field); // secondBound answers in-band samples only; the rest keep theirs
  *out_other = {on & laneMask(pairs), load(od), {load(onx), load(ony), load(onz)}};
  LaneSample out = s;
  out.distance = select(on, load(d), s.distance);
  out.normal = select(on, V3{load(nx), load(ny), load(nz)}, s.normal);
  out.in_band = (on & laneMask(in_band)) | andNot(s.in_band, on);
  out.far_outside = (on & laneMask(far_outside)) | andNot(s.far_outside, on);
  out.far_inside = (on & laneMask(far_inside)) | andNot(s.far_inside, on);
  return out;
}

// What a cell's plane, read at t (walk.cpp planCell), says for the lanes `live`: each lane is in one of
// covers (split into roomy_end and need_end), far, stop, to_wall (split into through and next), or none
// of them (nothing: the plane proves nothing). `gap` and `exit` as planCell's clear and exit.
struct CellLanes {
  M covers, roomy_end, need_end, far, stop, to_wall, through, next;
  F gap, exit;
  M nothing(M live) const { return andNot(andNot(andNot(andNot(live, covers), far), stop), to_wall); }
};

// `other`, when not null, is the other plane of the lanes whose `s` is the lower of a pair (planCell's).
DNG_LANE_INLINE CellLanes planCellLanes(const GridInfo& g, float inv_h, V3 a, V3 delta, F t, F t_end, F len,
                                        const LaneSample& s, const OtherLanes* other, M live, F reach, F margin,
                                        F proof, F roomy) {
  const F zero = splat(0.0f);
  CellLanes c;
  const F q = select(s.far_inside, zero - reach, minOf(reach, s.distance));
  c.gap = q - margin;
  const F rest = (t_end - t) * len;
  c.covers = live & (c.gap >= rest);
  c.roomy_end = c.covers & (c.gap - rest >= roomy);
  c.need_end = andNot(c.covers, c.roomy_end);
  live = andNot(live, c.covers);
  c.far = live & s.far_outside; // a ball that does not reach the end: step on by it
  live = andNot(live, c.far);
  // Inside one cell the field is the cell's plane (or the smaller of a pair).
  const F rate = select(s.in_band, dot(s.normal, delta), zero);
  c.exit = cellExit(g, inv_h, a, delta, t);
  const M approaching = (rate < zero) & (c.gap >= zero);
  F hit = select(approaching, t + c.gap / (zero - rate), splat(std::numeric_limits<float>::infinity()));
  M rising = (rate >= zero) & (q >= proof) & s.in_band;
  if (other != nullptr) { // the pair's other plane stops the walk where it reaches the margin first
    const F other_rate = select(other->present, dot(other->normal, delta), zero);
    const F other_hit = t + (minOf(reach, other->distance) - margin) / (zero - other_rate);
    hit = select((other_rate < zero) & (c.gap >= zero) & (other_hit < hit), other_hit, hit);
    rising = rising & (other_rate >= zero);
  }
  c.stop = live & (hit < c.exit) & (hit < t_end);
  c.to_wall = andNot(live, c.stop) & ((c.gap >= zero) | rising);
  c.through = c.to_wall & (c.exit >= t_end);
  c.next = andNot(c.to_wall, c.through);
  return c;
}

DNG_LANE_INLINE CellLanes merge(M m, const CellLanes& a, const CellLanes& b) {
  const auto pick = [m](M x, M y) { return (m & x) | andNot(y, m); };
  return {pick(a.covers, b.covers), pick(a.roomy_end, b.roomy_end), pick(a.need_end, b.need_end), pick(a.far, b.far),
          pick(a.stop, b.stop),     pick(a.to_wall, b.to_wall),     pick(a.through, b.through),   pick(a.next, b.next),
          select(m, a.gap, b.gap),  select(m, a.exit, b.exit)};
}

// Whether an end sample proves its point outside (walk.cpp provable, but for the neighbours' bound,
// which the scalar walk takes): far outside, beyond the grid, its plane reading at least `proof`, or
// its second plane doing so.
DNG_LANE_INLINE M endProven(const View& field, V3 end, const LaneSample& e, M m, F proof) {
  M proven = m & (e.far_outside | e.no_field | (e.in_band & (e.distance >= proof)));
  const M second = andNot(m & e.in_band, proven);
  if (ViewInternals::hasSecondPlanesFast(field) && any(second)) {
    OtherLanes unused;
    const LaneSample better = secondBoundLanes(field, end, e, second, &unused);
    proven = proven | (second & (better.far_outside | (better.distance >= proof)));
  }
  return proven;
}

// The lanes whose walk (walk.cpp walkSegment) asks the neighbours at its start: there its own planes
// prove nothing, read below the proof level and are not far inside. `local`: the starts in the body's
// frame, as the walk samples them.
struct StartLanes {
  M lanes;
  V3 local;
};

// The neighbour bound at such a start, and whether it blocks the walk there (walkSegment's kReverse at
// t = 0): when it neither proves the start outside nor leaves it room. The bound is walk.cpp's, taken
// by the same kernel, so a walk handed over with it reads the same numbers.
template <class Body> DNG_LANE_INLINE bool startBound(const Body& sb, Vec3f local, StartBound* out) {
  const View& field = *sb.field;
  out->bound = neighbourBound(field, neighbourAxes(field.grid(), local), sb.reach, &out->points, out->terms);
  return out->bound < sb.proof_level && !(out->bound - sb.margin > 0.0f);
}

// walkSegment (walk.cpp) through body `sb` for the lanes `near` it, from `a` (the start in the body's
// start-of-step frame) to `end` (world), as far as its cases that only advance go: balls, the two-ball
// test, cell planes that stay clear to the cell's wall, the end point's proof (`part` says which).
// Returns the lanes it proves clear; every other near lane needs another part or the scalar walk (a
// stop, a slide, a neighbour bound, a clip at the grid's edge, a walk out of samples). Any subset of
// walkSegment's cases proves only what walkSegment proves, so the parts give the scalar bits. With
// `out_start` (kCells only), also the lanes that ask the neighbours at their start (StartLanes).
template <class Body>
DNG_LANE_INLINE M walkLanes(const Body& sb, int max_samples, V3 a, V3 end, const LaneSample* kept, M kept_valid, M near,
                            WalkPart part, StartLanes* out_start = nullptr) {
  const View& field = *sb.field;
  const GridInfo& g = field.grid();
  const V3 delta = toLocal(sb.end, end) - a;
  const F len = length(delta);
  // The start sample: the response's where it kept one (the same numbers), else a new one.
  const M fresh = andNot(near, kept_valid);
  LaneSample s = kept != nullptr ? *kept : LaneSample{};
  if (any(fresh)) s = merge(kept_valid, s, sampleBody(sb, a, fresh));
  const F margin = splat(sb.margin), roomy = splat(sb.roomy), reach = splat(sb.reach), proof = splat(sb.proof_level);
  const F zero = splat(0.0f), one = splat(1.0f);
  // The common case first: far from the surface, the first ball covers the whole step.
  M clear = ~near | ~(len > zero) | ((s.far_outside | s.in_band) & (minOf(reach, s.distance) - margin - len >= roomy));
  // Segments that miss the grid's box are clear; those that leave it are walked over the part
  // [t, t_end] inside it.
  F t = zero, t_end = one;
  const M inside = insideGrid(g, a) & insideGrid(g, a + delta);
  const M outside = andNot(andNot(near, inside), clear);
  if (any(outside)) {
    F t0 = zero, t1 = one;
    clear = clear | (outside & clipToGrid(g, a, delta, &t0, &t1));
    t = select(outside, t0, t), t_end = select(outside, t1, t_end);
  }
  M active = andNot(near, clear);
  // Two balls, the start's and the end's (walk.cpp twoBallsClear), for the whole segment only.
  const M usable = active & (s.far_outside | s.in_band) & ~(t != zero) & ~(t_end != one);
  if (part != WalkPart::kCells && any(usable)) {
    const LaneSample e = sampleBody(sb, a + delta, usable);
    const M end_proven = e.far_outside | e.no_field | (e.in_band & (e.distance >= proof));
    const F gap_start = minOf(reach, s.distance) - margin;
    const F gap_end = select(e.in_band, minOf(reach, e.distance), reach) - margin;
    const M two = usable & end_proven & ((gap_start >= len) | (gap_start + gap_end >= len));
    clear = clear | two;
    active = andNot(active, two);
  }
  if (part == WalkPart::kBalls) return clear;
  const F nudge = splat(2e-3f * g.voxel_size) / len;
  const float inv_h = ViewInternals::invVoxelSize(field);
  const bool second_planes = ViewInternals::hasSecondPlanesFast(field);
  // Each lane's end (a + delta t_end) stays where it is while the lanes step from cell to cell, so its
  // sample is taken once, for every lane still walking, the first time a lane needs it: a register's
  // lanes need it in different cells, and each cell's sample took a register's gathers and decodes.
  // Lanes only ever leave `active`, so every lane that needs the end later was sampled then.
  LaneSample end_sample{};
  bool end_taken = false;
  for (int n = 0; n < max_samples && any(active); ++n) {
    const M arrived = active & (t >= t_end);
    clear = clear | arrived;
    active = andNot(active, arrived);
    const V3 p = a + delta * t;
    const LaneSample here = n == 0 ? firstSample(sb, p, s, active & (t != zero)) : sampleBody(sb, p, active);
    const M no_field = active & here.no_field; // rounding at a face of the grid: step on
    t = select(no_field, t + nudge, t);
    const M live = andNot(active, no_field);
    CellLanes c = planCellLanes(g, inv_h, a, delta, t, t_end, len, here, nullptr, live, reach, margin, proof, roomy);
    // Where the cell's plane stops the walk or proves nothing, its second bound may read higher.
    const M retry = (c.stop | c.nothing(live)) & here.in_band;
    LaneSample cell = here; // the sample the cell's plan rests on
    if (second_planes && any(retry)) {
      OtherLanes other;
      const LaneSample better = secondBoundLanes(field, p, here, retry, &other);
      const M upgraded = retry & (better.distance > here.distance);
      if (any(upgraded)) {
        const CellLanes second =
            planCellLanes(g, inv_h, a, delta, t, t_end, len, better, &other, upgraded, reach, margin, proof, roomy);
        c = merge(upgraded, second, c);
        cell = merge(upgraded, better, here);
      }
    }
    // At the start, where the planes prove nothing and read below the proof level, walkSegment asks the
    // neighbours, and stops there when they cannot prove the start either (but in far inside cells).
    if (out_start != nullptr && n == 0) {
      out_start->lanes =
          andNot(c.nothing(live) & ~(t != zero), cell.far_inside | (minOf(reach, cell.distance) >= proof));
      out_start->local = p;
    }
    // One ball covers the rest: clear when it leaves room, or when the end proves itself outside.
    clear = clear | c.roomy_end;
    if (any(c.need_end)) {
      const V3 last = a + delta * t_end;
      if (!end_taken) {
        end_sample = sampleBody(sb, last, active);
        end_taken = true;
      }
      clear = clear | endProven(field, last, end_sample, c.need_end, proof);
    }
    active = andNot(active, c.covers);
    t = select(c.far, t + c.gap / len, t);
    clear = clear | c.through;
    t = select(c.next, maxOf(t + c.gap / len, c.exit + nudge), t);
    // Stops and neighbour bounds go to the scalar walk.
    active = andNot(active, andNot(andNot(live, c.covers), c.far | c.next));
  }
  return clear | (active & (t >= t_end));
}

// The move's walk through body `b` for the lanes `done` that its move box meets; `kept`: the body's
// response sample, or null. Returns the lanes of `done` that stay proven clear.
template <class Body>
DNG_LANE_INLINE M walkThroughBody(const Body& b, const Material& material, M done, const LaneParticles& p, V3 end,
                                  const KeptSample* kept, WalkPart part, StartLanes* out_start = nullptr) {
  if (!collides(material)) return done;
  const M near = done & nearBounds(b, p.position, end);
  if (!any(near)) return done;
  // The response kept the start's local position and sample where the body's box held the particle.
  const bool has_kept = kept != nullptr && any(kept->valid);
  const M kept_valid = has_kept ? kept->valid : andNot(done, done);
  const V3 a = has_kept ? kept->local : toLocal(b.start, p.position);
  return done & walkLanes(b, walkSamples(material), a, end, has_kept ? &kept->sample : nullptr, kept_valid, near, part,
                          out_start);
}

// The move's walks through the listed bodies, for the lanes `live`: the lanes every one proves clear
// by the walk's `part`. `kept`: the responses' samples, per body of the response list (list.kept
// indexes it), or null (the walks sample their starts). With
// `out_start` (kCells, a list of one body), also the lanes that ask the neighbours at their start.
DNG_LANE_INLINE M moveLanes(const NearList& list, M live, const LaneParticles& p, V3 end, const KeptSample* kept,
                            WalkPart part, StartLanes* out_start = nullptr) {
  M done = live;
  for (std::size_t k = 0; k < list.count && any(done); ++k) {
    const std::int32_t r = list.kept[k];
    done = walkThroughBody(*list.body[k], *list.material[k], done, p, end,
                           kept != nullptr && r >= 0 ? &kept[r] : nullptr, part, out_start);
  }
  return done;
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
