// Internal to the conservative-planes stage (stages.h makePlanesConservative): what its two parts share.
// conservative_planes.cpp lowers every voxel's own plane; second_planes.cpp gives the voxels beside
// edges and creases a second bound (docs/FORMAT.md §5.5), proven against the triangles.
#pragma once

#include "stages.h"

namespace dng {
namespace baker {

inline constexpr int kHalo = VoxelBlock::kDim + 2; // a block and one voxel around it

/// A block's voxels and their neighbours, read once: exact distances (before any lowering) clamped to
/// +-band, and normals. Voxel (x, y, z) of the block, each -1..kDim, is at(x, y, z).
struct Neighbourhood {
  float distance[kHalo * kHalo * kHalo];
  Vec3f normal[kHalo * kHalo * kHalo];
  static int at(int x, int y, int z) { return ((z + 1) * kHalo + (y + 1)) * kHalo + (x + 1); }
};

/// The mesh the planes are checked against, and its index. The second bounds need a closed,
/// consistently oriented soup.
struct PlaneMesh {
  const TriangleSoup* soup;
  const ClosestPointIndex* index;
};

/// Triangle t of `soup` clipped to the box centre +- half: `poly` (room for 12) gets the polygon, the
/// count of its vertices is returned (0 when the triangle misses the box).
int clipTriangleToBox(const TriangleSoup& soup, std::uint32_t t, Vec3f centre, float half, Vec3f* poly);

/// The second bounds of one block's voxels (format::FieldSource::readSecondPlanes says what they are),
/// given `hood` and how far each voxel's own plane was lowered (VoxelBlock order), written to `out`.
/// Thread-safe for different blocks.
void secondBoundsOfBlock(const Neighbourhood& hood, const PlaneMesh& mesh, const format::GridGeometry& g,
                         const float* lowered, const SecondPlaneBlock& out);

} // namespace baker
} // namespace dng
