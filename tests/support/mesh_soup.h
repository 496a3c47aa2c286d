// A test mesh as the baker's stages take it (baker-side tests only: needs the baker's stages.h).
#pragma once

#include "stages.h"
#include "test_meshes.h"

namespace dng {
namespace testing {

/// The same vertices and triangles as a baker::TriangleSoup.
inline baker::TriangleSoup soupOf(const Mesh& mesh) {
  baker::TriangleSoup soup;
  soup.vertices = mesh.vertices;
  soup.triangles = mesh.triangles;
  return soup;
}

} // namespace testing
} // namespace dng
