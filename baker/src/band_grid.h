// The baker's working store (docs/DESIGN.md §5.5): the band of a DN field as sparse OpenVDB grids, a float
// grid of signed distances and a Vec3s grid of normals sharing one topology of 8^3 leaves. Only the
// blocks near the surface exist, so memory follows the surface area, not the grid's volume.
//
// This header is free of OpenVDB: stages fill blocks through plain arrays (VoxelBlock), and the
// encoders read the band through format::FieldSource. The few translation units that need the
// grids themselves include band_grid_vdb.h (OpenVDB headers cost ~25 s and >1 GB per unit to compile).
#pragma once

#include "dng/format/field_source.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace dng {
namespace baker {

/// One 8^3 leaf of the band as plain arrays. Voxel (x, y, z) of the block (each 0..7) is voxel
/// origin + (x, y, z) of the grid and sits at offset(x, y, z) (OpenVDB's leaf order: z fastest).
struct VoxelBlock {
  static constexpr int kDim = 8;
  static constexpr int kVoxels = kDim * kDim * kDim;
  static constexpr int offset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }

  std::array<std::int32_t, 3> origin{}; ///< multiples of kDim
  float* distance = nullptr;            ///< kVoxels signed distances
  float* normal = nullptr;              ///< 3 * kVoxels floats: x, y, z per voxel

  void setNormal(int n, Vec3f v) const {
    normal[3 * n] = v.x;
    normal[3 * n + 1] = v.y;
    normal[3 * n + 2] = v.z;
  }
};

/// One block's second bounds (BandGrid::secondPlaneBlocks): a VoxelBlock's plane (distance -infinity:
/// none) plus per voxel the raise of the voxel's own plane that makes the bound a pair (negative: not
/// a pair), as format::FieldSource::readSecondPlanes gives them.
struct SecondPlaneBlock : VoxelBlock {
  float* raise = nullptr; ///< kVoxels
};

/// Block coordinates: voxel index / VoxelBlock::kDim on each axis.
using BlockKey = std::array<std::int32_t, 3>;

/// The band of a DN field over `grid`. Voxels nobody wrote read as far outside (+band) with a zero
/// normal. Not thread-safe, except that blocks() may be filled from many threads, one block each, and
/// that read() and farHint() may run on many threads at once while nothing changes the grid.
class BandGrid final : public format::FieldSource {
public:
  explicit BandGrid(const format::GridGeometry& grid);
  ~BandGrid() override;
  BandGrid(const BandGrid&) = delete;
  BandGrid& operator=(const BandGrid&) = delete;

  const format::GridGeometry& grid() const override { return grid_; }
  /// Records a promise about the values (format::kGridFlag*), written into the file's GRID section.
  void addFlags(std::uint32_t flags) { grid_.flags |= flags; }

  /// Allocates the blocks at `keys` (duplicates allowed), every voxel far outside.
  void addBlocks(const std::vector<BlockKey>& keys);

  /// Every allocated block, in a fixed order. The pointers stay valid until addBlocks or finishBand.
  std::vector<VoxelBlock> blocks();

  /// Call once the distances are in: voxels with |distance| < band become the band (OpenVDB's active
  /// voxels), blocks without any are dropped, and every other voxel and tile takes the sign of its
  /// side by OpenVDB's signedFloodFill (exact when the band is closed and at least a voxel thick).
  void finishBand();

  /// Voxels with |distance| < band (after finishBand).
  std::uint64_t bandVoxels() const;
  /// Blocks allocated now.
  std::uint64_t blockCount() const;
  /// Whether any voxel lies inside beyond the band (after finishBand): space the surface encloses.
  bool hasFarInside() const;

  void read(const format::VoxelBox& box, float* distance, Vec3f* normal) const override;

  /// Keeps a copy of the distances as they are now, before a stage lowers them (conservative planes),
  /// so the encoders can write what lifts them back (the file's LIFT section). Costs one more float
  /// per band voxel. Call after finishBand, once.
  void keepAccurateDistances();
  bool hasAccurate() const override;
  void readAccurate(const format::VoxelBox& box, float* distance) const override;
  /// Starts the shading normals as a copy of the normals as they are now, the distance's own gradient,
  /// for a stage to replace with its mode's (normal-blur, potential); the normals stay the planes'.
  /// The encoders write them beside the planes (the file's SHAD section). Costs three more floats per
  /// band voxel. Call after finishBand, once.
  void startShading();
  bool hasShading() const override;
  void readShading(const format::VoxelBox& box, Vec3f* shading) const override;
  /// Starts the second bounds, none anywhere, over the band's blocks, for a stage to fill block by block
  /// (secondPlaneBlocks). The encoders write them beside the planes (the file's PLN2 section). Costs
  /// five more floats per voxel of the band's blocks. Call after finishBand, once.
  void startSecondPlanes();
  /// The second bounds' blocks, in blocks()' order. Valid until the band's topology changes.
  std::vector<SecondPlaneBlock> secondPlaneBlocks();
  bool hasSecondPlanes() const override;
  void readSecondPlanes(const format::VoxelBox& box, float* distance, Vec3f* normal, float* raise) const override;
  /// Far when no block overlaps the box and every tile it covers lies on one side.
  format::FarHint farHint(const format::VoxelBox& box) const override;

  /// The OpenVDB grids, for the translation units that include band_grid_vdb.h.
  struct Impl;
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

private:
  format::GridGeometry grid_;
  std::unique_ptr<Impl> impl_;
};

} // namespace baker
} // namespace dng
