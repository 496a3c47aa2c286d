// Internal: stepParticles over a whole span in lanes: loading and storing chunks of particles
// (packed or strided), finding each chunk's bodies, and the order the work is done in. The per-chunk
// kernels are step_lanes.h's.
//
// Each batch translation unit includes this one.
#pragma once

#include "slot_lanes.h"

#include <algorithm>
#include <cstring>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

// Strided particles (an array of structs) are gathered and scattered where the set has both as single
// instructions (AVX-512): written lane by lane to an array and read back as registers, they stall on
// store forwarding (bench/swarm_hash --structs, fandisk, AVX-512, medians of 5 in turn: 21.5 -> 20.2
// ns per particle-step; arrays 17.5-18). With AVX2's gathers and no scatter, no faster (30.3 -> 30.8).
// Lane n's offset in floats from a register's first particle, when a 32-bit index holds every lane's.
#ifdef DNG_LANES_SCATTER
DNG_LANE_INLINE bool gatherOffsets(std::size_t stride, I* out) {
  const std::size_t floats = stride / sizeof(float);
  if (floats > std::size_t(INT32_MAX) / std::size_t(kWidth)) return false;
  *out = laneNumbers() * splatI(std::int32_t(floats));
  return true;
}
#endif

DNG_LANE_INLINE V3 loadLanes(float* x, float* y, float* z, std::size_t stride, std::size_t n) {
  if (stride == sizeof(float)) return {load(x + n), load(y + n), load(z + n)};
#ifdef DNG_LANES_SCATTER
  I at;
  if (gatherOffsets(stride, &at))
    return {gather(&strided(x, stride, n), at, allTrue()), gather(&strided(y, stride, n), at, allTrue()),
            gather(&strided(z, stride, n), at, allTrue())};
#endif
  Lanes3 l;
  for (int lane = 0; lane < kWidth; ++lane) {
    const std::size_t i = n + std::size_t(lane);
    l.x[lane] = strided(x, stride, i), l.y[lane] = strided(y, stride, i), l.z[lane] = strided(z, stride, i);
  }
  return {load(l.x), load(l.y), load(l.z)};
}

DNG_LANE_INLINE void storeLanes(float* x, float* y, float* z, std::size_t stride, std::size_t n, V3 v, LaneBits on) {
  if (stride == sizeof(float)) { // packed: whole registers, lanes left to the scalar path keep their bytes
    const M m = laneMask(on);
    store(x + n, select(m, v.x, load(x + n)));
    store(y + n, select(m, v.y, load(y + n)));
    store(z + n, select(m, v.z, load(z + n)));
    return;
  }
#ifdef DNG_LANES_SCATTER
  I at;
  if (gatherOffsets(stride, &at)) {
    const M m = laneMask(on);
    scatter(&strided(x, stride, n), at, m, v.x), scatter(&strided(y, stride, n), at, m, v.y);
    scatter(&strided(z, stride, n), at, m, v.z);
    return;
  }
#endif
  Lanes3 l;
  store(l.x, v.x), store(l.y, v.y), store(l.z, v.z);
  for (int lane = 0; lane < kWidth; ++lane) {
    if (!((on >> lane) & 1u)) continue;
    const std::size_t i = n + std::size_t(lane);
    strided(x, stride, i) = l.x[lane], strided(y, stride, i) = l.y[lane], strided(z, stride, i) = l.z[lane];
  }
}

// The optional per-particle outputs of the lanes in `on`. The bodies as whole registers, as storeLanes
// stores packed positions (a branch and a store per lane had been about 4% of the step's instructions,
// callgrind on bench/swarm_hash); the contact bytes lane by lane.
DNG_LANE_INLINE void storeTouches(const ParticleSpan& s, std::size_t n, I touch, LaneBits on) {
  if (s.out_body != nullptr) {
    I before;
    std::memcpy(&before, s.out_body + n, sizeof before);
    const I merged = select(laneMask(on), touch, before);
    std::memcpy(s.out_body + n, &merged, sizeof merged);
  }
  if (s.out_contact == nullptr) return;
  alignas(kLaneAlign) std::int32_t body[kWidth];
  std::memcpy(body, &touch, sizeof body);
  for (LaneBits l = on; l != 0; l &= l - 1) {
    const int lane = lowestLane(l);
    s.out_contact[n + std::size_t(lane)] = contactFlag(body[lane]);
  }
}

// A chunk's bodies through an index, those the broadphase has near its lanes (near_lanes.h): the
// responses' (the positions, against the bodies' boxes) and the moves' (the moves' boxes, against the
// grown boxes).
struct ChunkBodies {
  NearList responses, moves;
  V3 lo, hi; // the move boxes `moves` was listed for, from the velocities before the responses
};

// The union path's lists (the union of the lanes' lists): the responses' bodies, and the moves' for
// the velocities as they are (most responses change none). Lanes whose bodies do not all fit leave
// *io_live.
DNG_LANE_INLINE const NearList& chunkResponses(const StepBatch& batch, const LaneLists* lists, ChunkBodies* io,
                                               M* io_live) {
  unionOfLanes(*lists, &io->moves, &io->responses, io_live);
  prepareListed(batch, nullptr, &io->responses);
  return io->responses;
}

// The moves' bodies, start -> end: listed again for the lanes whose move boxes the responses changed
// (the bodies their old boxes met stay listed; the lanes' own tests pass them by).
DNG_LANE_INLINE const NearList& chunkMoves(const StepBatch& batch, V3 start, V3 end, ChunkBodies* io, M* io_live) {
  V3 lo, hi;
  moveBox(start, end, &lo, &hi);
  const M moved = *io_live & boxChanged(lo, hi, io->lo, io->hi);
  if (any(moved))
    *io_live = andNot(*io_live, moved) | listNear(*batch.index, {lo, hi, start, &io->moves, nullptr}, moved);
  prepareListed(batch, &io->responses, &io->moves);
  return io->moves;
}

// Where a chunk's lanes are in the span: the kWidth particles from `first`, or, for a chunk gathered from
// several (Crowded below), particle index[lane] for each of the lanes `lanes`.
struct ChunkPlace {
  std::size_t first = 0;
  const std::size_t* index = nullptr;
  LaneBits lanes = allLanes();

  std::size_t of(int lane) const { return index != nullptr ? index[lane] : first + std::size_t(lane); }
};

// Particles whose walks need cells, set aside while the chunks go on and walked cell by cell 8 (or 4)
// at a time. A chunk's walk through cells runs every lane for as long as its slowest one needs, and
// near a surface most chunks have one or two such particles: gathered, every walk in a chunk is one
// that needs it. Nothing else differs: each lane still gives the scalar path's bits, or goes to it.
struct Deferred {
  static constexpr std::size_t kCapacity = 128; // on the stack (3 KB): stepParticles allocates nothing
  std::size_t count = 0;
  std::size_t index[kCapacity];
  // The velocities after the responses, and the bodies they touched at what distance, padded to whole
  // registers.
  alignas(kLaneAlign) float vx[kCapacity + kWidth], vy[kCapacity + kWidth], vz[kCapacity + kWidth];
  alignas(kLaneAlign) std::int32_t touch[kCapacity + kWidth];
  alignas(kLaneAlign) float touch_distance[kCapacity + kWidth];

  bool full() const { return count + std::size_t(kWidth) > kCapacity; }

  // Adds the lanes `on` of the chunk at `place`, with their velocities and touches.
  void add(const ChunkPlace& place, V3 velocity, const TouchLanes& touched, LaneBits on) {
    Lanes3 v;
    alignas(kLaneAlign) std::int32_t t[kWidth];
    alignas(kLaneAlign) float d[kWidth];
    store(v.x, velocity.x), store(v.y, velocity.y), store(v.z, velocity.z);
    std::memcpy(t, &touched.body, sizeof t);
    store(d, touched.distance);
    for (; on != 0; on &= on - 1) {
      const int lane = lowestLane(on);
      index[count] = place.of(lane);
      vx[count] = v.x[lane], vy[count] = v.y[lane], vz[count] = v.z[lane], touch[count] = t[lane];
      touch_distance[count] = d[lane];
      ++count;
    }
  }
};

// The floats of the particles at index[lane] (lanes past `lanes` repeat the first).
DNG_LANE_INLINE V3 gatherLanes(float* x, float* y, float* z, std::size_t stride, const std::size_t* index, int lanes) {
  Lanes3 l;
  for (int lane = 0; lane < kWidth; ++lane) {
    const std::size_t i = index[lane < lanes ? lane : 0];
    l.x[lane] = strided(x, stride, i), l.y[lane] = strided(y, stride, i), l.z[lane] = strided(z, stride, i);
  }
  return {load(l.x), load(l.y), load(l.z)};
}

DNG_LANE_INLINE V3 gatherPositions(const ParticleSpan& s, const std::size_t* index, int lanes) {
  return gatherLanes(s.position_x, s.position_y, s.position_z, s.position_stride, index, lanes);
}

// Writes the lanes `on`: position, velocity and the optional outputs of the particle at index[lane].
DNG_LANE_INLINE void scatterLanes(const ParticleSpan& s, const std::size_t* index, V3 position, V3 velocity, I touch,
                                  LaneBits on) {
  Lanes3 p, v;
  store(p.x, position.x), store(p.y, position.y), store(p.z, position.z);
  store(v.x, velocity.x), store(v.y, velocity.y), store(v.z, velocity.z);
  alignas(kLaneAlign) std::int32_t t[kWidth];
  std::memcpy(t, &touch, sizeof t);
  for (; on != 0; on &= on - 1) {
    const int lane = lowestLane(on);
    const std::size_t i = index[lane];
    strided(s.position_x, s.position_stride, i) = p.x[lane];
    strided(s.position_y, s.position_stride, i) = p.y[lane];
    strided(s.position_z, s.position_stride, i) = p.z[lane];
    strided(s.velocity_x, s.velocity_stride, i) = v.x[lane];
    strided(s.velocity_y, s.velocity_stride, i) = v.y[lane];
    strided(s.velocity_z, s.velocity_stride, i) = v.z[lane];
    writeTouch(s, i, t[lane]);
  }
}

// Walks the set-aside particles' moves through every body cell by cell (their balls could not prove
// them) and finishes them: the lanes proven clear move, the rest go to the scalar path's move. The
// responses already acted (their velocities are kept); the walks sample their starts again (the same
// numbers as the responses' samples).
//
// Out of line, as stepListed below: it runs once per Deferred::kCapacity set-aside particles at most,
// and inlined at each of its callers it made stepLanes 132 KB of code on AVX-512 (25 KB without it).
__attribute__((noinline)) inline void finishDeferred(const StepBatch& batch, Deferred* io) {
  if (io->count == 0) return;
  const ParticleSpan& s = *batch.particles;
  // Whole registers: the last chunk's empty lanes repeat its first particle's numbers (and stay off).
  const std::size_t last = (io->count - 1) / std::size_t(kWidth) * std::size_t(kWidth);
  for (std::size_t k = io->count; k < last + std::size_t(kWidth); ++k)
    io->vx[k] = io->vx[last], io->vy[k] = io->vy[last], io->vz[k] = io->vz[last], io->touch[k] = io->touch[last],
    io->touch_distance[k] = io->touch_distance[last];
  NearList listed; // with a broadphase: the bodies of the gathered lanes' moves
  for (std::size_t from = 0; from < io->count; from += std::size_t(kWidth)) {
    const int lanes = int(std::min(io->count - from, std::size_t(kWidth)));
    const std::size_t* index = io->index + from;
    const LaneParticles p{gatherPositions(s, index, lanes),
                          {load(io->vx + from), load(io->vy + from), load(io->vz + from)}};
    const V3 end = p.position + p.velocity * splat(batch.dt);
    const LaneBits on = firstLanes(lanes);
    M live = laneMask(on);
    const NearList* bodies = batch.all;
    if (batch.index != nullptr) {
      V3 lo, hi;
      moveBox(p.position, end, &lo, &hi);
      listed.count = 0;
      live = listNear(*batch.index, {lo, hi, p.position, &listed, nullptr}, live);
      prepareListed(batch, nullptr, &listed);
      bodies = &listed;
    }
    // With one body, the lanes that ask the neighbours at their start: the bound goes with the walk
    // handed over, and a walk it blocks is that body's stop, settled without walking. (With more
    // bodies, an earlier body's stop could come first.)
    StartLanes start{andNot(live, live), {}};
    const LaneBits done =
        bits(moveLanes(*bodies, live, p, end, nullptr, WalkPart::kCells, bodies->count == 1 ? &start : nullptr));
    I touch;
    std::memcpy(&touch, io->touch + from, sizeof touch);
    scatterLanes(s, index, end, p.velocity, touch, done);
    const LaneBits asks = bits(start.lanes) & on & ~done;
    Lanes3 local;
    if (asks != 0) store(local.x, start.local.x), store(local.y, start.local.y), store(local.z, start.local.z);
    for (LaneBits rest = on & ~done; rest != 0; rest &= rest - 1) { // the scalar path's move, after these responses
      const int lane = lowestLane(rest);
      const std::size_t k = from + std::size_t(lane);
      const Vec3f velocity{io->vx[k], io->vy[k], io->vz[k]};
      if (!(asks & laneBit(lane))) {
        batch.scalar_move(batch.context, io->index[k], velocity, io->touch[k], io->touch_distance[k], nullptr, 0);
        continue;
      }
      const std::size_t body = std::size_t(bodies->index[0]);
      StartBound bound;
      if (startBound(*bodies->body[0], {local.x[lane], local.y[lane], local.z[lane]}, &bound))
        batch.scalar_block(batch.context, io->index[k], velocity, io->touch[k], io->touch_distance[k], body);
      else
        batch.scalar_move(batch.context, io->index[k], velocity, io->touch[k], io->touch_distance[k], &bound, body);
    }
  }
  io->count = 0;
}

/// What one chunk's responses and balls leave: every lane's end and touched body, the lanes still in
/// the lanes (live), and of those the lanes proven clear (done).
struct ChunkStep {
  V3 end;
  TouchLanes touch;
  M live;
  LaneBits done;
  LaneBits queued = 0;   ///< live lanes another chunk will step (Crowded below), left alone here
  bool responded = true; ///< false: no response ran, so every velocity is still the one in the span
};

// The chunk's responses and balls through the union of its lanes' lists `lists` (an index's), for the
// lanes `live`.
DNG_LANE_INLINE ChunkStep stepUnion(const StepBatch& batch, const LaneLists* lists, ChunkBodies* near, M live,
                                    LaneParticles* io) {
  ChunkStep out;
  out.live = live;
  const NearList& respond = chunkResponses(batch, lists, near, &out.live);
  KeptSample kept[NearList::kCapacity];
  respondLanes(batch, respond, out.live, io, &out.touch, kept);
  out.end = io->position + io->velocity * splat(batch.dt);
  const NearList& walk = chunkMoves(batch, io->position, out.end, near, &out.live);
  out.done = bits(moveLanes(walk, out.live, *io, out.end, kept, WalkPart::kBalls));
  return out;
}

// The chunk at `place` after its responses and balls: the lanes proven clear move, the rest of the live
// ones are set aside for the cells (but those queued), the others go to the scalar path.
DNG_LANE_INLINE void finishChunk(const StepBatch& batch, const ChunkPlace& place, const LaneParticles& p,
                                 const ChunkStep& c, Deferred* deferred) {
  const ParticleSpan& s = *batch.particles;
  if (place.index != nullptr) {
    scatterLanes(s, place.index, c.end, p.velocity, c.touch.body, c.done);
  } else {
    storeLanes(s.position_x, s.position_y, s.position_z, s.position_stride, place.first, c.end, c.done);
    if (c.responded)
      storeLanes(s.velocity_x, s.velocity_y, s.velocity_z, s.velocity_stride, place.first, p.velocity, c.done);
    storeTouches(s, place.first, c.touch.body, c.done);
  }
  const LaneBits later = bits(c.live) & ~c.done & ~c.queued; // their walks need cells
  if (later != 0) {
    if (deferred->full()) finishDeferred(batch, deferred);
    deferred->add(place, p.velocity, c.touch, later);
  }
  // The lanes whose bodies the lists could not hold.
  for (LaneBits rest = place.lanes & ~bits(c.live); rest != 0; rest &= rest - 1)
    batch.scalar(batch.context, place.of(lowestLane(rest)));
}

DNG_LANE_INLINE LaneParticles loadChunk(const ParticleSpan& s, std::size_t n) {
  return {loadLanes(s.position_x, s.position_y, s.position_z, s.position_stride, n),
          loadLanes(s.velocity_x, s.velocity_y, s.velocity_z, s.velocity_stride, n)};
}

// What stepping chunks through an index needs besides the particles: the union way's lists, each
// lane's bodies, and the chunk's slots.
struct IndexScratch {
  ChunkBodies near;
  LaneLists lists;
  ChunkSlots slots;
};

// The chunk's responses and balls through its lanes' lists, `live` (near.lo, near.hi their move boxes):
// slot by slot where the slots share fields and materials (slot_lanes.h), else the union way. Out of
// line: one copy serves the queue and the whole chunks. Inlined in both, and finishDeferred inlined
// too, stepThroughIndex was 455 KB of code on AVX-512, and the index path 13% slower
// (bench/many_bodies_bench).
__attribute__((noinline)) inline ChunkStep stepListed(const StepBatch& batch, IndexScratch* w, M live,
                                                      LaneParticles* io) {
  if (!makeSlots(batch, w->lists, live, &w->slots)) return stepUnion(batch, &w->lists, &w->near, live, io);
  ChunkStep c;
  c.live = live;
  c.done = bits(stepSlots(batch, w->slots, w->lists, w->near.lo, w->near.hi, io, &c.live, &c.end, &c.touch));
  return c;
}

// Lanes that meet a body, queued from chunks where most lanes meet none. A chunk's slots cost the same
// however few of its lanes they are for: with raindrops in random order over a city, about one lane in
// six meets a building (bench/many_bodies_bench), so each chunk paid the slots' and the field's work
// for a handful of lanes. Queued, those lanes fill whole chunks. Each lane's result does not depend on
// the others', so the order lanes are stepped in changes no bit.
// Room for two chunks' worth: a chunk's lanes may join a queue one lane short of a chunk.
struct Crowded {
  static constexpr int kCapacity = 2 * kWidth;
  std::size_t count = 0;
  std::size_t index[kCapacity];
  // Each queued lane's list as its chunk listed it, a column per lane as in LaneLists: a lane's list
  // depends on its own position and move alone (listEachLane), so the queue's chunk does not list it
  // again.
  alignas(kLaneAlign) std::int32_t body[LaneLists::kMax][kCapacity];
  alignas(kLaneAlign) std::int32_t listed[kCapacity];

  // Queues particle i, lane `lane` of a chunk whose lists are `lists`.
  void add(std::size_t i, const LaneLists& lists, int lane) {
    index[count] = i;
    listed[count] = lists.count[lane];
    for (int k = 0; k < LaneLists::kMax; ++k)
      body[k][count] = lists.body[k][lane];
    ++count;
  }

  // The lists of the first `lanes` queued lanes as a chunk's; the lanes past them list no body. Every
  // listed body counts as held, which LaneLists::held allows (listOneCellEach does the same).
  void takeLists(int lanes, LaneLists* out) const {
    I n;
    std::memcpy(&n, listed, sizeof n);
    n = select(laneMask(firstLanes(lanes)), n, splatI(0));
    std::memcpy(out->count, &n, sizeof n);
    for (int k = 0; k < LaneLists::kMax; ++k) {
      std::memcpy(out->body[k], body[k], sizeof out->body[k]);
      out->held[k] = bits(toFloat(n) > splat(float(k))); // a count: small, exact as a float
    }
  }

  // Drops the first `lanes` queued lanes: all of them, or a chunk's worth (kWidth), whose followers,
  // fewer than kWidth, move down as a chunk's worth of each column (a copy of known size, no call).
  void drop(int lanes) {
    count -= std::size_t(lanes);
    if (count == 0) return;
    const auto moveDown = [](auto* column) { std::memcpy(column, column + kWidth, kWidth * sizeof *column); };
    moveDown(index);
    moveDown(listed);
    for (int k = 0; k < LaneLists::kMax; ++k)
      moveDown(body[k]);
  }
};

// Lists the lanes of the chunk at `place` and steps them; or, when at most half of them meet a body,
// finishes the others (they move as they would through the slots: no response, their own end) and
// adds those to `queue`. Lanes whose bodies the lists cannot hold go to the scalar path.
DNG_LANE_INLINE void stepOrQueue(const StepBatch& batch, IndexScratch* w, const ChunkPlace& place, LaneParticles p,
                                 Crowded* queue, Deferred* deferred) {
  const V3 end = p.position + p.velocity * splat(batch.dt);
  moveBox(p.position, end, &w->near.lo, &w->near.hi);
  const M live = listEachLane(*batch.index, w->near.lo, w->near.hi, p.position, laneMask(place.lanes), &w->lists);
  I count;
  std::memcpy(&count, w->lists.count, sizeof count);
  LaneBits meeting = bits(andNot(live, count == splatI(0)));
  if (2 * laneCount(meeting) > kWidth) {
    finishChunk(batch, place, p, stepListed(batch, w, live, &p), deferred);
    return;
  }
  ChunkStep c;
  c.end = end;
  c.touch = noTouch();
  c.live = live;
  c.done = bits(live) & ~meeting;
  c.queued = meeting;
  c.responded = false;
  finishChunk(batch, place, p, c, deferred);
  for (; meeting != 0; meeting &= meeting - 1)
    queue->add(place.of(lowestLane(meeting)), w->lists, lowestLane(meeting));
}

// Steps the first kWidth queued lanes (all of them, when fewer) as one chunk, gathered (lanes past the
// count repeat the first and stay off), with the lists their chunks gave them, and drops them from the
// queue.
DNG_LANE_INLINE void stepQueue(const StepBatch& batch, IndexScratch* w, Crowded* queue, Deferred* deferred) {
  if (queue->count == 0) return;
  const ParticleSpan& s = *batch.particles;
  const int lanes = int(std::min(queue->count, std::size_t(kWidth)));
  LaneParticles p{gatherPositions(s, queue->index, lanes),
                  gatherLanes(s.velocity_x, s.velocity_y, s.velocity_z, s.velocity_stride, queue->index, lanes)};
  moveBox(p.position, p.position + p.velocity * splat(batch.dt), &w->near.lo, &w->near.hi);
  queue->takeLists(lanes, &w->lists);
  const ChunkPlace place{0, queue->index, firstLanes(lanes)};
  finishChunk(batch, place, p, stepListed(batch, w, laneMask(place.lanes), &p), deferred);
  queue->drop(lanes);
}

// Through an index: each chunk lists its lanes' bodies; a chunk where at most half of them meet one
// queues those (Crowded), any other is stepped whole.
__attribute__((noinline)) inline std::size_t stepThroughIndex(const StepBatch& batch, Deferred* deferred) {
  const ParticleSpan& s = *batch.particles;
  IndexScratch w;
  Crowded queue;
  std::size_t n = 0;
  for (; n + kWidth <= s.count; n += kWidth) {
    stepOrQueue(batch, &w, {n}, loadChunk(s, n), &queue, deferred);
    if (queue.count >= std::size_t(kWidth)) stepQueue(batch, &w, &queue, deferred);
  }
  stepQueue(batch, &w, &queue, deferred);
  return n;
}

// Without an index: every chunk meets every body. Each chunk's response samples are taken one chunk
// ahead, just before the chunk before it responds and walks: the two chunks' chains of dependent
// gathers and decodes are independent, and the core overlaps them. A chunk's samples depend on its
// positions alone, which nothing before its own step writes. Measured (bench/swarm_hash, fandisk,
// Table 1-like load, medians of 5 runs in turn, an Intel Xeon): AVX2 kernels 30.5 -> 28.3 ns per
// particle-step, SSE4.1 67.8 -> 60.6, AVX-512 18.5 -> 18.1 (its two registers per operation already
// overlapped much of it).
__attribute__((noinline)) inline std::size_t stepEveryBody(const StepBatch& batch, Deferred* deferred) {
  const ParticleSpan& s = *batch.particles;
  const NearList& all = *batch.all;
  if (s.count < std::size_t(kWidth)) return 0;
  LaneParticles p[2];
  ResponseSamples samples[2];
  p[0] = loadChunk(s, 0);
  sampleResponses(all, allTrue(), p[0].position, &samples[0]);
  std::size_t n = 0;
  for (int now = 0; n + kWidth <= s.count; n += kWidth, now ^= 1) {
    if (n + 2 * kWidth <= s.count) {
      p[now ^ 1] = loadChunk(s, n + kWidth);
      sampleResponses(all, allTrue(), p[now ^ 1].position, &samples[now ^ 1]);
    }
    ChunkStep c;
    c.live = allTrue();
    applyResponses(batch, all, samples[now], &p[now], &c.touch);
    c.end = p[now].position + p[now].velocity * splat(batch.dt);
    c.done = bits(moveLanes(all, c.live, p[now], c.end, samples[now].kept, WalkPart::kBalls));
    finishChunk(batch, {n}, p[now], c, deferred);
  }
  return n;
}

/// stepParticles over the whole span: lanes for what balls and cells settle, the scalar path for the
/// rest and for the tail.
inline void stepLanes(const StepBatch& batch) {
  const ParticleSpan& s = *batch.particles;
  Deferred deferred;
  std::size_t n = 0;
  if (batch.index != nullptr) {
    n = stepThroughIndex(batch, &deferred);
  } else {
    n = stepEveryBody(batch, &deferred);
  }
  finishDeferred(batch, &deferred);
  for (; n < s.count; ++n)
    batch.scalar(batch.context, n);
}

/// This set's table of kernels (step_batch.h), under `name`: what each batch_*.cpp exports.
constexpr BatchKernels kernelTable(const char* name) {
  return {name, &sampleNearestBatch, &sampleTrilinearBatch, &sampleAccurateBatch, &stepLanes, &neighbourBound};
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
