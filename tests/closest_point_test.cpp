// The baker's closest-point index (Embree's point queries, closest_point.cpp) against brute force over
// every triangle: the candidates its cheap bounds send away must never include the closest one, also
// where those bounds are least sure (sliver triangles, whose normals floats get wrong, and coordinates
// far from the origin).
#include "mesh_soup.h"
#include "stages.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace dng {
namespace baker {
namespace {

using testing::soupOf;

// A torus, plus slivers: needle triangles at odd angles, a millionth as wide as they are long near the
// origin; farther out as thin as floats there allow (a few steps of them), or they would be segments.
testing::Mesh torusWithSlivers(Vec3f offset) {
  const float thinness = 1e-6f * (1.0f + std::max({std::fabs(offset.x), std::fabs(offset.y), std::fabs(offset.z)}));
  testing::Mesh mesh = testing::torusMesh(offset, 1.0f, 0.35f, 32, 16);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  for (int n = 0; n < 200; ++n) {
    const Vec3f a = offset + Vec3f{u(rng), u(rng), u(rng)}, b = offset + Vec3f{u(rng), u(rng), u(rng)};
    const Vec3f side = normalizeOrZero(cross(b - a, Vec3f{0.3f, 0.5f, 0.81f})) * (thinness * length(b - a));
    const auto first = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back(a);
    mesh.vertices.push_back(b);
    mesh.vertices.push_back((a + b) * 0.5f + side);
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  return mesh;
}

void expectBruteForceDistances(Vec3f offset) {
  const testing::Mesh mesh = torusWithSlivers(offset);
  const TriangleSoup soup = soupOf(mesh);
  ClosestPointIndex index;
  ASSERT_TRUE(index.build(soup).ok());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  int found = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3f p = offset + Vec3f{u(rng), u(rng), u(rng)};
    const float truth = testing::bruteDistance(mesh, p);
    const float tolerance = 1e-5f * (1.0f + std::fabs(offset.x));
    // Within a radius a little over the truth the closest point is found, at the true distance.
    const ClosestPointIndex::Hit hit = index.query(p, truth * 1.01f + tolerance);
    ASSERT_TRUE(hit.found) << "at " << p.x << " " << p.y << " " << p.z << ", " << truth << " away";
    EXPECT_NEAR(hit.distance, truth, tolerance);
    EXPECT_NEAR(length(hit.point - p), hit.distance, tolerance);
    // Within one short of it, nothing is.
    EXPECT_FALSE(index.query(p, truth * 0.99f - tolerance).found);
    // Every triangle within the radius is listed.
    const float radius = truth + 0.05f;
    int listed = 0, within = 0;
    index.forEachTriangleNear(p, radius, [&](std::uint32_t) { ++listed; });
    for (const auto& t : mesh.triangles)
      within += testing::triangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]) <
                        radius - tolerance
                    ? 1
                    : 0;
    EXPECT_GE(listed, within);
    ++found;
  }
  EXPECT_EQ(found, 3000);
}

TEST(ClosestPointIndex, MatchesBruteForceWithSlivers) { expectBruteForceDistances({0.1f, -0.2f, 0.05f}); }

TEST(ClosestPointIndex, MatchesBruteForceFarFromTheOrigin) { expectBruteForceDistances({3000.0f, -2000.0f, 500.0f}); }

} // namespace
} // namespace baker
} // namespace dng
