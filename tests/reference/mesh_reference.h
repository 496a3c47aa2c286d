// The judge's view of a mesh: exact geometric queries on the ORIGINAL triangles, through Embree 3, with
// no DN field involved. The leak harness and the accuracy comparison check the runtime against it.
//
//   closest()    unsigned distance and closest point (rtcPointQuery, exact point-triangle distance)
//   inside()     ray parity for closed meshes: a majority vote over three non-axis-aligned rays whose
//                hits are all clear of triangle edges (a ray through an edge or vertex may count one
//                crossing twice or not at all, so such rays are set aside for the next direction)
//   crossings()  every place a segment meets a triangle, in order along it
#pragma once

#include "dng/format/vec3.h"

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace dng {
namespace reference {

/// Where a segment meets the surface.
struct Crossing {
  float t = 0.0f;             ///< along the segment, in [0, 1]
  std::uint32_t triangle = 0; ///< index into the triangles given to build()
  bool near_edge = false;     ///< the hit is within a hair of the triangle's edges (ambiguous)
};

/// The closest surface point.
struct Closest {
  bool found = false;    ///< false when nothing lies within the search radius
  float distance = 0.0f; ///< unsigned
  Vec3f point;
  std::uint32_t triangle = 0;
};

/// An Embree scene over a triangle soup. build() once, then every query is const and thread-safe.
/// Degenerate and non-finite triangles are left out of the scene (they have no surface).
class MeshReference {
public:
  MeshReference();
  ~MeshReference();
  MeshReference(const MeshReference&) = delete;
  MeshReference& operator=(const MeshReference&) = delete;

  /// Copies the triangles into Embree's buffers; false when Embree fails or nothing is left.
  bool build(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles);

  /// The closest point on the surface within `radius` of `p` (a finite radius makes far queries cheap).
  Closest closest(Vec3f p, float radius = std::numeric_limits<float>::infinity()) const;

  /// Whether `p` lies inside a closed mesh (meaningless for open ones: use crossings() there). Points
  /// on the surface itself may go either way.
  bool inside(Vec3f p) const;

  /// Every crossing of the segment a -> b with the triangles, sorted by t (two triangles sharing an edge
  /// the segment passes through both report it). Clears and fills *out.
  void crossings(Vec3f a, Vec3f b, std::vector<Crossing>* out) const;

  /// Unit geometric normal of a triangle (by its winding: outward on an outward-oriented mesh).
  Vec3f faceNormal(std::uint32_t triangle) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace reference
} // namespace dng
