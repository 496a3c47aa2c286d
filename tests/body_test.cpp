// Bodies: placing fields with rigid transforms and uniform scale, refusing what breaks normals.
#include "analytic_fields.h"
#include "dng/body.h"
#include "dng/format/writer.h"
#include "dng/particles.h"
#include "sample_files.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dng {
namespace {

class BodyTest : public ::testing::Test {
protected:
  void SetUp() override {
    bytes_ = testing::smallBrickedBox();
    ASSERT_EQ(View::open(bytes_.data(), bytes_.size(), &view_), Status::kOk);
    ASSERT_EQ(Body::create(&view_, Material(), &body_), Status::kOk);
  }
  std::vector<std::uint8_t> bytes_;
  View view_;
  Body body_;
};

TEST_F(BodyTest, RotationTranslationAndScaleRoundTrip) {
  const float c = std::cos(0.7f), s = std::sin(0.7f), k = 2.5f;
  const float m[12] = {k * c, -k * s, 0, 10, k * s, k * c, 0, -3, 0, 0, k, 1};
  ASSERT_EQ(body_.setTransform(m), Status::kOk);
  EXPECT_FLOAT_EQ(body_.scale(), 2.5f);
  const Vec3f local{1.0f, 2.0f, 3.0f};
  const Vec3f world = body_.toWorld(local);
  EXPECT_NEAR(world.x, 10 + k * (c * 1 - s * 2), 1e-4f);
  const Vec3f back = body_.toLocal(world);
  EXPECT_NEAR(back.x, 1.0f, 1e-5f);
  EXPECT_NEAR(back.y, 2.0f, 1e-5f);
  EXPECT_NEAR(back.z, 3.0f, 1e-5f);
  // The box's world bounds contain every transformed grid corner.
  const Vec3f corner = body_.toWorld({12.0f, 12.0f, 12.0f});
  EXPECT_GE(corner.x, body_.boundsMin().x);
  EXPECT_LE(corner.x, body_.boundsMax().x + 1e-4f);
}

TEST_F(BodyTest, QuaternionFormMatchesMatrixForm) {
  const float half = 0.35f;
  const float q[4] = {std::cos(half), 0.0f, 0.0f, std::sin(half)}; // 0.7 rad about z
  ASSERT_EQ(body_.setTransform({10, -3, 1}, q, 2.5f), Status::kOk);
  const Vec3f a = body_.toWorld({1, 2, 3});
  const float c = std::cos(0.7f), s = std::sin(0.7f), k = 2.5f;
  const float m[12] = {k * c, -k * s, 0, 10, k * s, k * c, 0, -3, 0, 0, k, 1};
  ASSERT_EQ(body_.setTransform(m), Status::kOk);
  const Vec3f b = body_.toWorld({1, 2, 3});
  EXPECT_NEAR(a.x, b.x, 1e-4f);
  EXPECT_NEAR(a.y, b.y, 1e-4f);
  EXPECT_NEAR(a.z, b.z, 1e-4f);
}

TEST_F(BodyTest, RejectsWhatBreaksNormalsAndKeepsThePreviousTransform) {
  const float good[12] = {2, 0, 0, 5, 0, 2, 0, 0, 0, 0, 2, 0};
  ASSERT_EQ(body_.setTransform(good), Status::kOk);
  const float shear[12] = {1, 0.5f, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const float non_uniform[12] = {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0};
  const float mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const float zero[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  const float nan[12] = {NAN, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  for (const float* m : {shear, non_uniform, mirror, zero, nan}) {
    Diagnostic diag;
    EXPECT_EQ(body_.setTransform(m, &diag), Status::kInvalidArgument);
    EXPECT_NE(diag.message[0], '\0');
  }
  Diagnostic diag;
  body_.setTransform(shear, &diag);
  EXPECT_NE(std::string(diag.message).find("shear"), std::string::npos);
  body_.setTransform(non_uniform, &diag);
  EXPECT_NE(std::string(diag.message).find("non-uniform"), std::string::npos);
  EXPECT_FLOAT_EQ(body_.scale(), 2.0f);
  EXPECT_FLOAT_EQ(body_.translation().x, 5.0f);
}

// Scales far from 1 either way: the checks run in double, so a float column's squared length, which
// overflows above about 1.8e19 and turns subnormal below about 1e-19, neither passes a scale of
// infinity nor a rotation that is not orthonormal; a scale whose inverse is not a normal float, or
// whose placed box overflows, is refused.
TEST_F(BodyTest, ScalesFarFromOneKeepAnOrthonormalRotationOrAreRefused) {
  for (const float k : {1e20f, 3e-23f, 1e-30f}) {
    const float m[12] = {k, 0, 0, 1, 0, k, 0, 2, 0, 0, k, 3};
    ASSERT_EQ(body_.setTransform(m), Status::kOk) << k;
    EXPECT_EQ(body_.scale(), k);
    const float* r = body_.rotation();
    for (int n = 0; n < 9; ++n)
      EXPECT_NEAR(r[n], n % 4 == 0 ? 1.0f : 0.0f, 1e-6f) << k << " entry " << n;
    EXPECT_TRUE(std::isfinite(body_.boundsMin().x) && std::isfinite(body_.boundsMax().z)) << k;
  }
  const float q[4] = {1, 0, 0, 0};
  ASSERT_EQ(body_.setTransform({0, 0, 0}, q, 3e19f), Status::kOk);
  EXPECT_EQ(body_.scale(), 3e19f);
  EXPECT_NEAR(body_.rotation()[0], 1.0f, 1e-6f);
  const float good[12] = {2, 0, 0, 5, 0, 2, 0, 0, 0, 0, 2, 0};
  ASSERT_EQ(body_.setTransform(good), Status::kOk);
  for (const float k : {1e38f, 1e-39f, 3e37f}) { // inverse subnormal; scale subnormal; box overflows
    const float m[12] = {k, 0, 0, 0, 0, k, 0, 0, 0, 0, k, 0};
    Diagnostic diag;
    EXPECT_EQ(body_.setTransform(m, &diag), Status::kInvalidArgument) << k;
    EXPECT_NE(diag.message[0], '\0');
  }
  const float huge_q[4] = {1e30f, 0, 0, 0}, tiny_q[4] = {1e-30f, 0, 0, 0};
  ASSERT_EQ(body_.setTransform({0, 0, 0}, huge_q, 1.0f), Status::kOk);
  EXPECT_EQ(body_.rotation()[0], 1.0f);
  ASSERT_EQ(body_.setTransform({0, 0, 0}, tiny_q, 1.0f), Status::kOk);
  EXPECT_EQ(body_.rotation()[0], 1.0f);
  ASSERT_EQ(body_.setTransform(good), Status::kOk);
  EXPECT_EQ(body_.setTransform({0, 0, 0}, q, 1e38f), Status::kInvalidArgument);
  EXPECT_EQ(body_.scale(), 2.0f); // unchanged
}

// A band too thin for the walk's balls (its guaranteed reach under the margin) cannot carry a body:
// every walk's ball would have a negative radius, and particles froze in the field's box.
format::EncodeResult sphereFile(float band_voxels) {
  return format::encodeDense(
      analytic::sampleField(analytic::cubeGrid({-4, -4, -4}, 0.25f, 32, band_voxels), analytic::sphereField({}, 2.0f)),
      "");
}

TEST_F(BodyTest, AFieldWhoseBandIsTooThinIsRefused) {
  for (const float band : {0.5f, 0.9f, 1.0f}) {
    const format::EncodeResult file = sphereFile(band);
    ASSERT_TRUE(file.ok()) << file.error;
    View view;
    ASSERT_EQ(View::open(file.bytes.data(), file.bytes.size(), &view), Status::kOk);
    Body body;
    Diagnostic diag;
    const Status status = Body::create(&view, Material(), &body, &diag);
    if (band < 0.93f) {
      EXPECT_EQ(status, Status::kInvalidArgument) << band;
      EXPECT_NE(std::string(diag.message).find("too thin"), std::string::npos) << diag.message;
      EXPECT_FALSE(body.valid());
    } else {
      EXPECT_EQ(status, Status::kOk) << band << ": " << diag.message; // dngbake's thinnest band
    }
  }
  // A View opened again in place on such a file: the step refuses the body it now carries, and moves
  // no particle (the body was made when the band was thick enough).
  const format::EncodeResult thick = sphereFile(3.0f), thin = sphereFile(0.5f);
  View view;
  ASSERT_EQ(View::open(thick.bytes.data(), thick.bytes.size(), &view), Status::kOk);
  Body body;
  ASSERT_EQ(Body::create(&view, Material(), &body), Status::kOk);
  ASSERT_EQ(View::open(thin.bytes.data(), thin.bytes.size(), &view), Status::kOk);
  float x = 3.0f, y = 0.0f, z = 0.0f, vx = -1.0f, vy = 0.0f, vz = 0.0f;
  ParticleSpan one;
  one.position_x = &x, one.position_y = &y, one.position_z = &z;
  one.velocity_x = &vx, one.velocity_y = &vy, one.velocity_z = &vz;
  one.count = 1;
  Diagnostic diag;
  EXPECT_EQ(stepParticles(one, 0.1f, &body, 1, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("too thin"), std::string::npos) << diag.message;
  EXPECT_EQ(x, 3.0f);
}

TEST_F(BodyTest, RejectsInvalidFieldsAndMaterials) {
  Body body;
  EXPECT_EQ(Body::create(nullptr, Material(), &body), Status::kInvalidArgument);
  View empty;
  EXPECT_EQ(Body::create(&empty, Material(), &body), Status::kInvalidArgument);
  EXPECT_FALSE(body.valid());
  Material bad;
  bad.restitution = -0.5f;
  EXPECT_EQ(Body::create(&view_, bad, &body), Status::kInvalidArgument);
  bad = Material();
  bad.drag = NAN;
  EXPECT_EQ(body_.setMaterial(bad), Status::kInvalidArgument);
  bad = Material();
  bad.response = Response(9);
  EXPECT_EQ(body_.setMaterial(bad), Status::kInvalidArgument);
}

TEST_F(BodyTest, SurfaceVelocityIncludesRotation) {
  body_.setVelocity({1, 0, 0}, {0, 0, 2}); // spinning about +z at 2 rad/s
  const Vec3f v = body_.surfaceVelocity({0, 3, 0});
  EXPECT_FLOAT_EQ(v.x, 1.0f - 6.0f);
  EXPECT_FLOAT_EQ(v.y, 0.0f);
}

} // namespace
} // namespace dng
