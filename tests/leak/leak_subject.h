// A leak subject: one mesh baked in one normal mode, with its reference on the original triangles.
#pragma once

#include "dng/file.h"
#include "leak_meshes.h"
#include "mesh_reference.h"
#include "stages.h"

#include <memory>
#include <string>

namespace dng {
namespace leak {

/// The step length the harness designs for, in seconds (the --dt of every bake).
constexpr float kDt = 0.016f;
/// Design travel per step in voxels: every bake's band comes from --max-speed = this many voxels / dt.
constexpr float kDesignVoxelsPerStep = 3.0f;

struct Subject {
  LeakMesh mesh;
  baker::NormalMode mode = baker::NormalMode::kNormalBlur;
  reference::MeshReference reference;
  File file;
  float voxel = 0.0f; ///< the baked grid's voxel edge, mesh units
  float reach = 0.0f; ///< View::guaranteedReach(), mesh units

  std::string label() const { return mesh.name + ", " + baker::normalModeName(mode); }
};

/// Bakes `mesh` at `resolution` (voxels along its longest axis; the code-made meshes are sized for
/// kResolution) with a band for kDesignVoxelsPerStep (the mesh goes through an OBJ in `folder`, which
/// must exist), maps the result and builds the reference. Null with *out_error on failure.
std::unique_ptr<Subject> bakeSubject(const LeakMesh& mesh, baker::NormalMode mode, const std::string& folder,
                                     std::string* out_error, int resolution = kResolution);

} // namespace leak
} // namespace dng
