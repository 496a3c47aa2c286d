// One mesh of Table 1 with everything every method needs, built once per process: the triangles,
// the judge on them (Embree, for crossings and spawn points), the baked dngrid fields, the Embree
// scene of the ray-casting peer and the NanoVDB level set (bench/table1_bench.cpp).
#pragma once

#include "dng/file.h"
#include "mesh_reference.h"
#include "table1_embree.h"
#include "table1_levelset.h"
#include "table1_swarm.h"

#include <map>
#include <string>

namespace dng {
namespace table1 {

/// The bake every field of the table uses: resolution 128 (the earlier measurement's), the baker's
/// default band (4 voxels, a guaranteed reach of 3.1 voxels per step at kDt) and normal mode.
constexpr std::uint32_t kResolution = 128;

struct MeshScene {
  std::string name; ///< the file's stem
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  float outward = 1.0f; ///< -1 when the mesh is wound inside out (negative signed volume)
  float voxel = 0.0f;   ///< the baked fields' voxel edge, mesh units
  reference::MeshReference judge;
  File bricked;
  File dense; ///< empty until a case asks for it (meshScene)
  File exact; ///< bricked, baked in exact mode; empty until a case asks for it
  EmbreeCaster caster;
  EmbreeCaster caster_avx2; ///< the same on a device limited to AVX2; unbuilt until a case asks for it
  nanovdb::GridHandle<nanovdb::HostBuffer> levelset;

  /// The spawn states of a swarm of `count` particles (table1_swarm.h), made once per count; with
  /// `proven`, only points the bricked field proves outside (Body::provesOutside).
  const Swarm& spawn(std::size_t count, bool proven = false) const;

private:
  mutable std::map<std::pair<std::size_t, bool>, Swarm> spawns_;
};

/// What a case may ask for beyond the default bricked field and Embree scene.
struct Extras {
  bool dense = false;       ///< the dense field, default mode
  bool exact = false;       ///< the bricked field in exact mode
  bool embree_avx2 = false; ///< the Embree scene on a device limited to AVX2
};

/// The scene of the mesh at `path` (any format the baker reads), built on first use and kept for the
/// process, with the `extra` parts made too (each once). Null, with *out_error set, when the mesh
/// cannot be loaded or baked. Not thread-safe: call from the benchmark thread.
const MeshScene* meshScene(const std::string& path, Extras extra, std::string* out_error);

} // namespace table1
} // namespace dng
