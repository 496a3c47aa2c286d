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
// The 27 centres miss a surface that bends two ways within about a voxel (a convex edge beside a concave
// one, as between the holes of CGAL's cheese.off, where planes read up to 0.27 voxel above the distance
// and particles cut its edges; bunny and fandisk had 0.08 at worst). So each plane is then checked
// against the triangles themselves at its cell's corners, edge and face centres, and lowered by the
// largest excess found there plus the crease allowance. The unsigned distance is what the walk's proofs
// rely on (walk.h): a point reading q > 0 has no surface within q. A sheet can still cross the cell
// between those points where the plane reads above zero (a fold of libcgal-demo's open
// mannequin-devil.off: 0.034 voxel, and a resting particle passed it), so the surface inside the cell is
// read exactly too, each triangle clipped to the cell.
#include "conservative_planes.h"
#include "dng/format/limits.h"
#include "parallel_blocks.h"

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

// Whether voxel (x, y, z) of the block carries a plane worth lowering: in the band, inside the grid, and
// able to reach zero somewhere in its cell (d + |n|_1 h/2 >= 0). Others promise nothing and are left
// alone, so deep inside stays exact.
bool lowersPlane(const Neighbourhood& hood, const format::GridGeometry& g, const VoxelBlock& block, int x, int y,
                 int z) {
  const int at = Neighbourhood::at(x, y, z);
  const float d = hood.distance[at];
  const Vec3f n = hood.normal[at];
  if (!(std::fabs(d) < g.band) || d + (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z)) * 0.5f * g.voxel_size < 0.0f)
    return false;
  return std::int64_t(block.origin[0]) + x < g.dims[0] && std::int64_t(block.origin[1]) + y < g.dims[1] &&
         std::int64_t(block.origin[2]) + z < g.dims[2];
}

// The points the check against the triangles reads: the cells' corners, edge and face centres (their
// centres never held the largest excess in measurements), on a lattice of half voxels shared between
// neighbouring cells. Point (a, b, c), each 0..2 kDim, lies at the block's first voxel centre plus
// (a - 1, b - 1, c - 1) half voxels; cell (x, y, z) holds the points 2x..2x+2 on each axis.
constexpr int kLattice = 2 * VoxelBlock::kDim + 1;
int latticeAt(int a, int b, int c) { return (c * kLattice + b) * kLattice + a; }

// A cell's point `o` (0..26, x fastest; 13 is the centre) as lattice steps from the cell's first point.
struct CellPoint {
  int a, b, c;
  Vec3f offset; // from the cell's centre
};
CellPoint cellPoint(int o, float h) {
  const int a = o % 3, b = (o / 3) % 3, c = o / 9;
  return {a, b, c, Vec3f{float(a - 1), float(b - 1), float(c - 1)} * (0.5f * h)};
}

// How far outside its cell the surface is read against a plane, in voxels (readingOnSurface).
constexpr float kSurfaceShellVoxels = 0.1f;
// Half the edge of the box readingOnSurface reads, around a cell of edge h.
float surfaceBoxHalf(float h) { return (0.5f + kSurfaceShellVoxels) * h; }

// The most a plane (reading `d` at `centre`, normal `n`) reads on the surface inside its own cell and
// within kSurfaceShellVoxels of it, as far as it reads above `floor`: exact, each triangle near the cell
// clipped to that box (a plane peaks at a vertex of the clip). Where a sheet crosses a cell between the
// lattice's points, only this sees the plane read above it. Just outside the cell it matters too: at
// the cell point nearest a surface point y, a short way off, the plane reads about P(y) and the distance
// is at most that way. Beside the rim of a hole in libcgal-demo's open elephant-with-holes.off, a rim
// 0.02 voxel outside a cell's face left its plane reading 0.088 voxel above the distance there.
float readingOnSurface(const PlaneMesh& mesh, Vec3f centre, float d, Vec3f n, float h, float floor) {
  float highest = floor;
  // A hair larger: rounding in the clip keeps every point.
  const float half = surfaceBoxHalf(h) * (1.0f + 1e-5f);
  // Most triangles lie below the plane: none of its part in the cell reads more than its corners do.
  // Asked before the exact distance: a coarse grid's cell is near thousands of triangles.
  const auto may_rise = [&](std::uint32_t t) {
    float corners = -std::numeric_limits<float>::infinity();
    for (int k = 0; k < 3; ++k)
      corners = std::max(corners, d + dot(n, mesh.soup->vertices[mesh.soup->triangles[t][std::size_t(k)]] - centre));
    return corners > highest;
  };
  mesh.index->forEachTriangleNear(centre, std::sqrt(3.0f) * half, may_rise, [&](std::uint32_t t) {
    Vec3f poly[12];
    const int count = clipTriangleToBox(*mesh.soup, t, centre, half, poly);
    for (int k = 0; k < count; ++k)
      highest = std::max(highest, d + dot(n, poly[k] - centre));
  });
  return highest;
}

// One block's planes as the check against the triangles reads them: the exact distances and normals
// (`hood`), and how far each is lowered so far (`lowered`, VoxelBlock order).
struct BlockPlanes {
  const Neighbourhood& hood;
  const format::GridGeometry& g;
  const VoxelBlock& block;
  float* lowered;
  float h = g.voxel_size;
  float slack = kAllowanceVoxels * h;
  float reach = format::guaranteedReach(g.band, h); // the most the runtime takes from a plane
  Vec3f first =
      g.voxelCentre(std::uint32_t(block.origin[0]), std::uint32_t(block.origin[1]), std::uint32_t(block.origin[2]));

  float distance(int x, int y, int z) const {
    return hood.distance[Neighbourhood::at(x, y, z)] - lowered[VoxelBlock::offset(x, y, z)];
  }
  Vec3f normal(int x, int y, int z) const { return hood.normal[Neighbourhood::at(x, y, z)]; }

  // Calls visit(x, y, z, lattice index, reading) for every point of every checked cell where the plane
  // reads above the allowance, the reading capped at the reach.
  template <class Visit> void forEachCellPoint(Visit&& visit) const {
    for (int x = 0; x < VoxelBlock::kDim; ++x)
      for (int y = 0; y < VoxelBlock::kDim; ++y)
        for (int z = 0; z < VoxelBlock::kDim; ++z) {
          if (!lowersPlane(hood, g, block, x, y, z)) continue;
          for (int o = 0; o < 27; ++o) {
            if (o == 13) continue;
            const CellPoint p = cellPoint(o, h);
            const float r = std::min(distance(x, y, z) + dot(normal(x, y, z), p.offset), reach);
            if (r > slack) visit(x, y, z, latticeAt(2 * x + p.a, 2 * y + p.b, 2 * z + p.c), r);
          }
        }
  }
};

constexpr int kLatticePoints = kLattice * kLattice * kLattice;

// The unsigned distance to the triangles at each lattice point a cell reads (infinity beyond the radius
// asked): one Embree query per point, within the largest radius any of its cells needs (a surface point
// closer than a reading, less the allowance, matters; a small radius is cheap).
void latticeDistances(const BlockPlanes& planes, const PlaneMesh& mesh, float* out) {
  float radius[kLatticePoints] = {};
  planes.forEachCellPoint([&](int, int, int, int at, float r) { radius[at] = std::max(radius[at], r - planes.slack); });
  for (int c = 0; c < kLattice; ++c)
    for (int b = 0; b < kLattice; ++b)
      for (int a = 0; a < kLattice; ++a) {
        const int at = latticeAt(a, b, c);
        if (!(radius[at] > 0.0f)) continue;
        const Vec3f p = planes.first + Vec3f{float(a - 1), float(b - 1), float(c - 1)} * (0.5f * planes.h);
        const ClosestPointIndex::Hit hit = mesh.index->query(p, radius[at]);
        out[at] = hit.found ? hit.distance : std::numeric_limits<float>::infinity();
      }
}

// Raises io_missed (VoxelBlock order) to the most each plane reads above the unsigned distance at its
// cell's points, where that is more than the allowance.
void excessAtLattice(const BlockPlanes& planes, const PlaneMesh& mesh, float* io_missed) {
  float distance[kLatticePoints];
  latticeDistances(planes, mesh, distance);
  planes.forEachCellPoint([&](int x, int y, int z, int at, float r) {
    if (!(distance[at] < r - planes.slack)) return;
    float& m = io_missed[VoxelBlock::offset(x, y, z)];
    m = std::max(m, r - distance[at]);
  });
}

// Raises io_missed to the most each plane reads on the surface in and just around its cell
// (readingOnSurface), where that is more than the allowance; only cells the surface can reach (the exact
// distance at the centre says so).
void excessOnSurface(const BlockPlanes& planes, const PlaneMesh& mesh, float* io_missed) {
  for (int x = 0; x < VoxelBlock::kDim; ++x)
    for (int y = 0; y < VoxelBlock::kDim; ++y)
      for (int z = 0; z < VoxelBlock::kDim; ++z) {
        if (!lowersPlane(planes.hood, planes.g, planes.block, x, y, z) ||
            std::fabs(planes.hood.distance[Neighbourhood::at(x, y, z)]) > std::sqrt(3.0f) * surfaceBoxHalf(planes.h))
          continue;
        const Vec3f centre = planes.first + Vec3f{float(x), float(y), float(z)} * planes.h;
        const float on_surface =
            readingOnSurface(mesh, centre, planes.distance(x, y, z), planes.normal(x, y, z), planes.h, planes.slack);
        float& m = io_missed[VoxelBlock::offset(x, y, z)];
        if (on_surface > planes.slack) m = std::max(m, on_surface);
      }
}

// Lowers further each plane `lowered` left above the unsigned distance to the triangles at one of its
// cell's points, or above zero on the surface inside its cell: by that excess plus the crease allowance.
void lowerToTriangles(const Neighbourhood& hood, const PlaneMesh& mesh, const format::GridGeometry& g,
                      const VoxelBlock& block, float* io_lowered) {
  const BlockPlanes planes{hood, g, block, io_lowered};
  float missed[VoxelBlock::kVoxels] = {};
  excessAtLattice(planes, mesh, missed);
  excessOnSurface(planes, mesh, missed);
  for (int v = 0; v < VoxelBlock::kVoxels; ++v)
    if (missed[v] > 0.0f) io_lowered[v] += missed[v] + kCreaseAllowanceVoxels * planes.h;
}

// How far to lower each voxel of one block (VoxelBlock order): the bound over its cell, then the check
// against the triangles.
void lowerBlock(const Neighbourhood& hood, const PlaneMesh& mesh, const format::GridGeometry& g,
                const VoxelBlock& block, float* out) {
  const float h = g.voxel_size;
  for (int x = 0; x < VoxelBlock::kDim; ++x)
    for (int y = 0; y < VoxelBlock::kDim; ++y)
      for (int z = 0; z < VoxelBlock::kDim; ++z) {
        if (!lowersPlane(hood, g, block, x, y, z)) continue;
        const int at = Neighbourhood::at(x, y, z);
        out[VoxelBlock::offset(x, y, z)] =
            lowering(planeExcess(hood, x, y, z, hood.distance[at], hood.normal[at], g.band, h), h);
      }
  lowerToTriangles(hood, mesh, g, block, out);
}

} // namespace

BakeStatus makePlanesConservative(bool keep_accurate, const TriangleSoup& soup, bool second_planes, ProgressFn progress,
                                  void* progress_user, BandGrid* io) {
  const format::GridGeometry& g = io->grid();
  const std::vector<VoxelBlock> blocks = io->blocks();
  ClosestPointIndex index;
  const BakeStatus built = index.build(soup);
  if (!built.ok()) return built;
  if (second_planes) io->startSecondPlanes();
  const PlaneMesh mesh{&soup, &index};
  const std::vector<SecondPlaneBlock> seconds =
      second_planes ? io->secondPlaneBlocks() : std::vector<SecondPlaneBlock>();
  std::vector<float> lowered(blocks.size() * VoxelBlock::kVoxels, 0.0f);
  const bool finished =
      forEachBlockInParallel(blocks.size(), "conservative", progress, progress_user, [&](std::size_t b) {
        Neighbourhood hood; // readNeighbourhood fills all of it
        readNeighbourhood(*io, blocks[b], &hood);
        lowerBlock(hood, mesh, g, blocks[b], &lowered[b * VoxelBlock::kVoxels]);
        if (second_planes) secondBoundsOfBlock(hood, mesh, g, &lowered[b * VoxelBlock::kVoxels], seconds[b]);
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
