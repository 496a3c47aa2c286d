// Internal: the walk's neighbour bound (walk.cpp neighbourBound) with its 26 points and samples in
// lanes. The points are built from the same per-axis numbers with the same operations, and the samples
// are nearestLanes, lane for lane the scalar planeSample; what the scalar loop does with each is done
// here with the same operations, and a maximum does not depend on the order it is taken in, so the
// bound is bit for bit the scalar one.
//
// Include after sample_lanes.h.
#pragma once

#include "sample_lanes.h"
#include "walk.h"

#include <algorithm>
#include <limits>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

// The points of the registers' worth of neighbours from `n` on (walk.cpp neighboursOf, lane for lane):
// per axis a select of the three coordinates and squared gaps by the table's side, the gap's sum in
// the scalar order.
DNG_LANE_INLINE V3 neighbourPoints(const NeighbourAxes& axes, F h, int n, F* out_gap) {
  const F half = splat(0.5f), one_and_half = splat(1.5f);
  F coord[3], term[3];
  for (int axis = 0; axis < 3; ++axis) {
    const F side = load(kNeighbourSides.side[axis] + n);
    const M below = side < half;
    const M above = side > one_and_half;
    const float* c = axes.coord[axis];
    const float* t = axes.term[axis];
    coord[axis] = select(below, splat(c[0]), select(above, splat(c[2]), splat(c[1])));
    term[axis] = select(below, splat(t[0]), select(above, splat(t[2]), splat(t[1])));
  }
  *out_gap = sqrt(term[0] + term[1] + term[2]) * h;
  return {coord[0], coord[1], coord[2]};
}

template <bool kDense>
float neighbourBoundLanes(const View& view, const NeighbourAxes& axes, float reach, NeighbourPoints* out_points,
                          float* out_terms) {
  static_assert(NeighbourPoints::kPadded % kWidth == 0, "the padded points fill whole registers");
  const F cap = splat(reach), h = splat(view.grid().voxel_size);
  F best = splat(-reach);
  for (int n = 0; n < NeighbourPoints::kPadded; n += kWidth) {
    F gap;
    const V3 p = neighbourPoints(axes, h, n, &gap);
    store(out_points->x + n, p.x), store(out_points->y + n, p.y), store(out_points->z + n, p.z);
    store(out_points->gap + n, gap);
    const LaneSample s = nearestLanes<kDense>(view, p, allTrue());
    const F value = select(s.no_field, cap, minOf(s.distance, cap));
    const F term = value - gap;
    store(out_terms + n, select(s.far_inside, splat(-std::numeric_limits<float>::infinity()), term));
    best = select(s.far_inside, best, maxOf(term, best));
  }
  alignas(kLaneAlign) float lane[kWidth];
  store(lane, best);
  return *std::max_element(lane, lane + kWidth);
}

/// The kernel table's entry (step_batch.h BatchKernels) for either encoding.
inline float neighbourBound(const View& view, const NeighbourAxes& axes, float reach, NeighbourPoints* out_points,
                            float* out_terms) {
  if (view.grid().encoding == format::Encoding::kDense)
    return neighbourBoundLanes<true>(view, axes, reach, out_points, out_terms);
  return neighbourBoundLanes<false>(view, axes, reach, out_points, out_terms);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
