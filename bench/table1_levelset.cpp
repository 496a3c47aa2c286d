// Only the level set's construction: OpenVDB's headers cost ~30 s and over 1 GB per translation unit.
#include "table1_levelset.h"
#include "lattice_level_set.h"

#include <nanovdb/util/OpenToNanoVDB.h>

namespace dng {
namespace table1 {

nanovdb::GridHandle<nanovdb::HostBuffer> meshToNanoLevelSet(const std::vector<Vec3f>& vertices,
                                                            const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                            Vec3f origin, float voxel, float band) {
  const openvdb::FloatGrid::Ptr grid = bench::latticeLevelSet(vertices, triangles, origin, voxel, band);
  return nanovdb::openToNanoVDB(*grid);
}

} // namespace table1
} // namespace dng
