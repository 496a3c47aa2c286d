// --export-vdb: the baked band as OpenVDB grids, for a look in Houdini or Blender. OpenVDB's headers
// are heavy (seconds and hundreds of MB per translation unit), so this is the only file including them.
#include "baker.h"

#include <openvdb/openvdb.h>

#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace dng {
namespace baker {

namespace {

// Our voxel (i, j, k) has its centre at origin + (i + 1/2) h; OpenVDB puts index (i, j, k) at
// transform(i, j, k): a linear transform of h, translated to the first centre.
openvdb::math::Transform::Ptr placement(const format::GridGeometry& g) {
  auto transform = openvdb::math::Transform::createLinearTransform(double(g.voxel_size));
  transform->postTranslate(openvdb::Vec3d(g.origin.x + 0.5 * g.voxel_size, g.origin.y + 0.5 * g.voxel_size,
                                          g.origin.z + 0.5 * g.voxel_size));
  return transform;
}

} // namespace

BakeStatus exportVdb(const DistanceResult& result, const std::string& path) {
  openvdb::initialize();
  const format::GridGeometry& g = result.field.grid;
  auto distance = openvdb::FloatGrid::create(g.band);
  auto normal = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  distance->setName("distance");
  normal->setName("normal");
  distance->setGridClass(openvdb::GRID_LEVEL_SET);
  distance->setTransform(placement(g));
  normal->setTransform(placement(g));
  auto distance_access = distance->getAccessor();
  auto normal_access = normal->getAccessor();
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        const std::size_t v = g.index(i, j, k);
        if (!result.in_band[v]) continue;
        const openvdb::Coord ijk{int(i), int(j), int(k)};
        const Vec3f n = result.field.normal[v];
        distance_access.setValue(ijk, result.field.distance[v]);
        normal_access.setValue(ijk, openvdb::Vec3s(n.x, n.y, n.z));
      }
  // Same promise as the .dng: the old file or the new one, never half of one.
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  try {
    openvdb::io::File file(temp);
    file.write({distance, normal});
    file.close();
  } catch (const std::exception& e) {
    std::remove(temp.c_str());
    return BakeStatus::failure(ExitCode::kIo, "cannot write '" + path + "': " + e.what());
  }
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::remove(temp.c_str());
    return BakeStatus::failure(ExitCode::kIo, "cannot replace '" + path + "': " + error.message());
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
