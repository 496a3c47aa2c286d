#include "leak_subject.h"
#include "mesh_soup.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace leak {

namespace {

// The voxel size placeGrid will choose at `resolution` for a band of kDesignVoxelsPerStep per step: the
// band and the padding depend on the voxel size, so settle them together.
float designVoxel(const LeakMesh& mesh, int resolution, std::string* out_error) {
  const baker::MeshReport report = baker::checkMesh(testing::soupOf(mesh.mesh));
  const Vec3f extent = report.bounds_max - report.bounds_min;
  // A first guess: the padding takes as many voxels at any resolution.
  float voxel = std::max({extent.x, extent.y, extent.z}) / (float(resolution) - (float(kResolution) - kMeshVoxels));
  for (int round = 0; round < 4; ++round) {
    baker::BakeOptions options;
    options.resolution = std::uint32_t(resolution);
    options.dt = kDt;
    options.max_speed = kDesignVoxelsPerStep * voxel / kDt;
    format::GridGeometry grid;
    std::vector<std::string> warnings;
    const baker::BakeStatus status = baker::placeGrid(report, options, &grid, &warnings);
    if (!status.ok()) {
      *out_error = status.message;
      return 0.0f;
    }
    if (std::fabs(grid.voxel_size - voxel) <= 1e-6f * voxel) break;
    voxel = grid.voxel_size;
  }
  return voxel;
}

} // namespace

std::unique_ptr<Subject> bakeSubject(const LeakMesh& mesh, baker::NormalMode mode, const std::string& folder,
                                     std::string* out_error, int resolution) {
  auto subject = std::make_unique<Subject>();
  subject->mesh = mesh;
  subject->mode = mode;
  const float voxel = designVoxel(mesh, resolution, out_error);
  if (!(voxel > 0.0f)) return nullptr;

  std::string stem = mesh.name + "_" + baker::normalModeName(mode);
  std::replace(stem.begin(), stem.end(), ' ', '_');
  const std::string obj = folder + "/" + stem + ".obj", dng_path = folder + "/" + stem + ".dng";
  testing::writeObj(mesh.mesh, obj);
  baker::BakeOptions options;
  options.mode = mode;
  options.resolution = std::uint32_t(resolution);
  options.dt = kDt;
  options.max_speed = kDesignVoxelsPerStep * voxel / kDt;
  baker::BakeReport report;
  const baker::BakeStatus status = baker::bake(obj, {dng_path, {}}, options, nullptr, nullptr, &report);
  if (!status.ok()) {
    *out_error = stem + ": " + status.message;
    return nullptr;
  }
  Diagnostic diag;
  if (File::open(dng_path.c_str(), &subject->file, &diag) != Status::kOk) {
    *out_error = dng_path + ": " + diag.message;
    return nullptr;
  }
  if (!subject->reference.build(mesh.mesh.vertices, mesh.mesh.triangles)) {
    *out_error = stem + ": Embree could not build the reference scene";
    return nullptr;
  }
  subject->voxel = subject->file.view().grid().voxel_size;
  subject->reach = subject->file.view().guaranteedReach();
  return subject;
}

} // namespace leak
} // namespace dng
