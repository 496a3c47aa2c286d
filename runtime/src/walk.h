// Internal: moving a point along a segment through a body's field without crossing its surface.
//
// The baker writes every voxel's plane as a lower bound of the true signed distance over the voxel's
// whole cell (docs/FORMAT.md, "conservative planes"). The walk relies on nothing else:
//   - a ball: a point whose field value q is positive has no surface within q of it, in any direction,
//     so the segment may advance by q (sphere tracing, as in a swept step);
//   - a plane: inside one cell the field is the linear function q + n . (x - p), so the segment is
//     clear up to where that plane reaches the margin, or to the cell's exit when it does not;
//   - where the own cell's plane stops the walk or proves nothing (beside an edge, where it may be the
//     other face's plane), the cell's second bound when the file has one (PLN2, docs/FORMAT.md §5.5)
//     and it reads higher: the larger of two lower bounds is one too. The second bound is a plane, or
//     beside a concave crease the smaller of two planes (the cell's own raised, and the other face's),
//     which reaches the margin along the segment where the first of the two does;
//   - where neither proves anything, the neighbouring cells' planes: the best one's value, less the
//     distance to its cell, is a ball, and it also holds while the point slides along with a twin
//     point in that cell (walk.cpp slideEnd).
// Each sample advances by the largest of these. Near a surface that is a few samples per cell the
// segment crosses; away from it one ball covers the whole step.
#pragma once

#include "dng/view.h"

namespace dng {

/// How a walk ended.
enum class WalkStop : std::uint32_t {
  kClear = 0,   ///< the whole segment is clear
  kPlane = 1,   ///< a voxel plane closer than the margin, approached along its normal: reflect and slide
  kReverse = 2, ///< the field cannot prove the way ahead clear and its normal does not face the motion: go back
  kStall = 3,   ///< out of samples: stop where the walk got to, keep the velocity
};

struct WalkResult {
  WalkStop stop = WalkStop::kClear;
  float t = 1.0f; ///< fraction of the segment proven clear; the point stops there unless kClear
  Vec3f normal;   ///< local frame, unit: the blocking plane's normal (kPlane) or minus the motion (kReverse)
};

/// The walk keeps this much of a voxel between a particle and the surface: more than rounding in the
/// next step's sample and than the planes' largest measured overshoot (0.011 voxel over the unsigned
/// distance, at random points of real meshes: docs/FORMAT.md §5.1).
constexpr float kMarginVoxels = 0.06f;

/// Whether the step can walk through `field`: its guaranteed reach leaves room beyond the margin. A
/// thinner band (under about 0.93 voxel; dngbake writes at least 1) would give every ball a negative
/// radius, and walks would step backwards.
inline bool walkable(const View& field) { return field.guaranteedReach() > kMarginVoxels * field.grid().voxel_size; }

/// A ball that leaves this much room (local units) around a walk's end point needs no look at the end
/// point itself: that far out the planes prove any point outside.
inline float walkRoomy(const View& field) { return 3.0f * field.grid().voxel_size; }

/// A field value proves a point outside from this level up: the planes' promise holds to a hundredth
/// of a voxel near the surface (docs/FORMAT.md §5.1); farther out, where balls reach, the margin
/// covers more.
inline float walkProofLevel(const View& field) { return 0.01f * field.grid().voxel_size; }

/// The 26 cells around a point's own, as the walk's neighbour bound reads them (walk.cpp): for each,
/// the point of the cell nearest p and how far that is (local units). Entries past the 26th copy the
/// first, which changes no maximum, so lanes of any width take whole registers.
struct NeighbourPoints {
  static constexpr int kCount = 26;
  static constexpr int kPadded = 32;
  alignas(64) float x[kPadded], y[kPadded], z[kPadded], gap[kPadded];
};

/// What the neighbour points are made of, per axis: a neighbour lies below (0), level with (1) or above
/// (2) p's cell, and for each of the three, `coord` is the coordinate of its point nearest p (local
/// units; level, p's own) and `term` that coordinate's part of the squared gap (voxel units; level, 0).
/// A point's gap is sqrt(term[0][i] + term[1][j] + term[2][k]) voxels, summed in that order.
struct NeighbourAxes {
  float coord[3][3];
  float term[3][3];
};

/// Each neighbour's side per axis (NeighbourAxes), x fastest, p's own cell skipped; the padding takes
/// the first neighbour's sides. Floats, so SIMD lanes load them as they are.
struct NeighbourSides {
  alignas(64) float side[3][NeighbourPoints::kPadded];
};
constexpr NeighbourSides makeNeighbourSides() {
  NeighbourSides t{};
  int c = 0;
  for (int n = 0; n < 27; ++n) {
    if (n == 13) continue; // p's own cell
    t.side[0][c] = float(n % 3), t.side[1][c] = float((n / 3) % 3), t.side[2][c] = float(n / 9);
    ++c;
  }
  for (; c < NeighbourPoints::kPadded; ++c)
    t.side[0][c] = t.side[0][0], t.side[1][c] = t.side[1][0], t.side[2][c] = t.side[2][0];
  return t;
}
inline constexpr NeighbourSides kNeighbourSides = makeNeighbourSides();

/// The neighbour points' parts for the local point `p` of a field with this grid.
NeighbourAxes neighbourAxes(const GridInfo& g, Vec3f p);

/// The neighbour bound at a walk's start, taken by its caller already (the SIMD kernels, asking whether
/// the start is blocked): what walkSegment's own neighbourBound would answer there, bit for bit.
struct StartBound {
  float bound = 0.0f;
  NeighbourPoints points;
  alignas(64) float terms[NeighbourPoints::kPadded];
};

/// Whether a walk from the local point `p` can leave it: its own plane, its second bound or a
/// neighbour's bound reads at least walkProofLevel there, or the point is beyond the field's band or
/// grid. walkSegment blocks a start where this is false in every direction (but in far inside voxels).
bool walkProvesOutside(const View& field, Vec3f p);

/// Walks the local segment a -> a + delta through `field`, keeping at least `margin` (local units)
/// between the path and the surface as far as the field can prove it. `first`, when not null, is the
/// field's sample at `a` (the step already took it for the particle's response). A start point the
/// field cannot prove outside, by its own plane or a neighbour's bound, is blocked in every direction
/// (kReverse at t = 0), except from a far inside voxel, where there is nothing left to protect.
/// At most `max_samples` samples. `start_bound`, when not null, is the neighbour bound at `a`.
WalkResult walkSegment(const View& field, Vec3f a, Vec3f delta, const Sample* first, float margin, int max_samples,
                       const StartBound* start_bound = nullptr);

} // namespace dng
