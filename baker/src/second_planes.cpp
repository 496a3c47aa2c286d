// Second bounds beside edges and creases (docs/FORMAT.md §5.5), for the voxels whose own conservative
// plane (conservative_planes.cpp) leaves points of their cell unproven.
//
// Beside a convex edge a voxel whose centre is nearest the face A carries A's plane, which reads far
// below the truth (below zero) just outside the face B in the same cell. The plane of a neighbour
// nearest B reads right there, and the larger of two lower bounds is one: the second bound is that
// plane. Beside a concave crease the voxel's own plane had to come down for the face B's sake, by up to
// a voxel, so points a little outside A read below zero; the distance there is the smaller of the
// distances to A and to B, and so the smaller of A's plane (raised back) and B's bounds it: the second
// bound is that pair.
//
// Each candidate is made a bound by an exact test against the triangles, not by samples (on a curved
// open sheet samples let a neighbour's plane rise 0.13 voxel above the distance beside the sheet's thin
// edge). For a plane P with a unit normal and any surface point y, |p - y| >= n . (p - y) = P(p) - P(y):
// if no surface point within P(p) of p rises above the plane (P(y) <= 0), the unsigned distance at p is
// at least P(p). For a pair, if every surface point y near the cell lies below one of the two planes,
// |p - y| is at least the smaller of P_A(p) and P_B(p). Lowering the plane (or both planes of a pair) by
// the most the surface near the cell rises above it makes that true for every point of the cell. The
// region where the lowered bound is positive, within that neighbourhood, then holds no surface, so it
// is all outside or all inside a solid (whose inside changes only across its surface): a voxel centre
// known to be outside, in that region, says which.
#include "conservative_planes.h"
#include "dng/format/limits.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dng {
namespace baker {

namespace {

// A second bound is worth keeping for the clearance it adds up to this far from the surface, in voxels:
// beyond it the first plane's balls already cover a design-speed step.
constexpr float kUsefulClearanceVoxels = 1.0f;
// Less added clearance than this, summed over a cell's 27 points, in voxels, is not worth a record (nor
// the test against the triangles: 0.05 and 2.5 degrees below gave the bunny at resolution 128 14 times
// as many planes and doubled its bake time, and proved no more of fandisk's unproven points).
constexpr float kMinGainVoxels = 0.3f;
// Neighbours whose normals are within 10 degrees of the voxel's give nearly its own plane.
constexpr float kSameNormalCosine = 0.985f;
// Candidates tested against the triangles, of each kind, the best by their gain before lowering.
constexpr int kCandidates = 3;
// A pair is worth trying where the voxel's own plane came down at least this far, in voxels.
constexpr float kPairLoweringVoxels = 0.05f;
// Beyond the exact test, for float rounding in it: voxels.
constexpr float kRoundingVoxels = 1e-4f;

constexpr float kNone = -std::numeric_limits<float>::infinity();

struct PlaneAtCentre {
  float d; // reading at the voxel's centre
  Vec3f n;
  float at(Vec3f offset) const { return d + dot(n, offset); }
};

// A second bound: one plane, or with `pair` the smaller of the voxel's own plane raised to `a` and `b`.
struct Bound {
  PlaneAtCentre a{kNone, {}}, b{kNone, {}};
  bool pair = false;
  float at(Vec3f offset) const { return pair ? std::min(a.at(offset), b.at(offset)) : b.at(offset); }
  bool valid() const { return std::isfinite(b.d); }
};

// The cell's 27 points (the centre, the faces', edges' and corners' centres), as offsets from its centre.
Vec3f cellPoint(int o, float h) {
  return Vec3f{float(o % 3 - 1), float((o / 3) % 3 - 1), float(o / 9 - 1)} * (0.5f * h);
}

// What `bound` adds to `first` over the cell: at its 27 points, the clearance the larger of the two
// proves beyond the first, counted up to `useful`.
float gain(const PlaneAtCentre& first, const Bound& bound, float h, float useful) {
  float sum = 0.0f;
  for (int o = 0; o < 27; ++o) {
    const Vec3f s = cellPoint(o, h);
    sum += std::max(0.0f, std::min(bound.at(s), useful) - std::max(first.at(s), 0.0f));
  }
  return sum;
}

// The convex polygon poly[0..count) clipped to the half-space dot(n, y) <= limit (Sutherland-Hodgman),
// in place; returns the new count (at most count + 1).
int clipToHalfSpace(Vec3f* poly, int count, Vec3f n, float limit) {
  Vec3f kept[12];
  int out = 0;
  for (int k = 0; k < count; ++k) {
    const Vec3f p = poly[k], q = poly[(k + 1) % count];
    const float fp = dot(n, p) - limit, fq = dot(n, q) - limit;
    if (fp <= 0.0f) kept[out++] = p;
    if ((fp < 0.0f && fq > 0.0f) || (fp > 0.0f && fq < 0.0f)) kept[out++] = p + (q - p) * (fp / (fp - fq));
  }
  for (int k = 0; k < out; ++k)
    poly[k] = kept[k];
  return out;
}

// The highest `plane` (anchored at `centre`) reads on the polygon: a linear function peaks at a vertex.
float highestOn(const Vec3f* poly, int count, Vec3f centre, const PlaneAtCentre& plane) {
  float highest = kNone;
  for (int k = 0; k < count; ++k)
    highest = std::max(highest, plane.at(poly[k] - centre));
  return highest;
}

// The highest `bound` reads at triangle t's corners (for a pair, the smaller of its planes' highest):
// at least what it reads anywhere on the triangle.
float cornerPeak(const TriangleSoup& soup, std::uint32_t t, Vec3f centre, const Bound& bound) {
  float a = kNone, b = kNone;
  for (int k = 0; k < 3; ++k) {
    const Vec3f offset = soup.vertices[soup.triangles[t][k]] - centre;
    b = std::max(b, bound.b.at(offset));
    if (bound.pair) a = std::max(a, bound.a.at(offset));
  }
  return bound.pair ? std::min(a, b) : b;
}

// The most the surface within `radius` of `centre` rises above `bound`, or 0: per triangle, the highest
// reading over its part inside the box around the ball (for a pair, the smaller plane's: over the part
// where A lies below B, A's highest, and B's over the rest), never more than the bound reads anywhere
// in the ball.
float surfaceRise(const PlaneMesh& mesh, Vec3f centre, const Bound& bound, float radius) {
  float rise = 0.0f;
  const float top = bound.at({}) + radius;
  // Most triangles lie below the bound: if none of a triangle's corners reads above the rise so far, no
  // part of it does (a plane peaks at a corner, and a pair's smaller plane below either's peak). Asked
  // before the exact distance: a coarse grid's cell is near thousands of triangles.
  const auto may_rise = [&](std::uint32_t t) { return cornerPeak(*mesh.soup, t, centre, bound) > rise; };
  mesh.index->forEachTriangleNear(centre, radius, may_rise, [&](std::uint32_t t) {
    Vec3f poly[12];
    // Slightly larger than the ball, so rounding in the clip cannot drop a point inside it.
    const int count = clipTriangleToBox(*mesh.soup, t, centre, radius * (1.0f + 1e-5f), poly);
    float highest = count == 0 ? top : kNone; // an empty clip cannot happen for a triangle this near: never trust it
    if (count > 0 && !bound.pair) highest = highestOn(poly, count, centre, bound.b);
    if (count > 0 && bound.pair) {
      // A - B = d_a - d_b + (n_a - n_b) . (y - centre), clipped where it is <= 0 (A the smaller) and >= 0.
      const Vec3f w = bound.a.n - bound.b.n;
      const float limit = bound.b.d - bound.a.d + dot(w, centre);
      Vec3f below[12], above[12];
      std::copy(poly, poly + count, below);
      std::copy(poly, poly + count, above);
      const int nb = clipToHalfSpace(below, count, w, limit);
      const int na = clipToHalfSpace(above, count, w * -1.0f, -limit);
      highest = std::max(highestOn(below, nb, centre, bound.a), highestOn(above, na, centre, bound.b));
    }
    rise = std::max(rise, std::min(highest, top));
  });
  return rise;
}

// `bound` made a lower bound over the cell centred at `centre` (the test at the top of this file):
// lowered by the surface's rise, and kept only when `outside` (an offset from the centre, a point known
// to be outside: the centre of a voxel whose distance is positive) still reads positive.
Bound lowerBoundOverCell(const PlaneMesh& mesh, Vec3f centre, Bound bound, Vec3f outside, float h) {
  const auto highest_in_cell = [h](const PlaneAtCentre& p) {
    return p.d + (std::fabs(p.n.x) + std::fabs(p.n.y) + std::fabs(p.n.z)) * 0.5f * h;
  };
  const float highest =
      bound.pair ? std::min(highest_in_cell(bound.a), highest_in_cell(bound.b)) : highest_in_cell(bound.b);
  if (!(highest > 0.0f)) return Bound{};
  // Every surface point within the bound's reading of some cell point, and the outside point.
  const float radius = std::max(highest + format::kHalfCubeDiagonal * h, length(outside));
  const float lowering =
      surfaceRise(mesh, centre, bound, radius) + kRoundingVoxels * h + 4e-7f * (std::fabs(bound.b.d) + radius);
  bound.a.d -= lowering, bound.b.d -= lowering;
  return bound.at(outside) > 0.0f ? bound : Bound{};
}

// A neighbour of the voxel whose plane may serve: its plane read at the voxel's centre, the point the
// bound's region must hold to show it outside, and the bound's gain before lowering.
struct Neighbour {
  PlaneAtCentre plane;
  Vec3f outside; // from the voxel's centre: the neighbour's centre (a plane alone), or the voxel's (a pair)
  float raw;
};

// The best of `candidates` (up to kCandidates, by raw gain) once proven, if it beats `best_gain`.
template <class MakeBound>
void tryBest(Neighbour* candidates, int count, const PlaneMesh& mesh, Vec3f centre, const PlaneAtCentre& first, float h,
             MakeBound make, float* io_best_gain, Bound* io_best) {
  std::sort(candidates, candidates + count, [](const Neighbour& x, const Neighbour& y) { return x.raw > y.raw; });
  const float useful = kUsefulClearanceVoxels * h;
  for (int c = 0; c < std::min(count, kCandidates); ++c) {
    if (candidates[c].raw <= *io_best_gain) break; // sorted: no later one can do better
    const Bound proven = lowerBoundOverCell(mesh, centre, make(candidates[c]), candidates[c].outside, h);
    if (!proven.valid()) continue;
    const float g = gain(first, proven, h, useful);
    if (g > *io_best_gain) *io_best_gain = g, *io_best = proven;
  }
}

// Voxel (x, y, z)'s best second bound, given its own plane before (`exact`) and after the lowering.
Bound secondBound(const Neighbourhood& hood, const PlaneMesh& mesh, int x, int y, int z, Vec3f centre,
                  const PlaneAtCentre& exact, const PlaneAtCentre& first, const format::GridGeometry& g) {
  const float h = g.voxel_size, useful = kUsefulClearanceVoxels * h;
  // A pair needs the voxel's own centre outside: it shows the pair's region is.
  const bool pairs = exact.d - first.d >= kPairLoweringVoxels * h && exact.d > 0.0f;
  Neighbour single[26], paired[26];
  int count = 0;
  for (int o = 0; o < 27; ++o) {
    const int ox = o % 3 - 1, oy = (o / 3) % 3 - 1, oz = o / 9 - 1;
    if (o == 13) continue; // the voxel itself
    const int at = Neighbourhood::at(x + ox, y + oy, z + oz);
    const float dy = hood.distance[at];
    const Vec3f ny = hood.normal[at];
    // Outside neighbours only: each one's centre is the bound's outside point.
    if (!(std::fabs(dy) < g.band) || !(dy > 0.0f) || dot(ny, ny) == 0.0f || dot(ny, first.n) > kSameNormalCosine)
      continue;
    const Vec3f offset = Vec3f{float(ox), float(oy), float(oz)} * h;
    const PlaneAtCentre plane{dy - dot(ny, offset), ny}; // read at this voxel's centre
    Bound alone;
    alone.b = plane;
    single[count] = {plane, offset, gain(first, alone, h, useful)};
    const Bound pair{exact, plane, true};
    paired[count] = {plane, Vec3f{}, pairs ? gain(first, pair, h, useful) : 0.0f};
    ++count;
  }
  float best_gain = kMinGainVoxels * h;
  Bound best;
  tryBest(
      single, count, mesh, centre, first, h,
      [](const Neighbour& n) {
        return Bound{{kNone, {}}, n.plane, false};
      },
      &best_gain, &best);
  if (pairs)
    tryBest(
        paired, count, mesh, centre, first, h,
        [&](const Neighbour& n) {
          return Bound{exact, n.plane, true};
        },
        &best_gain, &best);
  return best;
}

} // namespace

int clipTriangleToBox(const TriangleSoup& soup, std::uint32_t t, Vec3f centre, float half, Vec3f* poly) {
  const auto& tri = soup.triangles[t];
  for (int k = 0; k < 3; ++k)
    poly[k] = soup.vertices[tri[k]];
  int count = 3;
  for (int axis = 0; axis < 3 && count > 0; ++axis) {
    const Vec3f e{axis == 0 ? 1.0f : 0.0f, axis == 1 ? 1.0f : 0.0f, axis == 2 ? 1.0f : 0.0f};
    count = clipToHalfSpace(poly, count, e, component(centre, axis) + half);
    if (count > 0) count = clipToHalfSpace(poly, count, e * -1.0f, half - component(centre, axis));
  }
  return count;
}

void secondBoundsOfBlock(const Neighbourhood& hood, const PlaneMesh& mesh, const format::GridGeometry& g,
                         const float* lowered, const SecondPlaneBlock& out) {
  const float h = g.voxel_size;
  for (int x = 0; x < VoxelBlock::kDim; ++x)
    for (int y = 0; y < VoxelBlock::kDim; ++y)
      for (int z = 0; z < VoxelBlock::kDim; ++z) {
        const int at = Neighbourhood::at(x, y, z), v = VoxelBlock::offset(x, y, z);
        const PlaneAtCentre exact{hood.distance[at], hood.normal[at]};
        const PlaneAtCentre first{exact.d - lowered[v], exact.n};
        const float reach = (std::fabs(first.n.x) + std::fabs(first.n.y) + std::fabs(first.n.z)) * 0.5f * h;
        // Band voxels whose cell reaches outside and lies within the useful clearance of the surface.
        if (!(std::fabs(exact.d) < g.band) || exact.d < -format::kHalfCubeDiagonal * h ||
            first.d - reach >= kUsefulClearanceVoxels * h)
          continue;
        const std::int64_t i = out.origin[0] + x, j = out.origin[1] + y, k = out.origin[2] + z;
        if (i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) continue; // past the grid's edge
        const Vec3f centre = g.voxelCentre(std::uint32_t(i), std::uint32_t(j), std::uint32_t(k));
        const Bound bound = secondBound(hood, mesh, x, y, z, centre, exact, first, g);
        if (!bound.valid()) continue;
        out.distance[v] = bound.b.d;
        out.setNormal(v, bound.b.n);
        // A pair's own plane as the raise of the lowered one: the same normal, a constant offset (at least
        // 0: a pair with the lowered plane itself still bounds the distance).
        out.raise[v] = bound.pair ? std::max(bound.a.d - first.d, 0.0f) : -1.0f;
      }
}

} // namespace baker
} // namespace dng
