// The blur of the paper's §3.1 on sparse OpenVDB grids, and what each method makes of it.
//
// The kernel is the separable tent t(i) = 1 - |i| / (R + 1), |i| <= R, applied along x, y and z: a
// linear attenuation at 3 (2R + 1) taps per voxel instead of (2R + 1)^3. A round moves values at
// most R voxels along each axis, so after K rounds nothing lies further than R K voxels (max norm)
// from a surface voxel: blurring on the surface voxels dilated by R K gives exactly what blurring
// the whole grid would, at the cost of the surface's neighbourhood only.
#include "band_grid_vdb.h"
#include "stages.h"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace dng {
namespace baker {

namespace {

using openvdb::Coord;

openvdb::Vec3s toVdb(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3f fromVdb(const openvdb::Vec3s& v) { return {v.x(), v.y(), v.z()}; }

// Accessors without registration in the tree: each lives within one task, on a grid nobody edits meanwhile.
template <class GridT> using Reader = openvdb::tree::ValueAccessor<const typename GridT::TreeType, false>;

// The surface voxels with their start values; they are the grid's active voxels.
template <class GridT, class ValueFn>
typename GridT::Ptr surfaceGrid(const std::vector<SurfaceVoxel>& surface, ValueFn value) {
  auto grid = GridT::create(openvdb::zeroVal<typename GridT::ValueType>());
  auto access = grid->getAccessor();
  for (const SurfaceVoxel& s : surface)
    access.setValue(Coord(s.ijk[0], s.ijk[1], s.ijk[2]), value(s));
  return grid;
}

// One pass of the tent kernel along `axis` from `in` into `out` (same topology). Normalized by the
// weights of the taps inside the grid: a blur must not grow values (the surface voxels, reset each
// round, must stay the potential's maximum). Taps are read straight from the leaf and its two
// neighbours along the axis (R <= 8 stays within them); a missing neighbour is an inactive tile of 0.
// A leaf's voxels at one place along the axis share their taps and weights, so they are summed
// together, tap by tap, each voxel's sum in the same order as alone (the same bits); per voxel, a
// division for each tap's weight and one by the run-time stride had been most of the blur of the
// bunny at 512.
template <class GridT>
void blurAxis(const GridT& in, int axis, std::uint32_t radius, const openvdb::CoordBBox& bounds, GridT* out) {
  using ValueT = typename GridT::ValueType;
  using LeafT = typename GridT::TreeType::LeafNodeType;
  constexpr int kDim = int(LeafT::DIM), kLog2Dim = int(LeafT::LOG2DIM), kLayer = kDim * kDim;
  static_assert(kDim == 1 << kLog2Dim && LeafT::SIZE == kLayer * kDim, "a leaf is a cube of power-of-two edge");
  // OpenVDB's leaf order is x, y, z with z fastest: the axis' stride, and where each voxel of a layer
  // across the axis sits (its two other coordinates, the slower one first).
  const int shift = (2 - axis) * kLog2Dim, stride = 1 << shift;
  const int slow_shift = axis == 0 ? kLog2Dim : 2 * kLog2Dim, fast_shift = axis == 2 ? kLog2Dim : 0;
  int layer[kLayer];
  for (int n = 0; n < kLayer; ++n)
    layer[n] = (n >> kLog2Dim) << slow_shift | (n & (kDim - 1)) << fast_shift;
  const int r = int(radius);
  std::vector<float> tap(std::size_t(2 * r + 1));
  for (int o = -r; o <= r; ++o)
    tap[std::size_t(o + r)] = 1.0f - float(std::abs(o)) / float(radius + 1);
  openvdb::tree::LeafManager<typename GridT::TreeType> leaves(out->tree());
  leaves.foreach ([&](LeafT& leaf, std::size_t) {
    Coord step(0);
    step[axis] = kDim;
    const LeafT* neighbours[3] = {in.tree().probeConstLeaf(leaf.origin() - step),
                                  in.tree().probeConstLeaf(leaf.origin()),
                                  in.tree().probeConstLeaf(leaf.origin() + step)};
    // Raw buffers: LeafNode::getValue checks for delayed loading on every call.
    const ValueT* line[3];
    for (int n = 0; n < 3; ++n)
      line[n] = neighbours[n] != nullptr ? neighbours[n]->buffer().data() : nullptr;
    ValueT* target = leaf.buffer().data();
    const int first = leaf.origin()[axis], low = bounds.min()[axis], high = bounds.max()[axis];
    for (int at = 0; at < kDim; ++at) {
      // The taps inside the grid, in the order the sums have always taken them.
      const int from = std::max(-r, low - first - at), to = std::min(r, high - first - at);
      ValueT sum[kLayer];
      std::fill(std::begin(sum), std::end(sum), openvdb::zeroVal<ValueT>());
      float weights = 0.0f;
      for (int o = from; o <= to; ++o) {
        const int q = at + o + kDim; // 0..3 kDim - 1 across the three leaves
        const float w = tap[std::size_t(o + r)];
        weights += w;
        if (line[q >> kLog2Dim] == nullptr) continue;
        const ValueT* source = line[q >> kLog2Dim] + (q & (kDim - 1)) * stride;
        for (int n = 0; n < kLayer; ++n)
          sum[n] = sum[n] + source[layer[n]] * w;
      }
      const float scale = 1.0f / weights;
      for (int n = 0; n < kLayer; ++n) {
        const int v = layer[n] + at * stride;
        if (leaf.isValueMaskOn(openvdb::Index(v))) target[v] = sum[n] * scale;
      }
    }
  });
}

// Reports stage "normals" as passes complete; false once the caller asked to cancel.
class PassProgress {
public:
  PassProgress(ProgressFn fn, void* user, std::uint32_t passes) : fn_(fn), user_(user), passes_(passes + 1) {}
  bool passDone() { return fn_ == nullptr || fn_(user_, "normals", double(++done_) / double(passes_)); }

private:
  ProgressFn fn_;
  void* user_;
  std::uint32_t passes_; // the blur's passes plus the final one over the band
  std::uint32_t done_ = 0;
};

// K rounds of the three passes, the surface voxels put back to their start values after each round
// (the paper: "after each iteration the surface voxels are returned to their initial values").
// Null when cancelled.
template <class GridT>
typename GridT::Ptr blurRounds(const GridT& surface, const format::GridGeometry& g, std::uint32_t radius,
                               std::uint32_t rounds, PassProgress& progress) {
  const openvdb::CoordBBox bounds = vdbBounds(g);
  typename GridT::Ptr current = surface.deepCopy();
  if (radius * rounds > 0)
    openvdb::tools::dilateActiveValues(current->tree(), int(radius * rounds), openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::EXPAND_TILES);
  current->tree().clip(bounds);
  // Dilation prunes leaves that are all active and all zero into active tiles, which LeafManager does
  // not visit: make every active value a voxel again so each one is blurred.
  current->tree().voxelizeActiveTiles();
  typename GridT::Ptr next = current->deepCopy();
  for (std::uint32_t round = 0; round < rounds; ++round) {
    for (int axis = 0; axis < 3; ++axis) {
      blurAxis(*current, axis, radius, bounds, next.get());
      std::swap(current, next);
      if (!progress.passDone()) return nullptr;
    }
    auto access = current->getAccessor();
    for (auto voxel = surface.cbeginValueOn(); voxel; ++voxel)
      access.setValueOnly(voxel.getCoord(), *voxel);
  }
  return current;
}

// Calls visit(coordinate, distance, shading normal&) for every band voxel, leaves in parallel, the
// shading normals starting as the exact ones (BandGrid::startShading). `make_state` gives each leaf
// task its own state (an accessor), passed to visit as the first argument.
template <class MakeState, class Visit> void forEachBandVoxel(BandGrid* band, MakeState make_state, Visit visit) {
  band->startShading();
  openvdb::Vec3STree& normals = band->impl().shading->tree();
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(band->impl().distance->tree());
  leaves.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
    auto state = make_state();
    openvdb::Vec3STree::LeafNodeType* normal_leaf = normals.probeLeaf(leaf.origin());
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      openvdb::Vec3s n = normal_leaf->getValue(voxel.pos());
      visit(state, voxel.getCoord(), *voxel, n);
      normal_leaf->setValueOnly(voxel.pos(), n);
    }
  });
}

} // namespace

BakeStatus blurNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                       BandGrid* io, ProgressFn progress, void* progress_user) {
  PassProgress passes(progress, progress_user, 3 * rounds);
  const auto start = surfaceGrid<openvdb::Vec3SGrid>(surface, [](const SurfaceVoxel& s) { return toVdb(s.normal); });
  const openvdb::Vec3SGrid::Ptr blurred = blurRounds(*start, io->grid(), radius, rounds, passes);
  if (blurred == nullptr) return BakeStatus::cancelled();
  forEachBandVoxel(
      io, [&] { return Reader<openvdb::Vec3SGrid>(blurred->tree()); },
      [](Reader<openvdb::Vec3SGrid>& field, const Coord& at, float, openvdb::Vec3s& normal) {
        const Vec3f n = normalizeOrZero(fromVdb(field.getValue(at)));
        if (dot(n, n) > 0.0f) normal = toVdb(n); // beyond the blur's reach the exact normal stays
      });
  return passes.passDone() ? BakeStatus::success() : BakeStatus::cancelled();
}

BakeStatus potentialNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                            BandGrid* io, ProgressFn progress, void* progress_user) {
  PassProgress passes(progress, progress_user, 3 * rounds);
  const auto start = surfaceGrid<openvdb::FloatGrid>(surface, [](const SurfaceVoxel&) { return 1.0f; });
  const openvdb::FloatGrid::Ptr potential = blurRounds(*start, io->grid(), radius, rounds, passes);
  if (potential == nullptr) return BakeStatus::cancelled();
  forEachBandVoxel(
      io, [&] { return Reader<openvdb::FloatGrid>(potential->tree()); },
      [](Reader<openvdb::FloatGrid>& p, const Coord& at, float distance, openvdb::Vec3s& normal) {
        auto step = [&](int axis) {
          Coord down = at, up = at;
          --down[axis];
          ++up[axis];
          return p.getValue(down) - p.getValue(up);
        };
        const Vec3f downhill{step(0), step(1), step(2)};
        // Where the potential is flat (a sheet's own voxels, or beyond the blur) keep the exact normal
        // rather than normalizing rounding noise.
        if (!(length(downhill) > 1e-4f)) return;
        const Vec3f n = normalizeOrZero(downhill);
        // Down the potential is away from the surface outside, deeper inside a solid: orient it into
        // the exact normal's hemisphere (reliable in the band even in voxels the surface cuts), else
        // by the side of the surface.
        const Vec3f exact = fromVdb(normal);
        const bool flip = dot(exact, exact) > 0.0f ? dot(n, exact) < 0.0f : distance < 0.0f;
        normal = toVdb(flip ? n * -1.0f : n);
      });
  return passes.passDone() ? BakeStatus::success() : BakeStatus::cancelled();
}

} // namespace baker
} // namespace dng
