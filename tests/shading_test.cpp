// The SHAD section (format 1.3): shading normals beside planes that carry the distance's own normal.
// Queries answer with them, the step's rules bounce off them, the accurate query and the walk ignore
// them, and the section pads to whole 32-bit words. The blurred bakes' own use of it is in bake_test.
#include "analytic_fields.h"
#include "dng/format/writer.h"
#include "dng/particles.h"
#include "sample_files.h"
#include "swarm.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dng {
namespace {

constexpr float kDt = 1.0f / 60.0f;
const Vec3f kTilted = normalizeOrZero(Vec3f{0.3f, 0.0f, 1.0f}); // the shading normal everywhere

// The half-space z < 0 in a dense 9^3 grid of unit voxels (729 voxels: an odd count), with every
// voxel's shading normal tilted away from the plane's +z when `shaded`.
struct PlaneFile {
  std::vector<std::uint8_t> bytes;
  View view;
  explicit PlaneFile(bool shaded) {
    format::DenseField field = analytic::sampleField(analytic::cubeGrid({-4.5f, -4.5f, -4.5f}, 1.0f, 9, 3.0f),
                                                     analytic::planeField({0, 0, 1}, 0));
    if (shaded) field.shading.assign(field.normal.size(), kTilted);
    const format::EncodeResult encoded = format::encodeDense(field, "");
    EXPECT_TRUE(encoded.ok()) << encoded.error;
    bytes = encoded.bytes;
    EXPECT_EQ(View::open(bytes.data(), bytes.size(), &view), Status::kOk);
  }
};

TEST(Shading, TheSectionPadsToWholeWordsAndAnUnpaddedOneIsRefused) {
  PlaneFile file(true);
  ASSERT_TRUE(file.view.hasShading());
  EXPECT_EQ(testing::entryOf(file.bytes, format::kTagShading).size, 730u * 2u);
  EXPECT_FALSE(PlaneFile(false).view.hasShading());

  std::vector<std::uint8_t> unpadded = file.bytes;
  const std::size_t entry = testing::entryOffset(unpadded, format::kTagShading);
  testing::poke(unpadded, entry + offsetof(format::SectionEntry, size), std::uint64_t(729u * 2u));
  format::resealHashes(unpadded);
  View view;
  Diagnostic diag;
  EXPECT_EQ(View::open(unpadded.data(), unpadded.size(), &view, &diag), Status::kBadPayloadSize);
  EXPECT_NE(std::string(diag.message).find("SHAD"), std::string::npos) << diag.message;
}

TEST(Shading, QueriesAnswerWithTheShadingNormalAndTheAccurateQueryWithTheDistances) {
  PlaneFile shaded(true), plain(false);
  int in_band = 0;
  for (const Vec3f& p : analytic::randomPoints({-4.4f, -4.4f, -2.5f}, {4.4f, 4.4f, 2.5f}, 400, 5)) {
    for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear}) {
      const Sample a = shaded.view.sample(p, mode), b = plain.view.sample(p, mode);
      ASSERT_EQ(a.status, b.status);
      ASSERT_EQ(a.distance, b.distance); // the planes are the same
      if (a.status != SampleStatus::kInBand) continue;
      ++in_band;
      EXPECT_LT(analytic::angleDegrees(a.normal, kTilted), 1.0f); // 8-bit octahedral words
      EXPECT_LT(analytic::angleDegrees(b.normal, Vec3f{0, 0, 1}), 1e-3f);
    }
    const Sample a = shaded.view.sample(p, Interpolation::kAccurate),
                 b = plain.view.sample(p, Interpolation::kAccurate);
    ASSERT_EQ(a.status, b.status);
    ASSERT_EQ(a.distance, b.distance);
    ASSERT_EQ(a.normal.x, b.normal.x);
    ASSERT_EQ(a.normal.z, b.normal.z);
  }
  EXPECT_GT(in_band, 300);
}

// Particles moving straight down onto the plane, one voxel per step, impact with beta 0.5: the rule
// reflects their velocity about the shading normal, v - (1 + beta)(v . n) n, so they leave sideways.
TEST(Shading, TheStepBouncesOffTheShadingNormal) {
  for (bool shaded : {true, false}) {
    SCOPED_TRACE(shaded ? "shaded" : "plain");
    PlaneFile file(shaded);
    Body body;
    ASSERT_EQ(Body::create(&file.view, Material{}, &body), Status::kOk);
    testing::Swarm particles;
    const Vec3f v{0.0f, 0.0f, -60.0f};
    std::vector<Vec3f> starts;
    for (int n = 0; n < 16; ++n) {
      starts.push_back({-2.0f + 0.25f * float(n), 0.5f - 0.05f * float(n % 4), 0.5f});
      particles.add(starts.back(), v);
    }
    ASSERT_EQ(stepParticles(particles.span(), kDt, &body, 1), Status::kOk);
    for (std::size_t n = 0; n < particles.size(); ++n) {
      const Vec3f normal = file.view.sample(starts[n]).normal;
      EXPECT_LT(analytic::angleDegrees(normal, shaded ? kTilted : Vec3f{0, 0, 1}), 1.0f);
      const Vec3f want = v - normal * (1.5f * dot(v, normal));
      const Vec3f got = particles.velocity(n);
      EXPECT_LT(length(got - want), 1e-4f * length(want)) << n;
      EXPECT_GT(particles.position(n).z, 0.5f) << n; // the move went away from the plane
    }
  }
}

} // namespace
} // namespace dng
