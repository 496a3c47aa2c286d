// Only the level set's construction: OpenVDB's headers cost ~30 s and over 1 GB per translation unit.
#include "table1_levelset.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <nanovdb/util/OpenToNanoVDB.h>

namespace dng {
namespace table1 {

nanovdb::GridHandle<nanovdb::HostBuffer> meshToNanoLevelSet(const std::vector<Vec3f>& vertices,
                                                            const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                            Vec3f origin, float voxel, float band) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  points.reserve(vertices.size());
  for (const Vec3f& v : vertices)
    points.emplace_back(v.x, v.y, v.z);
  std::vector<openvdb::Vec3I> faces;
  faces.reserve(triangles.size());
  for (const auto& t : triangles)
    faces.emplace_back(t[0], t[1], t[2]);
  auto transform = openvdb::math::Transform::createLinearTransform(double(voxel));
  const double half = 0.5 * double(voxel);
  transform->postTranslate(openvdb::Vec3d(origin.x + half, origin.y + half, origin.z + half));
  const openvdb::FloatGrid::Ptr grid =
      openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, faces, band / voxel);
  return nanovdb::openToNanoVDB(*grid);
}

} // namespace table1
} // namespace dng
