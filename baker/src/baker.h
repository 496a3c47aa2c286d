// The baker's stages, declared in one place (DESIGN.md §4). Each stage lives in its own .cpp:
//   load_mesh.cpp   OpenMesh parsing into a triangle soup
//   check_mesh.cpp  mesh diagnostics and the "can this be baked" decision
// Later stages (grid placement, distance, sign, normals, encode, write) join this header.
#pragma once

#include "dng/format/vec3.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dng {
namespace baker {

/// Documented exit codes of the tools (docs/BAKING.md); every baker error carries one.
enum class ExitCode : int {
  kOk = 0,
  kUsage = 1,        ///< bad command line
  kIo = 2,           ///< a file could not be read or written
  kInvalidInput = 3, ///< the input is unusable (empty, non-finite, all degenerate)
  kInternal = 4,     ///< a bug or resource failure
  kUnsupported = 5,  ///< a format or feature this build does not handle
};

/// Result of a baker stage: ok, or a code plus a sentence for the user.
struct [[nodiscard]] BakeStatus {
  ExitCode code = ExitCode::kOk;
  std::string message;
  bool ok() const { return code == ExitCode::kOk; }
  static BakeStatus success() { return {}; }
  static BakeStatus failure(ExitCode c, std::string m) { return {c, std::move(m)}; }
};

/// Triangles exactly as the file gave them (polygons fanned into triangles), with no merging,
/// splitting or dropping: non-manifold and open input survives intact.
struct TriangleSoup {
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::uint64_t polygons = 0;               ///< faces read, before triangulation
  std::uint64_t faces_with_bad_index = 0;   ///< faces that referred to missing vertices (skipped)
  std::vector<std::string> reader_messages; ///< what OpenMesh's reader reported, one line each
};

/// Loads OBJ, OFF, PLY, STL or OM with OpenMesh's readers. Errors: kIo when the file cannot be
/// opened or parsed, kUnsupported for other extensions. Not thread-safe (OpenMesh's IO registry and
/// log streams are global).
BakeStatus loadMesh(const std::string& path, TriangleSoup* out_soup);

/// What the checks found. Edges are counted by vertex index pairs.
struct MeshReport {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t non_finite_vertices = 0;
  std::uint64_t degenerate_triangles = 0; ///< repeated vertex or zero area
  std::uint64_t boundary_edges = 0;       ///< used by one triangle: the mesh is open
  std::uint64_t non_manifold_edges = 0;   ///< used by three or more triangles
  std::uint64_t components = 0;           ///< connected by shared vertices
  Vec3f bounds_min;
  Vec3f bounds_max;
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
};

MeshReport checkMesh(const TriangleSoup& soup);

/// kInvalidInput when the mesh cannot be baked: no triangles, non-finite coordinates, or every
/// triangle degenerate. Open and non-manifold meshes are fine (the sign is robust to them).
BakeStatus requireBakeable(const MeshReport& report);

} // namespace baker
} // namespace dng
