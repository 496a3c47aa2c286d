#include "accuracy_vdb.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace dng {
namespace bench {

namespace {

// The gradient of the trilinear field by central differences this far apart (in voxels): the field is
// piecewise trilinear, so this is its derivative except within a hair of a cell face.
constexpr double kGradientStep = 1e-3;

} // namespace

std::vector<VdbReading> meshToLevelSetReadings(const std::vector<Vec3f>& vertices,
                                               const std::vector<std::array<std::uint32_t, 3>>& triangles, Vec3f origin,
                                               float voxel, float band, const std::vector<Vec3f>& points) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> vdb_points;
  vdb_points.reserve(vertices.size());
  for (const Vec3f& v : vertices)
    vdb_points.emplace_back(v.x, v.y, v.z);
  std::vector<openvdb::Vec3I> vdb_triangles;
  vdb_triangles.reserve(triangles.size());
  for (const auto& t : triangles)
    vdb_triangles.emplace_back(t[0], t[1], t[2]);
  auto transform = openvdb::math::Transform::createLinearTransform(double(voxel));
  const double half = 0.5 * double(voxel);
  transform->postTranslate(openvdb::Vec3d(origin.x + half, origin.y + half, origin.z + half));
  const openvdb::FloatGrid::Ptr grid =
      openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, vdb_points, vdb_triangles, band / voxel);

  std::vector<VdbReading> out(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    const openvdb::FloatGrid::ConstAccessor accessor = grid->getConstAccessor();
    const auto at = [&](const openvdb::Vec3d& index) {
      return double(openvdb::tools::BoxSampler::sample(accessor, index));
    };
    for (std::size_t n = r.begin(); n != r.end(); ++n) {
      const openvdb::Vec3d index = grid->worldToIndex(openvdb::Vec3d(points[n].x, points[n].y, points[n].z));
      openvdb::Vec3d gradient;
      for (int axis = 0; axis < 3; ++axis) {
        openvdb::Vec3d step(0.0);
        step[axis] = kGradientStep;
        gradient[axis] = (at(index + step) - at(index - step)) / (2.0 * kGradientStep);
      }
      out[n].distance = float(at(index));
      const double norm = gradient.length();
      if (norm > 0.0) out[n].normal = {float(gradient[0] / norm), float(gradient[1] / norm), float(gradient[2] / norm)};
    }
  });
  return out;
}

} // namespace bench
} // namespace dng
