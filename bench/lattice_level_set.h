// OpenVDB's meshToLevelSet of a mesh on a .dng grid's lattice: voxel centres where the .dng puts them
// (baker::vdbTransform) and a half-width of band / voxel. The outside baseline of accuracy_bench and
// table1_bench. Include only from a translation unit that already pays for OpenVDB's headers.
#pragma once

#include "band_grid_vdb.h"
#include "dng/format/vec3.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <array>
#include <cstdint>
#include <vector>

namespace dng {
namespace bench {

inline openvdb::FloatGrid::Ptr latticeLevelSet(const std::vector<Vec3f>& vertices,
                                               const std::vector<std::array<std::uint32_t, 3>>& triangles, Vec3f origin,
                                               float voxel, float band) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  points.reserve(vertices.size());
  for (const Vec3f& v : vertices)
    points.emplace_back(v.x, v.y, v.z);
  std::vector<openvdb::Vec3I> faces;
  faces.reserve(triangles.size());
  for (const auto& t : triangles)
    faces.emplace_back(t[0], t[1], t[2]);
  format::GridGeometry lattice;
  lattice.origin = origin;
  lattice.voxel_size = voxel;
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*baker::vdbTransform(lattice), points, faces, band / voxel);
}

} // namespace bench
} // namespace dng
