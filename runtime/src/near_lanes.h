// Internal: the broadphase (broadphase.h) for a chunk of lanes: the bodies its particles may meet,
// found in the index's cells with its own box tests. Two listings: each lane's own bodies
// (listEachLane, for the slot-by-slot step of slot_lanes.h, where neighbouring particles meet different
// buildings), and the union over the chunk's lanes (listNear, for the union step of span_lanes.h),
// which tests one body's box against every lane at once.
//
// The scalar path asks the index once per particle for its responses (the bodies whose boxes may hold
// its position) and once for its move (those whose grown boxes may meet the move's box). The union
// lists those over its lanes, in increasing index, and each lane then tests every listed body
// itself with the scalar path's own tests (step_lanes.h), so a body listed for another lane changes
// nothing for it. Every body the scalar path visits for a lane is listed: the grid enters a body in
// every cell its grown box touches, the lanes read every cell their box touches (cellAxis does
// BodyIndex::Impl::cellOf's operations in its order, so both find the same cells), and a listed body
// is kept when its box passes NearBodies::forEach's test for any lane. One walk over the cells of the
// moves' boxes lists both: a move's box holds its position, and a body's grown box holds its box (its
// corners minus and plus a travel >= 0, or not a number), so a body whose box holds a lane's position
// has a grown box that meets the lane's move box, in a cell that box touches. A lane whose position or
// move is not a number (the index would list every body), whose move crosses many cells, or whose
// bodies do not fit a NearList leaves the chunk for the scalar path. A lane alone in its chunk with a
// body stays: the lanes' work for the body serves one particle, but that costs less than the scalar
// path's own broadphase and step (bench/many_bodies_bench, particles in random order each near a
// different building).
#pragma once

#include "lanes.h"
#include "step_batch.h"

#include <cstring>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

/// The box of each lane's move from a to e.
DNG_LANE_INLINE void moveBox(V3 a, V3 e, V3* lo, V3* hi) {
  *lo = V3{minOf(a.x, e.x), minOf(a.y, e.y), minOf(a.z, e.z)};
  *hi = V3{maxOf(a.x, e.x), maxOf(a.y, e.y), maxOf(a.z, e.z)};
}

/// The lanes whose box [lo, hi] differs from [was_lo, was_hi] (a move the responses changed).
DNG_LANE_INLINE M boxChanged(V3 lo, V3 hi, V3 was_lo, V3 was_hi) {
  return (lo.x != was_lo.x) | (lo.y != was_lo.y) | (lo.z != was_lo.z) | (hi.x != was_hi.x) | (hi.y != was_hi.y) |
         (hi.z != was_hi.z);
}

/// A move's box over more cells than this sends its lane to the scalar path.
constexpr std::uint32_t kMaxMoveCells = 8;

// Coordinates along `axis` in cells from the grid's origin, unclamped: the first step of
// BodyIndex::Impl::cellOf and of cell_box::quantize, which cellAxis and quantizeInCell take from here.
DNG_LANE_INLINE F inCells(const IndexGrid& g, F x, int axis) { return (x - splat(g.origin[axis])) * splat(g.inv_cell); }

// BodyIndex::Impl::cellOf on lanes, from inCells: maxOf and minOf are the same comparisons as its clamps.
DNG_LANE_INLINE I cellAxis(const IndexGrid& g, F in_cells, int axis) {
  F t = maxOf(in_cells, splat(0.0f));
  t = minOf(t, splat(g.last_cell[axis]));
  return truncate(t);
}

struct LaneCells {
  alignas(kLaneAlign) std::uint32_t axis[3][kWidth];
};

// The cells a register's boxes touch: per axis the first and last, and where a box is in one cell,
// that cell; and the boxes' corners in cells (inCells), for quantizeMoves.
struct LaneCellRange {
  I first[3], last[3];
  M single;
  I cell;
  F lo[3], hi[3];
};

DNG_LANE_INLINE LaneCellRange cellRange(const IndexGrid& g, V3 lo, V3 hi) {
  LaneCellRange r;
  const F l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  for (int a = 0; a < 3; ++a) {
    r.lo[a] = inCells(g, l[a], a), r.hi[a] = inCells(g, h[a], a);
    r.first[a] = cellAxis(g, r.lo[a], a), r.last[a] = cellAxis(g, r.hi[a], a);
  }
  r.single = (r.first[0] == r.last[0]) & (r.first[1] == r.last[1]) & (r.first[2] == r.last[2]);
  r.cell = (r.first[2] * splatI(std::int32_t(g.dims[1])) + r.first[1]) * splatI(std::int32_t(g.dims[0])) + r.first[0];
  return r;
}

// The cells of a register's boxes per axis, stored for scalar code (LaneCells).
DNG_LANE_INLINE void storeCells(const LaneCellRange& r, LaneCells* first, LaneCells* last) {
  for (int a = 0; a < 3; ++a) {
    std::memcpy(first->axis[a], &r.first[a], sizeof first->axis[a]);
    std::memcpy(last->axis[a], &r.last[a], sizeof last->axis[a]);
  }
}

// Calls visit(c) for each cell c that lane `lane`'s box touches (the cells c0 to c1 per axis) while it
// returns true. False when the box touches more than kMaxMoveCells cells or a visit returns false.
template <class Visit>
DNG_LANE_INLINE bool forEachCell(const IndexGrid& g, const LaneCells& c0, const LaneCells& c1, int lane,
                                 Visit&& visit) {
  std::uint32_t from[3], to[3], cells = 1;
  for (int a = 0; a < 3; ++a) {
    from[a] = c0.axis[a][lane], to[a] = c1.axis[a][lane];
    cells *= to[a] - from[a] + 1;
  }
  if (cells > kMaxMoveCells) return false;
  for (std::uint32_t z = from[2]; z <= to[2]; ++z)
    for (std::uint32_t y = from[1]; y <= to[1]; ++y)
      for (std::uint32_t x = from[0]; x <= to[0]; ++x)
        if (!visit((std::size_t(z) * g.dims[1] + y) * g.dims[0] + x)) return false;
  return true;
}

// The lanes whose boxes [lo, hi] meet the scene's (the rest meet only the bodies listed everywhere).
DNG_LANE_INLINE M inScene(const IndexGrid& g, V3 lo, V3 hi) {
  return (hi.x >= splat(g.scene_lo.x)) & (hi.y >= splat(g.scene_lo.y)) & (hi.z >= splat(g.scene_lo.z)) &
         (lo.x <= splat(g.scene_hi.x)) & (lo.y <= splat(g.scene_hi.y)) & (lo.z <= splat(g.scene_hi.z));
}

// The lanes whose boxes [lo, hi] have a coordinate that is not a number.
DNG_LANE_INLINE M notNumbers(V3 lo, V3 hi) {
  return (lo.x != lo.x) | (lo.y != lo.y) | (lo.z != lo.z) | (hi.x != hi.x) | (hi.y != hi.y) | (hi.z != hi.z);
}

// The lanes whose boxes [lo, hi] NearBodies::forEach would not drop against `box`: its negated
// rejection, so a NaN rejects nothing, as there.
DNG_LANE_INLINE M meets(const Box& box, V3 lo, V3 hi) {
  return ~((hi.x < splat(box.lo.x)) | (hi.y < splat(box.lo.y)) | (hi.z < splat(box.lo.z)) | (lo.x > splat(box.hi.x)) |
           (lo.y > splat(box.hi.y)) | (lo.z > splat(box.hi.z)));
}

// Adds body b to the increasing list, once; false when the list is full without it.
DNG_LANE_INLINE bool insert(std::int32_t b, NearList* io) {
  std::size_t k = io->count;
  while (k > 0 && io->index[k - 1] > b)
    --k;
  if (k > 0 && io->index[k - 1] == b) return true;
  if (io->count == NearList::kCapacity) return false;
  for (std::size_t j = io->count; j > k; --j)
    io->index[j] = io->index[j - 1];
  io->index[k] = b;
  ++io->count;
  return true;
}

/// What a chunk asks the index: the bodies whose grown boxes meet the lanes' move boxes [lo, hi] into
/// *moves, and with `responses`, those of them whose boxes hold the lanes' positions `at` into
/// *responses (a box that holds `at` grown by the travel meets a move box that holds `at`: the same
/// bodies, read from the same cells).
struct NearQuery {
  V3 lo, hi, at;
  NearList* moves;
  NearList* responses; // null: the moves only
};

// Lists the bodies bodies[0, count) that meet a live lane's boxes; the lanes of a body that does not
// fit leave *io_live.
DNG_LANE_INLINE void listBodies(const IndexGrid& g, const std::uint32_t* bodies, std::size_t count, const NearQuery& q,
                                M* io_live) {
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t b = bodies[k];
    const BodyBoxes& boxes = g.boxes[b];
    const M moves = *io_live & meets(boxes.box[int(BodyBox::kGrown)], q.lo, q.hi);
    if (!any(moves)) continue; // then no box holds a lane's position either
    if (!insert(std::int32_t(b), q.moves)) {
      *io_live = andNot(*io_live, moves);
      continue;
    }
    if (q.responses == nullptr) continue;
    const M held = *io_live & meets(boxes.box[int(BodyBox::kBounds)], q.at, q.at);
    if (any(held) && !insert(std::int32_t(b), q.responses)) *io_live = andNot(*io_live, held);
  }
}

DNG_LANE_INLINE void listCell(const IndexGrid& g, std::size_t c, const NearQuery& q, M* io_live) {
  listBodies(g, g.cell_bodies + g.cell_start[c], g.cell_start[c + 1] - g.cell_start[c], q, io_live);
}

// Lists the bodies of the cells lane `lane`'s box touches (the cells c0 to c1 per axis); false when
// they are too many.
DNG_LANE_INLINE bool listLaneCells(const IndexGrid& g, const LaneCells& c0, const LaneCells& c1, int lane,
                                   const NearQuery& q, M* io_live) {
  return forEachCell(g, c0, c1, lane, [&](std::size_t c) DNG_LANE_LAMBDA {
    listCell(g, c, q, io_live);
    return true;
  });
}

/// The bodies `q` asks for, added to its lists in increasing index. Returns the live lanes every such
/// body is listed for.
DNG_LANE_INLINE M listNear(const IndexGrid& g, const NearQuery& q, M live) {
  const V3 lo = q.lo, hi = q.hi;
  // A lane whose position is not a number has no number in its move box either.
  live = andNot(live, notNumbers(lo, hi));
  listBodies(g, g.everywhere, g.everywhere_count, q, &live);
  // Boxes outside the scene's meet only the bodies listed everywhere (BodyIndex::Impl::listsFor).
  const LaneBits lanes = bits(live & inScene(g, lo, hi));
  if (lanes == 0) return live;
  const LaneCellRange r = cellRange(g, lo, hi);
  LaneCells c0, c1;
  storeCells(r, &c0, &c1);
  // Lanes whose box is in one cell, and that cell: a cell's bodies are listed once for all its lanes.
  const LaneBits single = bits(r.single);
  alignas(kLaneAlign) std::int32_t cells[kWidth];
  std::memcpy(cells, &r.cell, sizeof cells);
  for (LaneBits pending = lanes; pending != 0;) {
    const int lane = lowestLane(pending);
    pending &= pending - 1;
    if (!((single >> lane) & 1u)) {
      if (!listLaneCells(g, c0, c1, lane, q, &live)) live = andNot(live, laneMask(laneBit(lane)));
      continue;
    }
    listCell(g, std::size_t(std::uint32_t(cells[lane])), q, &live);
    pending &= ~(single & bits(r.cell == splatI(cells[lane])));
  }
  return live;
}

/// Each lane's own bodies (the chunk's slots, slot_lanes.h): per lane, in increasing index, the bodies
/// whose grown boxes meet its move box (the moves'), and which of them have boxes that hold its
/// position (the responses'): what the scalar path visits for that particle alone. Lane-interleaved:
/// body[k] holds every lane's k-th body.
struct LaneLists {
  static constexpr int kMax = 4; ///< a lane near more bodies goes to the scalar path
  alignas(kLaneAlign) std::int32_t body[kMax][kWidth];
  alignas(kLaneAlign) std::int32_t count[kWidth];
  /// Per k, the lanes whose k-th body's box holds their position, or may (listOneCellEach): the union
  /// path's responses list those bodies, and each lane tests the box again.
  LaneBits held[kMax];
};

// The lanes' query boxes and positions, stored for scalar code.
struct LaneQuery {
  Lanes3 lo, hi, at;
};

DNG_LANE_INLINE LaneQuery storeQuery(V3 lo, V3 hi, V3 at) {
  LaneQuery q;
  store(q.lo.x, lo.x), store(q.lo.y, lo.y), store(q.lo.z, lo.z);
  store(q.hi.x, hi.x), store(q.hi.y, hi.y), store(q.hi.z, hi.z);
  store(q.at.x, at.x), store(q.at.y, at.y), store(q.at.z, at.z);
  return q;
}

// NearBodies::forEach's test for lane `lane`'s box [lo, hi], scalar: the negated rejection.
DNG_LANE_INLINE bool meetsBox(const Box& box, const Lanes3& lo, const Lanes3& hi, int lane) {
  return !(hi.x[lane] < box.lo.x || hi.y[lane] < box.lo.y || hi.z[lane] < box.lo.z || lo.x[lane] > box.hi.x ||
           lo.y[lane] > box.hi.y || lo.z[lane] > box.hi.z);
}

// Adds the bodies of bodies[0, count) that lane `lane` meets to its list, in increasing index, once
// each; false when the list is full without one.
DNG_LANE_INLINE bool listForLane(const IndexGrid& g, const std::uint32_t* bodies, std::size_t count, const LaneQuery& q,
                                 int lane, LaneLists* io) {
  const LaneBits bit = laneBit(lane);
  std::int32_t& n = io->count[lane];
  for (std::size_t k = 0; k < count; ++k) {
    const auto b = std::int32_t(bodies[k]);
    const BodyBoxes& boxes = g.boxes[b];
    if (!meetsBox(boxes.box[int(BodyBox::kGrown)], q.lo, q.hi, lane)) continue;
    int at = n;
    while (at > 0 && io->body[at - 1][lane] > b)
      --at;
    if (at > 0 && io->body[at - 1][lane] == b) continue;
    if (n == LaneLists::kMax) return false;
    for (int j = n; j > at; --j) {
      io->body[j][lane] = io->body[j - 1][lane];
      io->held[j] = (io->held[j] & ~bit) | (io->held[j - 1] & bit);
    }
    io->body[at][lane] = b;
    const bool held = meetsBox(boxes.box[int(BodyBox::kBounds)], q.at, q.at, lane);
    io->held[at] = held ? io->held[at] | bit : io->held[at] & ~bit;
    ++n;
  }
  return true;
}

DNG_LANE_INLINE bool listCellForLane(const IndexGrid& g, std::size_t c, const LaneQuery& q, int lane, LaneLists* io) {
  return listForLane(g, g.cell_bodies + g.cell_start[c], g.cell_start[c + 1] - g.cell_start[c], q, lane, io);
}

// Lane `lane`'s bodies: the ones listed everywhere, then those of the cells its box touches (c0 to c1
// per axis) when it is in the scene; false when they are too many cells or bodies.
DNG_LANE_INLINE bool listLane(const IndexGrid& g, const LaneQuery& q, const LaneCells& c0, const LaneCells& c1,
                              int lane, bool in_scene, LaneLists* io) {
  io->count[lane] = 0;
  if (g.everywhere_count != 0 && !listForLane(g, g.everywhere, g.everywhere_count, q, lane, io)) return false;
  if (!in_scene) return true;
  return forEachCell(g, c0, c1, lane,
                     [&](std::size_t c) DNG_LANE_LAMBDA { return listCellForLane(g, c, q, lane, io); });
}

// Lists the lanes `lanes` one at a time (listLane); returns those whose lists are complete.
DNG_LANE_INLINE LaneBits listLanes(const IndexGrid& g, V3 lo, V3 hi, V3 at, const LaneCellRange& r, LaneBits lanes,
                                   LaneBits scene, LaneLists* io) {
  const LaneQuery q = storeQuery(lo, hi, at);
  LaneCells c0, c1;
  storeCells(r, &c0, &c1);
  LaneBits complete = 0;
  for (LaneBits on = lanes; on != 0; on &= on - 1) {
    const int lane = lowestLane(on);
    if (listLane(g, q, c0, c1, lane, (scene >> lane) & 1u, io)) complete |= laneBit(lane);
  }
  return complete;
}

// cell_box::quantize on lanes, for coordinates in cells (inCells) in the cells `cell`.
DNG_LANE_INLINE I quantizeInCell(F in_cells, I cell) {
  F f = (in_cells - toFloat(cell)) * splat(float(cell_box::kSteps));
  f = maxOf(f, splat(0.0f));
  f = minOf(f, splat(float(cell_box::kSteps - 1)));
  return truncate(f);
}

// Each lane's move box (r.lo, r.hi) in its one cell (r.first), as the two halves of a cell_box test: the
// high ends in fields 0-2, the low ends in fields 3-5.
struct QuantizedMoves {
  I high, low;
};
DNG_LANE_INLINE QuantizedMoves quantizeMoves(const LaneCellRange& r) {
  QuantizedMoves q{splatI(0), splatI(0)};
  for (int a = 0; a < 3; ++a) {
    q.high = q.high | quantizeInCell(r.hi[a], r.first[a]) * splatI(std::int32_t(cell_box::field(a, 1)));
    q.low = q.low | quantizeInCell(r.lo[a], r.first[a]) * splatI(std::int32_t(cell_box::field(3 + a, 1)));
  }
  return q;
}

// The lanes whose moves' fields meet the cell_boxes words `box`: per axis, the move's high end at or
// above the box's low end, and the box's high end at or above the move's low end. All six comparisons
// at once: each field of (x | guard) - y keeps its guard bit where x >= y, and never borrows from the
// next (16 + x - y >= 1).
DNG_LANE_INLINE M meetsCellBox(const QuantizedMoves& q, I box) {
  const I x = q.high | (box & splatI(std::int32_t(cell_box::kHighValues)));
  const I y = (box & splatI(std::int32_t(cell_box::kLowValues))) | q.low;
  const I guards = splatI(std::int32_t(cell_box::kGuards));
  return (((x | guards) + y * splatI(-1)) & guards) == guards;
}

// The lists of the lanes `listed`, each in the scene with its box in one cell (and no body listed
// everywhere): the j-th entry of every lane's cell at once, tested against its lane by the cell's
// coarse box (cell_box, broadphase.h), then the bodies of the entries that met, gathered once per
// place in the lists (a chunk's lanes walk as many entries as its longest cell holds, but list one or
// two bodies each). Cells list their bodies in increasing index, so each lane's come in order. A
// listed body's box may not hold the lane's position, nor its grown box meet the lane's move: the
// kernels test both again. Every other lane gets an empty list. Returns the lanes whose lists
// overflow.
DNG_LANE_INLINE M listOneCellEach(const IndexGrid& g, M listed, const LaneCellRange& r, LaneLists* out) {
  I start, stop;
  gatherPair(g.cell_start, r.cell, listed, &start, &stop);
  const F length = toFloat(stop + start * splatI(-1)); // a cell's count: small, exact as a float
  const QuantizedMoves moves = quantizeMoves(r);
  I count = splatI(0);
  I entry[LaneLists::kMax]; // per place in the lists, the entry of cell_bodies that met
  M held[LaneLists::kMax];
  for (int k = 0; k < LaneLists::kMax; ++k)
    entry[k] = splatI(0), held[k] = andNot(listed, listed);
  M full = andNot(listed, listed);
  // Entry `at` of the lanes `has`, whose coarse box is `box`, into their lists where it meets.
  const auto take = [&](I at, M has, I box) DNG_LANE_LAMBDA {
    const M meet = has & meetsCellBox(moves, box);
    full = full | (meet & (count == splatI(LaneLists::kMax)));
    for (int k = 0; k < LaneLists::kMax; ++k) {
      const M put = meet & (count == splatI(k));
      entry[k] = select(put, at, entry[k]);
      held[k] = held[k] | put;
    }
    count = count + select(meet, splatI(1), splatI(0));
  };
  // Two entries per gathered element (lanes.h gatherPair; cell_boxes keeps a word past its last entry):
  // the boxes' gathers were about a seventh of a city's step (bench/many_bodies_bench, perf).
  for (int j = 0;; j += 2) {
    const M has = listed & (length > splat(float(j)));
    if (!any(has)) break;
    const I at = start + splatI(j);
    I box, next_box;
    gatherPair(g.cell_boxes, at, has, &box, &next_box);
    take(at, has, box);
    take(at + splatI(1), has & (length > splat(float(j + 1))), next_box);
  }
  for (int k = 0; k < LaneLists::kMax; ++k) {
    const I body = any(held[k]) ? gather(g.cell_bodies, entry[k], held[k]) : splatI(0);
    std::memcpy(out->body[k], &body, sizeof body);
    out->held[k] = bits(held[k]);
  }
  std::memcpy(out->count, &count, sizeof count);
  return full;
}

/// Each live lane's bodies for the move boxes [lo, hi] and positions `at` into *out. Returns the live
/// lanes whose lists are complete: the others (a position or move that is not a number, a move over
/// many cells, more than LaneLists::kMax bodies) need the scalar path.
DNG_LANE_INLINE M listEachLane(const IndexGrid& g, V3 lo, V3 hi, V3 at, M live, LaneLists* out) {
  live = andNot(live, notNumbers(lo, hi));
  const M in_scene = inScene(g, lo, hi);
  const LaneCellRange r = cellRange(g, lo, hi);
  // Lanes in one cell all at once; the rest (boxes over several cells, bodies listed everywhere) one
  // at a time.
  const M one_cell = g.everywhere_count == 0 ? live & in_scene & r.single : andNot(live, live);
  live = andNot(live, listOneCellEach(g, one_cell, r, out));
  // Lanes outside the scene meet only the bodies listed everywhere: with none, listOneCellEach's empty
  // lists are theirs (raindrops above a city's roofs).
  const M empty = g.everywhere_count == 0 ? andNot(live, in_scene) : andNot(live, live);
  const LaneBits others = bits(andNot(andNot(live, one_cell), empty));
  if (others != 0) live = andNot(live, laneMask(others & ~listLanes(g, lo, hi, at, r, others, bits(in_scene), out)));
  return live;
}

/// The chunk's lists for the union path: every live lane's bodies as *moves, and those whose boxes
/// hold a live lane's position as *responses, each in increasing index; the lanes whose bodies do not
/// fit a NearList leave *io_live.
DNG_LANE_INLINE void unionOfLanes(const LaneLists& lists, NearList* moves, NearList* responses, M* io_live) {
  moves->count = responses->count = 0;
  for (LaneBits on = bits(*io_live); on != 0; on &= on - 1) {
    const int lane = lowestLane(on);
    bool fits = true;
    for (int k = 0; k < lists.count[lane]; ++k) {
      fits = fits && insert(lists.body[k][lane], moves);
      if ((lists.held[k] >> lane) & 1u) fits = fits && insert(lists.body[k][lane], responses);
    }
    if (!fits) *io_live = andNot(*io_live, laneMask(laneBit(lane)));
  }
}

/// Gives each listed body its numbers, the index's (kept there since its rebuild), its material as it
/// is now (materials may change without a rebuild), and its place in the chunk's response list, if any.
DNG_LANE_INLINE void prepareListed(const StepBatch& batch, const NearList* responses, NearList* io) {
  std::size_t r = 0;
  for (std::size_t k = 0; k < io->count; ++k) {
    const std::int32_t b = io->index[k];
    io->body[k] = &batch.prepared[b];
    io->material[k] = &batch.bodies[b].material();
    while (responses != nullptr && r < responses->count && responses->index[r] < b)
      ++r;
    io->kept[k] = responses != nullptr && r < responses->count && responses->index[r] == b ? std::int32_t(r) : -1;
  }
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
