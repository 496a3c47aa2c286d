// The OpenVDB side of BandGrid, for the few translation units that work on the grids directly
// (band_grid.cpp, blurred_normals.cpp, export_vdb.cpp). Including this costs seconds of compile time.
#pragma once

#include "band_grid.h"

#include <openvdb/openvdb.h>

namespace dng {
namespace baker {

struct BandGrid::Impl {
  openvdb::FloatGrid::Ptr distance;        ///< background +band; a level set once finishBand has run
  openvdb::Vec3SGrid::Ptr normal;          ///< background zero; same topology as `distance`
  openvdb::FloatGrid::Ptr accurate;        ///< null, or `distance` as keepAccurateDistances() found it
  openvdb::Vec3SGrid::Ptr shading;         ///< null, or the mode's normals (startShading()); same topology
  openvdb::FloatGrid::Ptr second_distance; ///< null, or second planes (startSecondPlanes()), -inf: none
  openvdb::Vec3SGrid::Ptr second_normal;   ///< their normals; both on `distance`'s leaves
  openvdb::FloatGrid::Ptr second_raise;    ///< the pairs' raises (negative: not a pair); same leaves
};

/// Our voxel (i, j, k) is OpenVDB's coordinate (i, j, k); the transform puts it at its centre,
/// origin + (i + 1/2) h, so world positions agree with the .dng.
openvdb::math::Transform::Ptr vdbTransform(const format::GridGeometry& grid);

/// The grid's voxels as an OpenVDB box (inclusive bounds).
inline openvdb::CoordBBox vdbBounds(const format::GridGeometry& g) {
  return {openvdb::Coord(0), openvdb::Coord(int(g.dims[0]) - 1, int(g.dims[1]) - 1, int(g.dims[2]) - 1)};
}

} // namespace baker
} // namespace dng
