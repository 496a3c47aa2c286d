// The meshes the leak harness throws particles at: the real ones from disk, and hard cases built in
// code for the features a grid of one-voxel cells handles worst (thin parts, concave edges, walls
// closer together than the band). Every mesh is centred on the origin, so bodies spin and scale
// about its middle.
#pragma once

#include "test_meshes.h"

#include <string>

namespace dng {
namespace leak {

/// A mesh and how to judge it.
struct LeakMesh {
  std::string name;
  testing::Mesh mesh;
  /// Closed solids are judged by depth inside (ray parity); open ones (sheets, tubes open at their
  /// ends) by which side of the surface a particle is on: any crossing passes through.
  bool closed = true;
};

/// Voxels along the longest axis of every bake; the harness's code-made meshes are built so that this
/// resolution gives voxels of exactly one unit (their longest side is kMeshVoxels long).
constexpr int kResolution = 64;
constexpr float kMeshVoxels = 52.0f; // 64 minus the padding of a 3-voxel-per-step band on each side

/// Loads a mesh file with the baker's reader and moves its bounding-box centre to the origin. It is
/// judged closed when it is (no boundary or non-manifold edge: baker::MeshReport::closed), open
/// otherwise. False (with *out_error) when it cannot be read.
bool loadMeshFile(const std::string& path, const std::string& name, LeakMesh* out, std::string* out_error);

/// The mesh's bounding box in its own frame (the harness centres every mesh on the origin).
void meshBounds(const LeakMesh& mesh, Vec3f* lo, Vec3f* hi);

/// A closed plate half a voxel thick, 52 x 40 voxels: thinner than a voxel.
LeakMesh thinPlate();
/// An L-shaped block: a 90-degree concave notch edge along z.
LeakMesh concaveNotch();
/// Thin rods (0.6 voxel square) and fins (0.4 voxel thick) at odd angles, apart from each other.
LeakMesh rodsAndFins();
/// A closed box whose walls are one voxel thick, with its cavity (outside, by parity) inside.
LeakMesh hollowBox();
/// Three parallel plates 1.5 voxels thick with 2-voxel gaps: closer together than the band.
LeakMesh closeFins();

} // namespace leak
} // namespace dng
