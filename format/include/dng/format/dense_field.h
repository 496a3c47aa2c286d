// An in-memory DN field: the common currency between producers (the baker, tests, analytic
// functions) and the writer. Dense, one distance and one normal per voxel, x fastest.
#pragma once

#include "dng/format/vec3.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dng {
namespace format {

/// Placement of a grid in its body's local frame. Voxel (i, j, k) covers
/// [origin + (i, j, k) * voxel_size, origin + (i + 1, j + 1, k + 1) * voxel_size).
struct GridGeometry {
  Vec3f origin;                      ///< minimum corner of voxel (0, 0, 0)
  float voxel_size = 1.0f;           ///< cubic voxel edge, > 0
  std::uint32_t dims[3] = {0, 0, 0}; ///< voxels per axis, each >= 1
  float band = 1.0f;                 ///< |distance| >= band is "far", > 0, in local units
  /// GridSection::flags for the file (format::kGridFlag*): what the producer promises about its
  /// values, e.g. conservative planes. Writers copy it; they do not check it.
  std::uint32_t flags = 0;

  std::size_t voxelCount() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
  std::size_t index(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return (std::size_t(k) * dims[1] + j) * dims[0] + i;
  }
  Vec3f voxelCentre(std::uint32_t i, std::uint32_t j, std::uint32_t k) const {
    return origin + Vec3f{float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f} * voxel_size;
  }
};

/// Distance and normal per voxel. `distance` and `normal` both hold grid.voxelCount() entries.
/// Normals of far voxels (|distance| >= band) carry no meaning and may be zero.
struct DenseField {
  GridGeometry grid;
  std::vector<float> distance;
  std::vector<Vec3f> normal;
  /// Optional: empty, or one entry per voxel holding the distance before the producer lowered it
  /// into `distance` (conservative planes). When present the writers add a LIFT section.
  std::vector<float> accurate;
  /// Optional: empty, or one entry per voxel holding the distance's gradient (unit, or zero where
  /// unknown) when `normal` holds something else, such as blurred normals. When present the writers
  /// add a GRAD section.
  std::vector<Vec3f> gradient;
  /// Optional: empty, or one entry per voxel holding the normal the field's mode gives (unit, or zero
  /// where unknown) when `normal` holds the distance's own gradient, the plane the runtime's walk
  /// trusts. When present the writers add a SHAD section; queries and responses read these normals.
  std::vector<Vec3f> shading;
  /// Optional: empty, or one entry per voxel in all three: a second bound (FieldSource::readSecondPlanes
  /// says what the three mean). When present the bricked writer adds a PLN2 section; the dense writer
  /// has nowhere to put them and leaves them out.
  std::vector<float> second_distance;
  std::vector<Vec3f> second_normal;
  std::vector<float> second_raise;

  /// Sizes both arrays for `geometry`, far outside (+band) with zero normals.
  void reset(const GridGeometry& geometry) {
    grid = geometry;
    distance.assign(grid.voxelCount(), grid.band);
    normal.assign(grid.voxelCount(), Vec3f{});
    accurate.clear();
    gradient.clear();
    shading.clear();
    second_distance.clear();
    second_normal.clear();
    second_raise.clear();
  }
};

} // namespace format
} // namespace dng
