// The PLN2 section (format 1.3): second planes beside edges, stored sparsely, read by View::lowerBound
// and by the step's walk where a voxel's own plane stops or fails it. The baker's choice of planes, and
// their promise on real shapes, are in bake_test.
#include "analytic_fields.h"
#include "dng/body.h"
#include "dng/format/codec.h"
#include "dng/format/writer.h"
#include "dng/particles.h"
#include "sample_files.h"
#include "swarm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dng {
namespace {

constexpr float kDt = 1.0f / 60.0f;
const Vec3f kBoxHalf{6.25f, 6.25f, 6.25f}; // loweredBoxField's box, centred at the origin

View openView(const std::vector<std::uint8_t>& bytes) {
  View view;
  Diagnostic diag;
  EXPECT_EQ(View::open(bytes.data(), bytes.size(), &view, &diag), Status::kOk) << diag.message;
  return view;
}

std::vector<std::uint8_t> encodeBricks(const format::DenseField& field) {
  format::BrickOptions options;
  options.brick_size = 4;
  const format::EncodeResult encoded = format::encodeBricked(field, options, "");
  EXPECT_TRUE(encoded.ok()) << encoded.error;
  return encoded.bytes;
}

// Whether voxel (i, j, k) got a second plane from addUnloweredSecondPlanes.
bool chosen(const format::DenseField& field, Vec3f p) {
  const format::GridGeometry& g = field.grid;
  const Vec3f u = (p - g.origin) * (1.0f / g.voxel_size);
  const auto i = std::uint32_t(u.x), j = std::uint32_t(u.y), k = std::uint32_t(u.z);
  return std::isfinite(field.second_distance[g.index(i, j, k)]);
}

TEST(SecondPlanes, OnlyBricksCarryThemAndOnlyWhereVoxelsHaveOne) {
  const std::vector<std::uint8_t> bytes = testing::smallBrickedBoxSecondPlanes();
  const View view = openView(bytes);
  ASSERT_TRUE(view.hasSecondPlanes());
  // Sparse: a header, masks and first indices per block, a slot per tile, a record per plane only.
  format::DenseField field = testing::loweredBoxField();
  testing::addUnloweredSecondPlanes(&field);
  const format::SectionEntry section = testing::entryOf(bytes, format::kTagSecondPlanes);
  const auto header = testing::peek<format::SecondPlanesHeader>(bytes, section.offset);
  const std::uint64_t tiles = 6 * 6 * 6;
  EXPECT_EQ(section.size, 8u + header.blocks * 12u + tiles * 4u + header.planes * 8u);
  std::uint64_t planes_given = 0;
  for (float d : field.second_distance)
    planes_given += std::isfinite(d) ? 1 : 0;
  EXPECT_GT(header.planes, planes_given / 2); // far tiles have none; every band voxel of the rest keeps its
  EXPECT_LE(header.planes, planes_given);
  // A dense file has nowhere to put them; a field without them writes no section.
  EXPECT_FALSE(openView(format::encodeDense(field, "").bytes).hasSecondPlanes());
  EXPECT_FALSE(openView(testing::smallBrickedBoxLifted()).hasSecondPlanes());
}

// The higher of the two bounds, each refined at p: where the voxel has a second one, its unlowered plane
// (within quantization; a pair's smaller plane is the own plane raised back to it), which on a box bounds
// the true distance; elsewhere the first plane, bit for bit.
TEST(SecondPlanes, LowerBoundReadsTheHigherOfTheTwoPlanes) {
  format::DenseField field = testing::loweredBoxField();
  testing::addUnloweredSecondPlanes(&field);
  const std::vector<std::uint8_t> bytes = testing::smallBrickedBoxSecondPlanes();
  const View view = openView(bytes);
  const analytic::AnalyticField box = analytic::boxField({0, 0, 0}, kBoxHalf);
  int seconds = 0, firsts = 0;
  for (const Vec3f& p : analytic::randomPoints({-8.9f, -8.9f, -8.9f}, {8.9f, 8.9f, 8.9f}, 4000, 13)) {
    const Sample first = view.sample(p), bound = view.lowerBound(p);
    if (first.status != SampleStatus::kInBand) {
      EXPECT_EQ(bound.distance, first.distance);
      continue;
    }
    EXPECT_GE(bound.distance, first.distance);
    EXPECT_LE(std::min(bound.distance, view.guaranteedReach()), box(p).distance + 1e-4f) << p.x << " " << p.y;
    if (!chosen(field, p)) {
      EXPECT_EQ(bound.distance, first.distance);
      ++firsts;
      continue;
    }
    // The voxel's unlowered plane at p, as the box's tangent at the voxel centre.
    const format::GridGeometry& g = field.grid;
    const Vec3f u = (p - g.origin) * (1.0f / g.voxel_size);
    const Vec3f c = g.voxelCentre(std::uint32_t(u.x), std::uint32_t(u.y), std::uint32_t(u.z));
    const analytic::Exact at = box(c);
    const float unlowered = at.distance + dot(at.normal, p - c);
    if (std::fabs(unlowered) < g.band - 0.1f) {
      EXPECT_GT(bound.distance, unlowered - 0.02f) << p.x << " " << p.y;
    }
    ++seconds;
  }
  EXPECT_GT(seconds, 300);
  EXPECT_GT(firsts, 150);
}

// The lowered box with every band voxel's unlowered plane as its second bound (a third of them as pairs
// with the own plane raised back): particles 0.15 to 0.5 voxel
// above the top face, moving along it at 0.4 voxel per step, where the lowered planes (0.05 to 0.55
// voxel below the truth) leave many unproven. With the second planes every one keeps its whole move;
// without them many stay where they are, as the walk's limit says (docs/RUNTIME.md, "Limits").
TEST(SecondPlanes, TheWalkMovesParticlesTheFirstPlanesCannotProve) {
  format::DenseField field = testing::loweredBoxField();
  testing::addUnloweredSecondPlanes(&field);
  for (std::size_t v = 0; v < field.distance.size(); ++v) {
    if (std::fabs(field.accurate[v]) < field.grid.band && !std::isfinite(field.second_distance[v])) {
      field.second_distance[v] = field.accurate[v];
      field.second_normal[v] = field.normal[v];
    }
  }
  const std::vector<std::uint8_t> with_bytes = encodeBricks(field);
  field.second_distance.clear(), field.second_normal.clear(), field.second_raise.clear();
  const std::vector<std::uint8_t> without_bytes = encodeBricks(field);
  const View with = openView(with_bytes), without = openView(without_bytes);
  ASSERT_TRUE(with.hasSecondPlanes());
  ASSERT_FALSE(without.hasSecondPlanes());

  const float speed = 0.4f / kDt;
  const auto run = [&](const View& view, int* out_stuck) {
    Body body;
    EXPECT_EQ(Body::create(&view, Material{}, &body), Status::kOk);
    testing::Swarm particles;
    std::vector<Vec3f> starts;
    for (int n = 0; n < 200; ++n) {
      const float height = 0.15f + 0.35f * float(n % 17) / 16.0f;
      starts.push_back({-4.0f + 0.037f * float(n), -4.0f + 0.041f * float(n * 7 % 200), kBoxHalf.z + height});
      particles.add(starts.back(), {speed, 0.0f, 0.0f});
    }
    constexpr int kSteps = 6;
    for (int step = 0; step < kSteps; ++step)
      EXPECT_EQ(stepParticles(particles.span(), kDt, &body, 1), Status::kOk);
    *out_stuck = 0;
    for (std::size_t n = 0; n < particles.size(); ++n) {
      const Vec3f p = particles.position(n);
      EXPECT_GT(p.z, kBoxHalf.z) << "inside the box";
      const bool moved = std::fabs(p.x - (starts[n].x + float(kSteps) * speed * kDt)) < 1e-4f;
      *out_stuck += moved ? 0 : 1;
    }
  };
  int stuck_with = -1, stuck_without = -1;
  run(with, &stuck_with);
  run(without, &stuck_without);
  EXPECT_EQ(stuck_with, 0);
  EXPECT_GT(stuck_without, 40); // of 200: the test must show what the planes change
}

} // namespace
} // namespace dng
