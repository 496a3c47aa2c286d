// Internal: the broadphase (broadphase.h) for a chunk of lanes: the bodies its particles may meet,
// found in the index's cells with its own box tests, one body's box against every lane at once.
//
// The scalar path asks the index once per particle for its responses (the bodies whose boxes may hold
// its position) and once for its move (those whose grown boxes may meet the move's box). A chunk lists
// the union of those over its lanes, in increasing index, and each lane then tests every listed body
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

/// A move's box over more cells than this sends its lane to the scalar path.
constexpr std::uint32_t kMaxMoveCells = 8;

// BodyIndex::Impl::cellOf on lanes: maxOf and minOf are the same comparisons as its clamps.
DNG_LANE_INLINE I cellAxis(const IndexGrid& g, F x, int axis) {
  F t = (x - splat(g.origin[axis])) * splat(g.inv_cell);
  t = maxOf(t, splat(0.0f));
  t = minOf(t, splat(g.last_cell[axis]));
  return truncate(t);
}

struct LaneCells {
  alignas(32) std::uint32_t axis[3][kWidth];
};

DNG_LANE_INLINE LaneCells cellsOf(const IndexGrid& g, V3 p) {
  LaneCells c;
  const I x = cellAxis(g, p.x, 0), y = cellAxis(g, p.y, 1), z = cellAxis(g, p.z, 2);
  std::memcpy(c.axis[0], &x, sizeof c.axis[0]);
  std::memcpy(c.axis[1], &y, sizeof c.axis[1]);
  std::memcpy(c.axis[2], &z, sizeof c.axis[2]);
  return c;
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
  std::uint32_t from[3], to[3];
  std::uint32_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    from[a] = c0.axis[a][lane], to[a] = c1.axis[a][lane];
    cells *= to[a] - from[a] + 1;
  }
  if (cells > kMaxMoveCells) return false;
  for (std::uint32_t z = from[2]; z <= to[2]; ++z)
    for (std::uint32_t y = from[1]; y <= to[1]; ++y)
      for (std::uint32_t x = from[0]; x <= to[0]; ++x)
        listCell(g, (std::size_t(z) * g.dims[1] + y) * g.dims[0] + x, q, io_live);
  return true;
}

/// The bodies `q` asks for, added to its lists in increasing index. Returns the live lanes every such
/// body is listed for.
DNG_LANE_INLINE M listNear(const IndexGrid& g, const NearQuery& q, M live) {
  const V3 lo = q.lo, hi = q.hi;
  // A lane whose position is not a number has no number in its move box either.
  live =
      andNot(live, (lo.x != lo.x) | (lo.y != lo.y) | (lo.z != lo.z) | (hi.x != hi.x) | (hi.y != hi.y) | (hi.z != hi.z));
  listBodies(g, g.everywhere, g.everywhere_count, q, &live);
  // Boxes outside the scene's meet only the bodies listed everywhere (BodyIndex::Impl::listsFor).
  const M in_scene = (hi.x >= splat(g.scene_lo.x)) & (hi.y >= splat(g.scene_lo.y)) & (hi.z >= splat(g.scene_lo.z)) &
                     (lo.x <= splat(g.scene_hi.x)) & (lo.y <= splat(g.scene_hi.y)) & (lo.z <= splat(g.scene_hi.z));
  const unsigned lanes = bits(live & in_scene);
  if (lanes == 0) return live;
  const LaneCells c0 = cellsOf(g, lo), c1 = cellsOf(g, hi);
  // Lanes whose box is in one cell, and that cell: a cell's bodies are listed once for all its lanes.
  const I x0 = cellAxis(g, lo.x, 0), y0 = cellAxis(g, lo.y, 1), z0 = cellAxis(g, lo.z, 2);
  const unsigned single =
      bits((x0 == cellAxis(g, hi.x, 0)) & (y0 == cellAxis(g, hi.y, 1)) & (z0 == cellAxis(g, hi.z, 2)));
  const I cell = (z0 * splatI(std::int32_t(g.dims[1])) + y0) * splatI(std::int32_t(g.dims[0])) + x0;
  alignas(32) std::int32_t cells[kWidth];
  std::memcpy(cells, &cell, sizeof cells);
  for (unsigned pending = lanes; pending != 0;) {
    const int lane = __builtin_ctz(pending);
    pending &= pending - 1;
    if (!((single >> lane) & 1u)) {
      if (!listLaneCells(g, c0, c1, lane, q, &live)) live = andNot(live, laneMask(1u << lane));
      continue;
    }
    listCell(g, std::size_t(std::uint32_t(cells[lane])), q, &live);
    pending &= ~(single & bits(cell == splatI(cells[lane])));
  }
  return live;
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
