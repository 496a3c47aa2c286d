#include "accuracy_vdb.h"
#include "lattice_level_set.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
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
  const openvdb::FloatGrid::Ptr grid = latticeLevelSet(vertices, triangles, origin, voxel, band);

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
