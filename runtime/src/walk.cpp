// The conservative walk (walk.h). Beyond the paper: its particles are tested at the end of each step
// only, so a fast or grazing particle can pass through an edge or a thin part between two tests.
#include "walk.h"
#include "step_batch.h"
#include "view_internals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace dng {
namespace {

// The walk reads the planes, which the bake made conservative; a shading normal (SHAD) bounds nothing.
Sample planeAt(const View& field, Vec3f p) { return ViewInternals::planeSample(field, p); }

bool insideGrid(const GridInfo& g, Vec3f p) {
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = component(g.origin, axis);
    if (!(component(p, axis) >= lo && component(p, axis) < lo + float(g.dims[axis]) * g.voxel_size)) return false;
  }
  return true;
}

// Clips the segment a + t d, t in [0, 1], to the grid's box; false when it misses. The box holds the
// whole band with padding, so the parts of a segment outside it are clear.
bool clipToGrid(const GridInfo& g, Vec3f a, Vec3f d, float* io_t0, float* io_t1) {
  if (insideGrid(g, a) && insideGrid(g, a + d)) return true; // the common case: nothing to clip
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = component(g.origin, axis);
    const float hi = lo + float(g.dims[axis]) * g.voxel_size;
    const float start = component(a, axis), dir = component(d, axis);
    if (dir == 0.0f) {
      if (!(start >= lo && start < hi)) return false;
      continue;
    }
    float ta = (lo - start) / dir, tb = (hi - start) / dir;
    if (ta > tb) std::swap(ta, tb);
    *io_t0 = std::max(*io_t0, ta);
    *io_t1 = std::min(*io_t1, tb);
  }
  return *io_t0 <= *io_t1;
}

// Where the segment a + t d leaves the voxel that contains a + t d, computed in voxel units the way
// View finds the voxel, so the two agree about which cell a point is in.
float cellExit(const GridInfo& g, float inv_h, Vec3f a, Vec3f d, float t) {
  float exit = 2.0f;
  for (int axis = 0; axis < 3; ++axis) {
    const float du = component(d, axis) * inv_h;
    if (du == 0.0f) continue;
    const float u = (component(a, axis) + component(d, axis) * t - component(g.origin, axis)) * inv_h;
    const float wall = du > 0.0f ? std::floor(u) + 1.0f : std::floor(u);
    exit = std::min(exit, t + (wall - u) / du);
  }
  return exit;
}

WalkResult stopAt(WalkStop stop, float t, Vec3f normal) { return {stop, t, normal}; }

// The cells around p's own: for each, the point of the cell nearest p and how far p is from it. The
// SIMD kernels build the same points in lanes (neighbour_lanes.h).
NeighbourPoints neighboursOf(const NeighbourAxes& axes, float h) {
  NeighbourPoints out;
  float gap2[NeighbourPoints::kPadded];
  // Unrolled, the table's entries become constant offsets.
#pragma GCC unroll 32
  for (int c = 0; c < NeighbourPoints::kPadded; ++c) {
    const int i = int(kNeighbourSides.side[0][c]), j = int(kNeighbourSides.side[1][c]),
              k = int(kNeighbourSides.side[2][c]);
    out.x[c] = axes.coord[0][i], out.y[c] = axes.coord[1][j], out.z[c] = axes.coord[2][k];
    gap2[c] = axes.term[0][i] + axes.term[1][j] + axes.term[2][k]; // + 0 leaves a sum's bits as they are
  }
  for (int k = 0; k < NeighbourPoints::kPadded; ++k)
    out.gap[k] = std::sqrt(gap2[k]) * h;
  return out;
}

// A lower bound of the distance at p from the 26 cells around p's own. A cell's plane bounds the
// distance only inside that cell, but the distance is 1-Lipschitz, so the plane's value at the cell
// point nearest p, less the distance to it, bounds it at p too. This is what proves a point outside
// when its own cell's plane cannot: near a convex edge the plane of the face the voxel centre is
// closest to reads far below zero just outside the other face.
// Each point's own term, value - gap (-infinity for far inside cells), goes to out_terms, and the
// points themselves to out_points.
float neighbourBound(const View& field, float reach, Vec3f p, NeighbourPoints* out_points, float* out_terms) {
  const NeighbourAxes axes = neighbourAxes(field.grid(), p);
  // The SIMD kernels build the points and take the 26 samples in lanes (dng/instruction_set.h), with
  // the same result.
  const BatchKernels* kernels = activeBatchKernels();
  if (kernels != nullptr && batchIndexable(field))
    return kernels->neighbour_bound(field, axes, reach, out_points, out_terms);
  const NeighbourPoints& points = *out_points = neighboursOf(axes, field.grid().voxel_size);
  float best = -reach;
  for (int k = 0; k < NeighbourPoints::kCount; ++k) {
    const Sample s = planeAt(field, {points.x[k], points.y[k], points.z[k]});
    out_terms[k] = -std::numeric_limits<float>::infinity();
    if (s.status == SampleStatus::kFarInside) continue;
    const float value = s.status == SampleStatus::kNoField ? reach : std::min(s.distance, reach);
    out_terms[k] = value - points.gap[k];
    best = std::max(best, out_terms[k]);
  }
  return best;
}

float neighbourBound(const View& field, float reach, Vec3f p) {
  NeighbourPoints points;
  float terms[NeighbourPoints::kPadded];
  return neighbourBound(field, reach, p, &points, terms);
}

// How far (in t) the segment a + d t may go from t while a neighbour's plane keeps it `margin` clear:
// the neighbour that gave `bound` (its term equals it), sampled at its point c. Its plane bounds the
// distance inside its cell, so as the point moves by d (t - t0), the point c + d (t - t0) reads the
// plane's value plus its change along d while it stays in that cell, and it stays exactly `gap` away
// (distance is 1-Lipschitz). Beside an edge this slides a particle along the face it skims by up to
// a cell per bound, where the bound's ball alone proves only a sliver. Returns t when it proves less.
float slideEnd(const View& field, const NeighbourPoints& points, const float* terms, float bound, float margin, Vec3f d,
               float t) {
  int best = 0;
  while (best < NeighbourPoints::kCount && terms[best] != bound)
    ++best;
  if (best == NeighbourPoints::kCount) return t;
  const Vec3f c{points.x[best], points.y[best], points.z[best]};
  const Sample s = planeAt(field, c);
  if (s.status != SampleStatus::kInBand) return t; // a far cell's value need not follow one plane
  const GridInfo& g = field.grid();
  const float inv_h = 1.0f / g.voxel_size;
  float room = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) { // where c + d s leaves the cell c is in, as View finds it
    const float du = component(d, axis) * inv_h;
    if (du == 0.0f) continue;
    const float u = (component(c, axis) - component(g.origin, axis)) * inv_h;
    const float wall = du > 0.0f ? std::floor(u) + 1.0f : std::floor(u);
    room = std::min(room, (wall - u) / du);
  }
  const float rate = dot(s.normal, d); // the plane's change per unit t
  if (rate < 0.0f) room = std::min(room, (bound - margin) / -rate);
  return t + room;
}

// The best lower bound of the distance at p the field gives: its own plane, its second plane, or its
// neighbours'.
float fieldBound(const View& field, float reach, Vec3f p) {
  const Sample s = planeAt(field, p);
  if (s.status == SampleStatus::kFarOutside || s.status == SampleStatus::kNoField) return reach;
  if (s.status == SampleStatus::kInBand && s.distance >= 0.0f) return std::min(s.distance, reach);
  ViewInternals::OtherPlane other;
  const Sample second = ViewInternals::secondBound(field, p, s, &other);
  if (second.status == SampleStatus::kFarOutside) return reach;
  if (second.status == SampleStatus::kInBand && second.distance >= 0.0f) return std::min(second.distance, reach);
  return neighbourBound(field, reach, p);
}

// Whether the field itself proves p outside: its own plane reads >= `proof` there, or its second plane,
// or a neighbour's bound does. A walk only ever leaves a particle at such a point, so the next step can
// prove it again.
bool provable(const View& field, float reach, float proof, Vec3f p, const Sample& s) {
  if (s.status == SampleStatus::kFarOutside || s.status == SampleStatus::kNoField) return true;
  if (s.status == SampleStatus::kInBand && s.distance >= proof) return true;
  ViewInternals::OtherPlane other;
  const Sample second = ViewInternals::secondBound(field, p, s, &other);
  if (second.status == SampleStatus::kFarOutside || second.distance >= proof) return true;
  return neighbourBound(field, reach, p) >= proof;
}

// What one cell's plane, read at the walk's point (t), says about the rest of the walk.
enum class Verdict {
  kCovers,  // its ball covers the rest of the segment
  kFar,     // a far outside voxel: a ball that does not reach the end
  kStops,   // the plane reaches the margin inside the cell: the walk stops at `hit`
  kToWall,  // the plane proves the way clear to the cell's wall
  kNothing, // it proves nothing here (beside an edge): ask more of the field
};

struct CellPlan {
  Verdict verdict;
  float q;      // the sample's value, capped at the reach (-reach far inside)
  float clear;  // q less the margin
  float rate;   // the plane's change along the segment, per unit t
  float exit;   // where the segment leaves the cell
  float hit;    // kStops: where the plane reaches the margin
  Vec3f normal; // kStops: the normal of the plane that does
};

// `s` is the cell's plane at the walk's point, or with `other` present the lower of a pair of planes
// whose smaller one bounds the distance (a second bound beside a concave crease, docs/FORMAT.md §5.5):
// the smaller of two planes reaches the margin where the first of them does, and rises where both do.
CellPlan planCell(const GridInfo& g, float inv_h, Vec3f a, Vec3f d, float t, float t_end, float len, const Sample& s,
                  const ViewInternals::OtherPlane& other, float reach, float margin, float proof_level) {
  CellPlan plan{};
  plan.q = s.status == SampleStatus::kFarInside ? -reach : std::min(s.distance, reach);
  plan.clear = plan.q - margin;
  if (plan.clear >= (t_end - t) * len) return plan.verdict = Verdict::kCovers, plan;
  if (s.status == SampleStatus::kFarOutside) return plan.verdict = Verdict::kFar, plan;
  plan.rate = s.status == SampleStatus::kInBand ? dot(s.normal, d) : 0.0f;
  plan.exit = cellExit(g, inv_h, a, d, t);
  plan.hit = std::numeric_limits<float>::infinity();
  if (plan.rate < 0.0f && plan.clear >= 0.0f) { // approaching: clear until the plane reaches the margin
    plan.hit = t + plan.clear / -plan.rate;
    plan.normal = s.normal;
  }
  const float other_rate = other.present ? dot(other.normal, d) : 0.0f;
  if (other_rate < 0.0f && plan.clear >= 0.0f) {
    const float other_hit = t + (std::min(other.distance, reach) - margin) / -other_rate;
    if (other_hit < plan.hit) plan.hit = other_hit, plan.normal = other.normal;
  }
  if (plan.hit < plan.exit && plan.hit < t_end) return plan.verdict = Verdict::kStops, plan;
  // Clear to the cell's wall: the plane stays above the margin, or rises from a proving value.
  if (plan.clear >= 0.0f ||
      (plan.rate >= 0.0f && other_rate >= 0.0f && plan.q >= proof_level && s.status == SampleStatus::kInBand))
    return plan.verdict = Verdict::kToWall, plan;
  return plan.verdict = Verdict::kNothing, plan;
}

// Whether a sample proves a ball around its point clear: a far outside voxel, or a plane reading.
bool provesBall(const Sample& s) { return s.status == SampleStatus::kFarOutside || s.status == SampleStatus::kInBand; }

// Two balls, around the start and around the end, cover the whole segment when their clear radii
// add up to its length: every point of it lies within one of them (the distance is 1-Lipschitz and
// the planes bound it from below). The end must also prove itself outside on its own plane, so the
// next step starts from a point it can prove. One more sample settles most moves near a surface
// that the first ball alone cannot cover; without it the walk goes cell by cell.
bool twoBallsClear(const Sample& start, const Sample& end, float reach, float margin, float proof_level, float len) {
  const bool end_proven = end.status == SampleStatus::kFarOutside || end.status == SampleStatus::kNoField ||
                          (end.status == SampleStatus::kInBand && end.distance >= proof_level);
  if (!end_proven) return false;
  const float gap_start = std::min(start.distance, reach) - margin;
  const float gap_end = (end.status == SampleStatus::kInBand ? std::min(end.distance, reach) : reach) - margin;
  return gap_start >= len || gap_start + gap_end >= len;
}

} // namespace

// Per axis a neighbour's point is just past the wall between its cell and p's (below or above), or p's
// own coordinate.
NeighbourAxes neighbourAxes(const GridInfo& g, Vec3f p) {
  const float h = g.voxel_size, inv_h = 1.0f / h;
  constexpr float kInto = 1e-3f; // voxel units past a wall, so the sample lands in the other cell
  NeighbourAxes out;
  for (int axis = 0; axis < 3; ++axis) {
    const float origin = component(g.origin, axis);
    const float u = (component(p, axis) - origin) * inv_h, cell = std::floor(u);
    const float below = cell - kInto, above = cell + 1.0f + kInto;
    out.coord[axis][0] = origin + below * h, out.coord[axis][1] = component(p, axis);
    out.coord[axis][2] = origin + above * h;
    out.term[axis][0] = (u - below) * (u - below), out.term[axis][1] = 0.0f;
    out.term[axis][2] = (u - above) * (u - above);
  }
  return out;
}

bool walkProvesOutside(const View& field, Vec3f p) {
  return provable(field, field.guaranteedReach(), walkProofLevel(field), p, planeAt(field, p));
}

WalkResult walkSegment(const View& field, Vec3f a, Vec3f d, const Sample* first, float margin, int max_samples,
                       const StartBound* start_bound) {
  const GridInfo& g = field.grid();
  const float len = length(d);
  // A far voxel's centre is beyond the band, so every point of its cell is at least this far.
  const float reach = field.guaranteedReach();
  const float roomy = walkRoomy(field);
  // The common case first: far from the surface, the first sample's ball covers the whole step.
  if (first != nullptr && provesBall(*first) && std::min(first->distance, reach) - margin - len >= roomy) return {};
  float t = 0.0f, t_end = 1.0f;
  if (!(len > 0.0f) || !clipToGrid(g, a, d, &t, &t_end)) return {};
  const float proof_level = walkProofLevel(field);
  const Sample start = first != nullptr ? *first : planeAt(field, a);
  first = &start;
  if (t == 0.0f && t_end == 1.0f && provesBall(start) &&
      twoBallsClear(start, planeAt(field, a + d), reach, margin, proof_level, len))
    return {};
  const float inv_h = 1.0f / g.voxel_size;
  // Steps past a cell wall land in the next cell: a fraction of a voxel, far below any margin.
  const float nudge = 2e-3f * g.voxel_size / len;
  const Vec3f back = d * (-1.0f / len);
  // The last points the field proves outside by itself, where a blocked walk stops; -1: none yet.
  // Own: by the point's own cell, so the next step can always recede along that cell's normal.
  // Any: by a neighbour's bound as well, the fallback.
  float proof_own = t > 0.0f ? t : -1.0f; // entering from outside the grid is entering from beyond the band
  float proof = proof_own;
  const auto last_proof = [&] { return std::max(proof_own >= 0.0f ? proof_own : proof, 0.0f); };
  for (int n = 0; n < max_samples; ++n) {
    if (t >= t_end) return {};
    const Vec3f p = a + d * t;
    Sample s = n == 0 && t == 0.0f && first != nullptr ? *first : planeAt(field, p);
    if (s.status == SampleStatus::kNoField) { // rounding at a face of the grid
      t += nudge;
      continue;
    }
    ViewInternals::OtherPlane other;
    CellPlan plan = planCell(g, inv_h, a, d, t, t_end, len, s, other, reach, margin, proof_level);
    if (plan.verdict == Verdict::kStops || plan.verdict == Verdict::kNothing) {
      // Beside an edge the voxel's plane may be the other face's, far below the truth here, and beside a
      // concave crease it is lowered for the other face's sake: its second bound, where the file has
      // one, may read higher and prove more (docs/FORMAT.md §5.5).
      ViewInternals::OtherPlane second_other;
      const Sample second = ViewInternals::secondBound(field, p, s, &second_other);
      if (second.distance > s.distance) {
        s = second, other = second_other;
        plan = planCell(g, inv_h, a, d, t, t_end, len, s, other, reach, margin, proof_level);
      }
    }
    const float q = plan.q, rate = plan.rate;
    if (q >= proof_level) proof = proof_own = t;
    float clear = plan.clear;
    if (plan.verdict == Verdict::kCovers) { // one ball covers the rest: the end must be provable too
      if (clear - (t_end - t) * len >= roomy) return {};
      const Vec3f end = a + d * t_end;
      if (provable(field, reach, proof_level, end, planeAt(field, end))) return {};
      // Clear, but the next step could not prove the end outside again (beside an edge the planes
      // cannot resolve): turn back from the last point it can.
      return stopAt(WalkStop::kReverse, last_proof(), back);
    }
    if (plan.verdict == Verdict::kFar) {
      t += clear / len;
      continue;
    }
    if (plan.verdict == Verdict::kStops) return stopAt(WalkStop::kPlane, plan.hit, plan.normal);
    if (plan.verdict == Verdict::kToWall) {
      // The plane proves every point up to the wall; the ball may reach further.
      proof = proof_own = std::min(plan.exit - nudge, t_end);
      if (plan.exit >= t_end) return {};
      t = std::max(plan.exit + nudge, t + clear / len);
      continue;
    }
    // This cell's plane cannot clear the way: ask the cells around the point.
    // At the start, the caller's bound when it has one: the same numbers.
    const bool given = n == 0 && t == 0.0f && start_bound != nullptr;
    NeighbourPoints taken;
    float taken_terms[NeighbourPoints::kPadded];
    const float bound = given ? start_bound->bound : neighbourBound(field, reach, p, &taken, taken_terms);
    const NeighbourPoints& around = given ? start_bound->points : taken;
    const float* terms = given ? start_bound->terms : taken_terms;
    if (bound >= proof_level) proof = t;
    clear = bound - margin;
    if (clear > 0.0f) { // the bound's ball, or the sliding plane of the neighbour that gave it
      t = std::max(t + clear / len, slideEnd(field, around, terms, bound, margin, d, t));
      continue;
    }
    if (bound >= proof_level) {
      // Proven outside but cramped, as beside an edge: two balls, here and at the end, may still
      // cover the rest (a particle leaving the surface).
      const Vec3f end = a + d * t_end;
      if (bound + fieldBound(field, reach, end) - 2.0f * margin >= (t_end - t) * len) return {};
    }
    if (proof < 0.0f) {
      // Never proven outside. A far inside voxel's centre is deep inside for sure: nothing to protect.
      // Anywhere else the point may be just outside an edge the planes cannot resolve, so it stays.
      if (s.status == SampleStatus::kFarInside) return {};
      proof = t;
    }
    // A plane that reads >= 0 here and falls along the motion is what blocks: bounce off it. Below
    // zero the plane may be a loose one (the face beside an edge), and its normal no guide: go back.
    return rate < 0.0f && q >= proof_level ? stopAt(WalkStop::kPlane, last_proof(), s.normal)
                                           : stopAt(WalkStop::kReverse, last_proof(), back);
  }
  return t >= t_end ? WalkResult{} : stopAt(WalkStop::kStall, last_proof(), back);
}

} // namespace dng
