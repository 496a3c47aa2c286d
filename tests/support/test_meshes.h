// Procedural meshes for the baker's tests, and an independent brute-force reference: closest point
// by plane projection and segment distances (not the baker's Voronoi-region code) and the exact
// generalized winding number summed over every triangle (no hierarchy).
#pragma once

#include "dng/format/vec3.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dng {
namespace testing {

struct Mesh {
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

Mesh boxMesh(Vec3f centre, Vec3f half);
Mesh sphereMesh(Vec3f centre, float radius, int slices, int stacks);
Mesh cylinderMesh(Vec3f centre, float radius, float half_height, int segments);
Mesh torusMesh(Vec3f centre, float major, float minor, int major_segments, int minor_segments);
/// An L-shaped block: the square [0, 2]^2 without its [1, 2]^2 quarter, extruded over z in [0, depth],
/// then scaled by `size` and moved by `origin`. Its inner edge is a 90-degree concave crease.
Mesh lBlockMesh(Vec3f origin, float size, float depth);
/// A square sheet of zero thickness in the plane z = centre.z.
Mesh sheetMesh(Vec3f centre, float half);
/// The same triangles with every vertex duplicated per triangle: no shared connectivity at all.
Mesh toSoup(const Mesh& mesh);
/// Drops the triangles whose centroid has the largest value along `axis` (opens a box's face).
Mesh withoutFace(const Mesh& box, int axis);

void writeObj(const Mesh& mesh, const std::string& path);

/// Distance from p to the triangle abc: its plane where p projects inside it, else the nearest edge.
float triangleDistance(Vec3f p, Vec3f a, Vec3f b, Vec3f c);
/// Brute force over all triangles.
float bruteDistance(const Mesh& mesh, Vec3f p);
double bruteWinding(const Mesh& mesh, Vec3f p);

} // namespace testing
} // namespace dng
