// BandGrid on OpenVDB: allocation, the band's topology and far signs, and reads for the encoders.
#include "band_grid_vdb.h"

#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dng {
namespace baker {

static_assert(sizeof(openvdb::Vec3s) == 3 * sizeof(float), "normals are exposed as three floats per voxel");
static_assert(openvdb::FloatTree::LeafNodeType::DIM == VoxelBlock::kDim, "blocks are OpenVDB leaves");

openvdb::math::Transform::Ptr vdbTransform(const format::GridGeometry& g) {
  auto transform = openvdb::math::Transform::createLinearTransform(double(g.voxel_size));
  const double half = 0.5 * double(g.voxel_size);
  transform->postTranslate(openvdb::Vec3d(g.origin.x + half, g.origin.y + half, g.origin.z + half));
  return transform;
}

namespace {

// Calls visit(cell) for the origin of every block-sized cell the box overlaps, z slowest, until visit
// returns false. Returns whether it visited them all.
template <class Visit> bool forEachCell(const format::VoxelBox& box, Visit visit) {
  const int dim = VoxelBlock::kDim;
  for (int z = int(box.lo[2]) / dim; z <= int(box.hi[2] - 1) / dim; ++z)
    for (int y = int(box.lo[1]) / dim; y <= int(box.hi[1] - 1) / dim; ++y)
      for (int x = int(box.lo[0]) / dim; x <= int(box.hi[0] - 1) / dim; ++x)
        if (!visit(openvdb::Coord(x * dim, y * dim, z * dim))) return false;
  return true;
}

} // namespace

BandGrid::BandGrid(const format::GridGeometry& grid) : grid_(grid), impl_(std::make_unique<Impl>()) {
  openvdb::initialize(); // registers the grid types; idempotent
  impl_->distance = openvdb::FloatGrid::create(grid.band);
  impl_->distance->setName("distance");
  impl_->distance->setGridClass(openvdb::GRID_LEVEL_SET);
  impl_->distance->setTransform(vdbTransform(grid));
  impl_->normal = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  impl_->normal->setName("normal");
  impl_->normal->setTransform(vdbTransform(grid));
}

BandGrid::~BandGrid() = default;

void BandGrid::addBlocks(const std::vector<BlockKey>& keys) {
  for (const BlockKey& key : keys) {
    const openvdb::Coord at(key[0] * VoxelBlock::kDim, key[1] * VoxelBlock::kDim, key[2] * VoxelBlock::kDim);
    impl_->distance->tree().touchLeaf(at);
    impl_->normal->tree().touchLeaf(at);
  }
}

std::vector<VoxelBlock> BandGrid::blocks() {
  std::vector<VoxelBlock> out;
  out.reserve(impl_->distance->tree().leafCount());
  for (auto leaf = impl_->distance->tree().beginLeaf(); leaf; ++leaf) {
    auto* normal_leaf = impl_->normal->tree().probeLeaf(leaf->origin());
    VoxelBlock block;
    block.origin = {leaf->origin().x(), leaf->origin().y(), leaf->origin().z()};
    block.distance = leaf->buffer().data();
    block.normal = normal_leaf->buffer().data()->asPointer();
    out.push_back(block);
  }
  return out;
}

void BandGrid::finishBand() {
  const float band = grid_.band;
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(impl_->distance->tree());
  openvdb::Vec3STree& normal_tree = impl_->normal->tree();
  leaves.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
    auto* normal_leaf = normal_tree.probeLeaf(leaf.origin());
    for (openvdb::Index n = 0; n < openvdb::FloatTree::LeafNodeType::SIZE; ++n) {
      const bool in_band = std::fabs(leaf.getValue(n)) < band;
      leaf.setActiveState(n, in_band);
      normal_leaf->setActiveState(n, in_band);
    }
  });
  openvdb::tools::pruneInactive(impl_->distance->tree());
  openvdb::tools::pruneInactive(impl_->normal->tree());
  openvdb::tools::signedFloodFill(impl_->distance->tree());
}

std::uint64_t BandGrid::bandVoxels() const { return impl_->distance->tree().activeVoxelCount(); }

std::uint64_t BandGrid::blockCount() const { return impl_->distance->tree().leafCount(); }

bool BandGrid::hasFarInside() const {
  // After the flood fill every value off the band is +band or -band: any negative one is far inside.
  for (auto value = impl_->distance->tree().cbeginValueOff(); value; ++value)
    if (*value < 0.0f) return true;
  return false;
}

namespace {

// Copies the box's voxels out of `tree` leaf by leaf from the raw buffers (an accessor walks the tree
// and checks delayed loading per voxel); cells without a leaf hold one tile value. Calls
// store(out, value) with out the voxel's index in the box, x fastest.
template <class Tree, class Store> void readTree(const Tree& tree, const format::VoxelBox& box, Store store) {
  const int dim = VoxelBlock::kDim;
  const std::size_t nx = box.hi[0] - box.lo[0], ny = box.hi[1] - box.lo[1];
  forEachCell(box, [&](const openvdb::Coord& cell) {
    const auto* leaf = tree.probeConstLeaf(cell);
    const auto* values = leaf != nullptr ? leaf->buffer().data() : nullptr;
    const typename Tree::ValueType tile = leaf != nullptr ? typename Tree::ValueType(0) : tree.getValue(cell);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max(int(box.lo[a]), cell[a]);
      hi[a] = std::min(int(box.hi[a]), cell[a] + dim);
    }
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        for (int i = lo[0]; i < hi[0]; ++i) {
          const std::size_t out = ((k - box.lo[2]) * ny + (j - box.lo[1])) * nx + (i - box.lo[0]);
          store(out, values != nullptr ? values[VoxelBlock::offset(i - cell[0], j - cell[1], k - cell[2])] : tile);
        }
    return true;
  });
}

} // namespace

void BandGrid::read(const format::VoxelBox& box, float* distance, Vec3f* normal) const {
  readTree(impl_->distance->tree(), box, [&](std::size_t out, float d) { distance[out] = d; });
  readTree(impl_->normal->tree(), box, [&](std::size_t out, const openvdb::Vec3s& n) {
    normal[out] = {n.x(), n.y(), n.z()};
  });
}

void BandGrid::keepAccurateDistances() { impl_->accurate = impl_->distance->deepCopy(); }

bool BandGrid::hasAccurate() const { return impl_->accurate != nullptr; }

void BandGrid::readAccurate(const format::VoxelBox& box, float* distance) const {
  readTree(impl_->accurate->tree(), box, [&](std::size_t out, float d) { distance[out] = d; });
}

void BandGrid::startShading() {
  impl_->shading = impl_->normal->deepCopy();
  impl_->shading->setName("shading"); // its name in --export-vdb files
}

bool BandGrid::hasShading() const { return impl_->shading != nullptr; }

void BandGrid::readShading(const format::VoxelBox& box, Vec3f* shading) const {
  readTree(impl_->shading->tree(), box, [&](std::size_t out, const openvdb::Vec3s& n) {
    shading[out] = {n.x(), n.y(), n.z()};
  });
}

void BandGrid::startSecondPlanes() {
  const float none = -std::numeric_limits<float>::infinity();
  impl_->second_distance = openvdb::FloatGrid::create(none);
  impl_->second_normal = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  impl_->second_raise = openvdb::FloatGrid::create(-1.0f);
  for (auto leaf = impl_->distance->tree().cbeginLeaf(); leaf; ++leaf) {
    impl_->second_distance->tree().touchLeaf(leaf->origin())->fill(none);
    impl_->second_normal->tree().touchLeaf(leaf->origin());
    impl_->second_raise->tree().touchLeaf(leaf->origin())->fill(-1.0f);
  }
}

std::vector<SecondPlaneBlock> BandGrid::secondPlaneBlocks() {
  std::vector<SecondPlaneBlock> out;
  out.reserve(impl_->distance->tree().leafCount());
  for (auto leaf = impl_->distance->tree().beginLeaf(); leaf; ++leaf) {
    SecondPlaneBlock block;
    block.origin = {leaf->origin().x(), leaf->origin().y(), leaf->origin().z()};
    block.distance = impl_->second_distance->tree().probeLeaf(leaf->origin())->buffer().data();
    block.normal = impl_->second_normal->tree().probeLeaf(leaf->origin())->buffer().data()->asPointer();
    block.raise = impl_->second_raise->tree().probeLeaf(leaf->origin())->buffer().data();
    out.push_back(block);
  }
  return out;
}

bool BandGrid::hasSecondPlanes() const { return impl_->second_distance != nullptr; }

void BandGrid::readSecondPlanes(const format::VoxelBox& box, float* distance, Vec3f* normal, float* raise) const {
  readTree(impl_->second_distance->tree(), box, [&](std::size_t out, float d) { distance[out] = d; });
  readTree(impl_->second_normal->tree(), box, [&](std::size_t out, const openvdb::Vec3s& n) {
    normal[out] = {n.x(), n.y(), n.z()};
  });
  readTree(impl_->second_raise->tree(), box, [&](std::size_t out, float r) { raise[out] = r; });
}

format::FarHint BandGrid::farHint(const format::VoxelBox& box) const {
  const openvdb::FloatTree& tree = impl_->distance->tree();
  bool inside = false, outside = false;
  // A block-sized cell without a leaf holds one tile value throughout.
  const bool all_tiles = forEachCell(box, [&](const openvdb::Coord& cell) {
    if (tree.probeConstLeaf(cell) != nullptr) return false;
    const float value = tree.getValue(cell);
    if (std::fabs(value) < grid_.band) return false;
    (value < 0.0f ? inside : outside) = true;
    return true;
  });
  if (!all_tiles || inside == outside) return format::FarHint::kUnknown;
  return inside ? format::FarHint::kFarInside : format::FarHint::kFarOutside;
}

} // namespace baker
} // namespace dng
