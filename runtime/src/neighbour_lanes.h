// Internal: the walk's neighbour bound (walk.cpp neighbourBound) with its 26 samples in lanes. The
// samples are nearestLanes, lane for lane the scalar planeSample; what the scalar loop does with each
// is done here with the same operations, and a maximum does not depend on the order it is taken in, so
// the bound is bit for bit the scalar one.
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

template <bool kDense>
float neighbourBoundLanes(const View& view, const NeighbourPoints& points, float reach, float* out_terms) {
  static_assert(NeighbourPoints::kPadded % kWidth == 0, "the padded points fill whole registers");
  const F cap = splat(reach);
  F best = splat(-reach);
  for (int n = 0; n < NeighbourPoints::kPadded; n += kWidth) {
    const V3 p{load(points.x + n), load(points.y + n), load(points.z + n)};
    const LaneSample s = nearestLanes<kDense>(view, p, allTrue());
    const F value = select(s.no_field, cap, minOf(s.distance, cap));
    const F term = value - load(points.gap + n);
    store(out_terms + n, select(s.far_inside, splat(-std::numeric_limits<float>::infinity()), term));
    best = select(s.far_inside, best, maxOf(term, best));
  }
  alignas(kLaneAlign) float lane[kWidth];
  store(lane, best);
  return *std::max_element(lane, lane + kWidth);
}

/// The kernel table's entry (step_batch.h BatchKernels) for either encoding.
inline float neighbourBound(const View& view, const NeighbourPoints& points, float reach, float* out_terms) {
  if (view.grid().encoding == format::Encoding::kDense)
    return neighbourBoundLanes<true>(view, points, reach, out_terms);
  return neighbourBoundLanes<false>(view, points, reach, out_terms);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
