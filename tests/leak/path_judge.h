// Judges one particle-step: the straight path from where the particle was to where it ended, both in
// the body's own (mesh) frame, against the reference on the original triangles. Never looks at a field.
#pragma once

#include "mesh_reference.h"

#include <vector>

namespace dng {
namespace leak {

/// How a path that meets the surface met it.
enum class CrossingKind {
  kNone,    ///< the path does not touch the surface
  kEntered, ///< outside -> inside (closed meshes)
  kLeft,    ///< inside -> outside
  kThrough, ///< outside -> outside across the surface: cut a corner, or went through a thin part
  kWithin,  ///< inside -> inside across the surface (a particle already in, crossing inner walls)
};

/// Thresholds of a visible leak, in voxels (issue #10's definition).
constexpr float kVisiblePathDepth = 0.1f;
constexpr float kVisibleEndDepth = 0.05f;

struct StepVerdict {
  CrossingKind kind = CrossingKind::kNone;
  int crossings = 0;         ///< surface crossings along the path (edge hits reported twice count twice)
  float path_depth = 0.0f;   ///< closed: deepest point of the path inside the solid, voxels
  float end_depth = 0.0f;    ///< closed: depth of the end point when it is inside, voxels
  bool end_inside = false;   ///< closed: the end point is inside
  bool through_thin = false; ///< entered and left through opposite-facing faces (a thin part); open: crossed
  /// A leak one would see: a step that gets in (entered or through) deeper than kVisiblePathDepth on
  /// the way, ending deeper than kVisibleEndDepth, or through a thin part; on open meshes, any crossing.
  bool visible = false;
};

class PathJudge {
public:
  /// `closed`: judge depth inside (ray parity); otherwise the mesh is a sheet and any crossing passes it.
  PathJudge(const reference::MeshReference& mesh, bool closed, float voxel)
      : mesh_(mesh), closed_(closed), voxel_(voxel) {}

  /// The path a -> b, given whether a is inside (the previous step's end_inside; false for open meshes).
  /// `scratch` is reused between calls to save allocations; thread-safe with one scratch per thread.
  StepVerdict judge(Vec3f a, Vec3f b, bool a_inside, std::vector<reference::Crossing>* scratch) const;

  /// Depth of `p` inside the solid in voxels, 0 when outside (closed meshes).
  float depth(Vec3f p) const;

private:
  float deepestInside(Vec3f a, Vec3f b, const std::vector<reference::Crossing>& hits) const;

  const reference::MeshReference& mesh_;
  bool closed_;
  float voxel_;
};

} // namespace leak
} // namespace dng
