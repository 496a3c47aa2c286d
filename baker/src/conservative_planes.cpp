// Conservative planes: every band voxel's plane lowered until it is a lower bound of the true signed
// distance over the voxel's whole cell, so that the runtime can prove a path clear (docs/DESIGN.md §10;
// docs/FORMAT.md, "conservative planes").
//
// A voxel (distance d, normal n, centre c) answers d + n . (p - c) anywhere in its cell (paper §3.1's
// plane refinement). That overestimates the distance wherever the true distance D bends below the
// plane: outside a concave crease the plane extends one face past the other, and near a medial axis
// it extends the nearer side. The error f = plane - D is bounded per cell:
//   - where D is a minimum of planes (creases, medial axes) f is convex, so on the cell it is at most
//     the trilinear blend of f at the 27 voxel centres around it (exact distances from the band);
//   - where D bends upwards (convex edges, curved faces) f is concave and at most its tangent at c,
//     (n - grad D) . (p - c), which is zero: every mode's planes carry the distance's own normal (the
//     blurred modes keep theirs as shading normals beside them, docs/FORMAT.md §5.4). A blurred
//     normal's plane would need a lowering of up to |n - grad D|_1 h / 2 here, and beside sharp edges
//     that left particles no provable room (measured: docs/CHANGELOG.md, format 1.3).
// The plane is lowered by the bound plus a small allowance, never raised.
#include "dng/format/limits.h"
#include "parallel_blocks.h"
#include "stages.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dng {
namespace baker {

namespace {

// For what the 27 samples leave out in mixed cases, in voxels. Measured overshoots left after it stay
// below 0.01 voxel (tests/bake_test.cpp), which the runtime's 0.06-voxel margin absorbs.
constexpr float kAllowanceVoxels = 0.005f;
// Where the bounds found any excess the surface bends within a voxel (a crease, a medial axis), and
// the 27 samples miss more there: measured on fandisk's sharp creases.
constexpr float kCreaseAllowanceVoxels = 0.03f;

constexpr int kHalo = VoxelBlock::kDim + 2; // a block and one voxel around it

// The block's voxels and their neighbours, read once: distances clamped to +-band, normals.
struct Neighbourhood {
  float distance[kHalo * kHalo * kHalo];
  Vec3f normal[kHalo * kHalo * kHalo];
  static int at(int x, int y, int z) { return ((z + 1) * kHalo + (y + 1)) * kHalo + (x + 1); }
};

// Reads the halo box; voxels past the grid's edge lie beyond the padding, so they are far outside.
void readNeighbourhood(const BandGrid& band, const VoxelBlock& block, Neighbourhood* out) {
  const format::GridGeometry& g = band.grid();
  std::fill(std::begin(out->distance), std::end(out->distance), g.band);
  std::fill(std::begin(out->normal), std::end(out->normal), Vec3f{});
  format::VoxelBox box;
  int lo[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(block.origin[a] - 1, 0);
    box.lo[a] = std::uint32_t(lo[a]);
    box.hi[a] = std::uint32_t(std::min<std::int64_t>(block.origin[a] + VoxelBlock::kDim + 1, g.dims[a]));
  }
  std::vector<float> d(box.count());
  std::vector<Vec3f> n(box.count());
  band.read(box, d.data(), n.data());
  std::size_t v = 0;
  for (std::uint32_t k = box.lo[2]; k < box.hi[2]; ++k)
    for (std::uint32_t j = box.lo[1]; j < box.hi[1]; ++j)
      for (std::uint32_t i = box.lo[0]; i < box.hi[0]; ++i, ++v) {
        const int h = Neighbourhood::at(int(i) - block.origin[0], int(j) - block.origin[1], int(k) - block.origin[2]);
        out->distance[h] = std::clamp(d[v], -g.band, g.band);
        out->normal[h] = n[v];
      }
}

// The bound on plane - D over the cell of voxel (x, y, z) of the block (see the top of the file), for
// the plane reading `d` at the voxel's centre with normal `n`.
float planeExcess(const Neighbourhood& hood, int x, int y, int z, float d, Vec3f n, float band, float h) {
  // f at the 27 centres; far inside neighbours bound nothing (D could be anything below -band).
  float f[27];
  bool known[27];
  for (int o = 0; o < 27; ++o) {
    const int ox = o % 3 - 1, oy = (o / 3) % 3 - 1, oz = o / 9 - 1;
    const float dn = hood.distance[Neighbourhood::at(x + ox, y + oy, z + oz)];
    const float plane = d + h * (n.x * float(ox) + n.y * float(oy) + n.z * float(oz));
    known[o] = dn > -band;
    // Beyond the band the distance is only known to be >= band; the runtime never takes more than
    // the guaranteed reach (< band) from a point near there, so the plane may read up to band.
    f[o] = dn >= band ? std::min(plane - band, 0.0f) : plane - dn;
  }
  float excess = 0.0f;
  // The cell's 27 points c + (h/2) s, s in {-1, 0, 1}^3: blend of the centres c + h t, t_a in {0, s_a}.
  for (int o = 0; o < 27; ++o) {
    const int s[3] = {o % 3 - 1, (o / 3) % 3 - 1, o / 9 - 1};
    float sum = 0.0f;
    int count = 0;
    for (int corner = 0; corner < 8; ++corner) {
      int t[3];
      bool used = true;
      for (int a = 0; a < 3; ++a) {
        t[a] = (corner >> a) & 1 ? s[a] : 0;
        used = used && ((corner >> a) & 1 ? s[a] != 0 : true);
      }
      if (!used) continue;
      const int lattice = (t[0] + 1) + 3 * (t[1] + 1) + 9 * (t[2] + 1);
      if (!known[lattice]) continue;
      sum += f[lattice];
      ++count;
    }
    if (count > 0) excess = std::max(excess, sum / float(count));
  }
  return excess;
}

// The lowering for a plane whose excess over a cell is bounded by `excess`: the bound and an allowance.
float lowering(float excess, float h) {
  return excess + (excess > 1e-3f * h ? kCreaseAllowanceVoxels : kAllowanceVoxels) * h;
}

// How far to lower each voxel of one block (VoxelBlock order). A plane that cannot reach zero anywhere
// in its cell (d + |n|_1 h/2 < 0) promises nothing and is left alone, so deep inside stays exact.
void lowerBlock(const Neighbourhood& hood, const format::GridGeometry& g, float* out) {
  const float h = g.voxel_size;
  for (int x = 0; x < VoxelBlock::kDim; ++x)
    for (int y = 0; y < VoxelBlock::kDim; ++y)
      for (int z = 0; z < VoxelBlock::kDim; ++z) {
        const int at = Neighbourhood::at(x, y, z);
        const float d = hood.distance[at];
        const Vec3f n = hood.normal[at];
        if (!(std::fabs(d) < g.band) || d + (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z)) * 0.5f * h < 0.0f)
          continue;
        out[VoxelBlock::offset(x, y, z)] = lowering(planeExcess(hood, x, y, z, d, n, g.band, h), h);
      }
}

// ---- Second planes (docs/FORMAT.md §5.5) ----
//
// Beside a convex edge the distance is not one plane over a cell: a voxel whose centre is nearest the
// face A carries A's plane, which reads far below the truth (below zero) just outside the face B in the
// same cell, so a particle there cannot be proven outside. The plane of a neighbour nearest B reads
// right there, and the larger of two lower bounds is one. Each voxel gets the neighbour plane that adds
// the most provable clearance over its cell, made a lower bound by an exact test against the triangles
// rather than the samples above (on a curved open sheet those let a neighbour's plane rise 0.13 voxel
// above the distance, beside the sheet's thin edge):
//   for a plane P with a unit normal and any surface point y, |p - y| >= n . (p - y) = P(p) - P(y), so
//   if no surface point within P(p) of p lies above the plane (P(y) <= 0), the unsigned distance at p
//   is at least P(p). Lowering P by the most the surface near the cell rises above it makes that true
//   for every point of the cell. The region where the lowered plane is positive, within that
//   neighbourhood, then holds no surface, so it is all outside or all inside a solid (whose inside
//   changes only across its surface): the neighbour's own centre, outside and in that region, says
//   which.

// A second plane is worth keeping for the clearance it adds up to this far from the surface, in voxels:
// beyond it the first plane's balls already cover a design-speed step.
constexpr float kUsefulClearanceVoxels = 1.0f;
// Less added clearance than this, summed over a cell's 27 points, in voxels, is not worth a word (nor
// the test against the triangles: 0.05 and 2.5 degrees below gave the bunny at resolution 128 14 times
// as many planes and doubled its bake time, and proved no more of fandisk's unproven points).
constexpr float kMinGainVoxels = 0.3f;
// Neighbours whose normals are within 10 degrees of the voxel's give nearly its own plane.
constexpr float kSameNormalCosine = 0.985f;
// Candidates tested against the triangles, the best by their gain before lowering.
constexpr int kCandidates = 3;
// Beyond the exact test, for float rounding in it: voxels.
constexpr float kRoundingVoxels = 1e-4f;

struct PlaneAtCentre {
  float d; // reading at the voxel's centre
  Vec3f n;
};

// The mesh the second planes are tested against.
struct SecondPlaneMesh {
  const TriangleSoup* soup;
  const ClosestPointIndex* index;
};

// What `candidate` adds to `first` over the cell: at its 27 points (the centre, the faces', edges' and
// corners' centres), the clearance the larger plane proves beyond the first, counted up to `useful`.
float gain(const PlaneAtCentre& first, const PlaneAtCentre& candidate, float h, float useful) {
  float sum = 0.0f;
  for (int o = 0; o < 27; ++o) {
    const Vec3f s{0.5f * h * float(o % 3 - 1), 0.5f * h * float((o / 3) % 3 - 1), 0.5f * h * float(o / 9 - 1)};
    const float p1 = first.d + dot(first.n, s), p2 = candidate.d + dot(candidate.n, s);
    sum += std::max(0.0f, std::min(p2, useful) - std::max(p1, 0.0f));
  }
  return sum;
}

// Triangle abc clipped to the box centre +- half (Sutherland-Hodgman, one face of the box at a time):
// the vertices of what is left, at most 9, written to out; returns how many.
int clipToBox(Vec3f a, Vec3f b, Vec3f c, Vec3f centre, float half, Vec3f* out) {
  Vec3f poly[9] = {a, b, c}, next[9];
  int count = 3;
  for (int face = 0; face < 6 && count > 0; ++face) {
    const int axis = face / 2;
    const float sign = face % 2 ? -1.0f : 1.0f;
    const float limit = sign * component(centre, axis) + half; // keep sign * x <= limit
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      const Vec3f p = poly[k], q = poly[(k + 1) % count];
      const float fp = sign * component(p, axis) - limit, fq = sign * component(q, axis) - limit;
      if (fp <= 0.0f) next[kept++] = p;
      if ((fp < 0.0f && fq > 0.0f) || (fp > 0.0f && fq < 0.0f)) next[kept++] = p + (q - p) * (fp / (fp - fq));
    }
    count = kept;
    for (int k = 0; k < count; ++k)
      poly[k] = next[k];
  }
  for (int k = 0; k < count; ++k)
    out[k] = poly[k];
  return count;
}

// The most the surface within `radius` of `centre` rises above `plane` (anchored at `centre`), or 0: per
// triangle, the highest reading over its part inside the box around the ball (a linear function peaks
// at a vertex of the clipped polygon), never more than the plane reads anywhere in the ball.
float surfaceRise(const SecondPlaneMesh& mesh, Vec3f centre, const PlaneAtCentre& plane, float radius) {
  float rise = 0.0f;
  const float top = plane.d + radius;
  mesh.index->forEachTriangleNear(centre, radius, [&](std::uint32_t t) {
    const auto& tri = mesh.soup->triangles[t];
    Vec3f clipped[9];
    // Slightly larger than the ball, so rounding in the clip cannot drop a point inside it.
    const int n = clipToBox(mesh.soup->vertices[tri[0]], mesh.soup->vertices[tri[1]], mesh.soup->vertices[tri[2]],
                            centre, radius * (1.0f + 1e-5f), clipped);
    float highest = -std::numeric_limits<float>::infinity();
    for (int k = 0; k < n; ++k)
      highest = std::max(highest, plane.d + dot(plane.n, clipped[k] - centre));
    if (n == 0) highest = top; // cannot happen for a triangle within the radius; never trust an empty clip
    rise = std::max(rise, std::min(highest, top));
  });
  return rise;
}

// Neighbour (ox, oy, oz)'s plane made a lower bound over the cell centred at `centre` (the test at the
// top of this part), or d = -inf when it cannot be: the neighbour is not outside, or the lowered plane
// no longer reads positive at its centre.
PlaneAtCentre lowerBoundOverCell(const SecondPlaneMesh& mesh, Vec3f centre, const PlaneAtCentre& plane,
                                 float neighbour_d, float neighbour_gap, float h) {
  const PlaneAtCentre none{-std::numeric_limits<float>::infinity(), Vec3f{}};
  const float highest_in_cell =
      plane.d + (std::fabs(plane.n.x) + std::fabs(plane.n.y) + std::fabs(plane.n.z)) * 0.5f * h;
  if (!(neighbour_d > 0.0f) || !(highest_in_cell > 0.0f)) return none;
  // Every surface point within the plane's reading of some cell point, and the neighbour's centre.
  const float radius = std::max(highest_in_cell + format::kHalfCubeDiagonal * h, neighbour_gap);
  const float lowering =
      surfaceRise(mesh, centre, plane, radius) + kRoundingVoxels * h + 4e-7f * (std::fabs(plane.d) + radius);
  if (!(neighbour_d - lowering > 0.0f)) return none;
  return {plane.d - lowering, plane.n};
}

// Voxel (x, y, z)'s best second plane, given its own (already lowered) plane; d = -inf when none is worth it.
PlaneAtCentre secondPlane(const Neighbourhood& hood, const SecondPlaneMesh& mesh, int x, int y, int z, Vec3f centre,
                          const PlaneAtCentre& first, const format::GridGeometry& g) {
  const float h = g.voxel_size, useful = kUsefulClearanceVoxels * h;
  PlaneAtCentre best{-std::numeric_limits<float>::infinity(), Vec3f{}};
  // The best few neighbours' planes by gain before lowering; lowering only ever takes gain away.
  PlaneAtCentre candidate[kCandidates];
  float raw[kCandidates] = {}, source_d[kCandidates] = {}, gap[kCandidates] = {};
  int count = 0;
  for (int o = 0; o < 27; ++o) {
    const int ox = o % 3 - 1, oy = (o / 3) % 3 - 1, oz = o / 9 - 1;
    if (o == 13) continue; // the voxel itself
    const int at = Neighbourhood::at(x + ox, y + oy, z + oz);
    const float dy = hood.distance[at];
    const Vec3f ny = hood.normal[at];
    if (!(std::fabs(dy) < g.band) || !(dy > 0.0f) || dot(ny, ny) == 0.0f || dot(ny, first.n) > kSameNormalCosine)
      continue;
    // The neighbour's plane read at this voxel's centre, h (ox, oy, oz) away from its own.
    const PlaneAtCentre plane{dy - h * (ny.x * float(ox) + ny.y * float(oy) + ny.z * float(oz)), ny};
    const float g_raw = gain(first, plane, h, useful);
    int slot = count < kCandidates ? count++ : kCandidates - 1;
    if (slot == kCandidates - 1 && count == kCandidates && g_raw <= raw[slot]) continue;
    for (; slot > 0 && raw[slot - 1] < g_raw; --slot)
      raw[slot] = raw[slot - 1], candidate[slot] = candidate[slot - 1], source_d[slot] = source_d[slot - 1],
      gap[slot] = gap[slot - 1];
    raw[slot] = g_raw, candidate[slot] = plane, source_d[slot] = dy,
    gap[slot] = h * std::sqrt(float(ox * ox + oy * oy + oz * oz));
  }
  float best_gain = kMinGainVoxels * h;
  for (int c = 0; c < count; ++c) {
    if (raw[c] <= best_gain) break; // sorted: no later one can do better
    const PlaneAtCentre lowered = lowerBoundOverCell(mesh, centre, candidate[c], source_d[c], gap[c], h);
    if (!std::isfinite(lowered.d)) continue;
    const float g_lowered = gain(first, lowered, h, useful);
    if (g_lowered > best_gain) best_gain = g_lowered, best = lowered;
  }
  return best;
}

// The second planes of one block's voxels (VoxelBlock order), given the lowerings of their own planes:
// for band voxels whose cell reaches outside and lies within the useful clearance of the surface.
void secondPlanesOfBlock(const Neighbourhood& hood, const SecondPlaneMesh& mesh, const format::GridGeometry& g,
                         const float* lowered, const VoxelBlock& out) {
  const float h = g.voxel_size;
  for (int x = 0; x < VoxelBlock::kDim; ++x)
    for (int y = 0; y < VoxelBlock::kDim; ++y)
      for (int z = 0; z < VoxelBlock::kDim; ++z) {
        const int at = Neighbourhood::at(x, y, z), v = VoxelBlock::offset(x, y, z);
        const PlaneAtCentre first{hood.distance[at] - lowered[v], hood.normal[at]};
        const float reach = (std::fabs(first.n.x) + std::fabs(first.n.y) + std::fabs(first.n.z)) * 0.5f * h;
        if (!(std::fabs(hood.distance[at]) < g.band) || hood.distance[at] < -format::kHalfCubeDiagonal * h ||
            first.d - reach >= kUsefulClearanceVoxels * h)
          continue;
        const std::int64_t i = out.origin[0] + x, j = out.origin[1] + y, k = out.origin[2] + z;
        if (i >= g.dims[0] || j >= g.dims[1] || k >= g.dims[2]) continue; // past the grid's edge
        const Vec3f centre = g.voxelCentre(std::uint32_t(i), std::uint32_t(j), std::uint32_t(k));
        const PlaneAtCentre second = secondPlane(hood, mesh, x, y, z, centre, first, g);
        out.distance[v] = second.d;
        out.setNormal(v, second.n);
      }
}

} // namespace

BakeStatus makePlanesConservative(bool keep_accurate, const TriangleSoup* solid, ProgressFn progress,
                                  void* progress_user, BandGrid* io) {
  const format::GridGeometry& g = io->grid();
  const std::vector<VoxelBlock> blocks = io->blocks();
  const bool second_planes = solid != nullptr;
  ClosestPointIndex index;
  if (second_planes) {
    const BakeStatus built = index.build(*solid);
    if (!built.ok()) return built;
    io->startSecondPlanes();
  }
  const SecondPlaneMesh mesh{solid, &index};
  const std::vector<VoxelBlock> seconds = second_planes ? io->secondPlaneBlocks() : std::vector<VoxelBlock>();
  std::vector<float> lowered(blocks.size() * VoxelBlock::kVoxels, 0.0f);
  const bool finished =
      forEachBlockInParallel(blocks.size(), "conservative", progress, progress_user, [&](std::size_t b) {
        Neighbourhood hood; // readNeighbourhood fills all of it
        readNeighbourhood(*io, blocks[b], &hood);
        lowerBlock(hood, g, &lowered[b * VoxelBlock::kVoxels]);
        if (second_planes) secondPlanesOfBlock(hood, mesh, g, &lowered[b * VoxelBlock::kVoxels], seconds[b]);
      });
  if (!finished) return BakeStatus::cancelled();
  if (keep_accurate) io->keepAccurateDistances(); // what the file's LIFT section gives back
  // Applied after every block has read its neighbours' original distances.
  // Inside, a lowered value only has to stay negative (a plane proves nothing where it reads below
  // zero), so it stops short of -band: the voxel stays in the band, as the .vdb export has it.
  const float floor_value = -0.98f * g.band; // clear of the encoders' rounding towards -band
  for (std::size_t b = 0; b < blocks.size(); ++b)
    for (int v = 0; v < VoxelBlock::kVoxels; ++v) {
      float& d = blocks[b].distance[v];
      const float lowering = lowered[b * VoxelBlock::kVoxels + v];
      if (lowering > 0.0f) d = std::max(d - lowering, std::min(d, floor_value));
    }
  io->addFlags(format::kGridFlagConservativePlanes);
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
