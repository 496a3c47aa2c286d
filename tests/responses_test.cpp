// The paper's response rules (§3.3-3.6) as pure functions.
#include "analytic_fields.h"
#include "dng/responses.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dng {
namespace {

const Contact kFloor{0.05f, {0.0f, 0.0f, 1.0f}}; // 0.05 above a floor whose normal is +z
constexpr float kDt = 1.0f / 60.0f;

TEST(Impact, RestitutionOneKeepsSpeedZeroRemovesNormalComponent) {
  Vec3f v{3.0f, -1.0f, -4.0f};
  ASSERT_TRUE(applyImpact(kFloor, 1.0f, 0.1f, kDt, &v));
  EXPECT_FLOAT_EQ(length(v), length(Vec3f{3.0f, -1.0f, -4.0f}));
  EXPECT_FLOAT_EQ(v.z, 4.0f);
  EXPECT_FLOAT_EQ(v.x, 3.0f);

  Vec3f w{3.0f, -1.0f, -4.0f};
  ASSERT_TRUE(applyImpact(kFloor, 0.0f, 0.1f, kDt, &w));
  EXPECT_FLOAT_EQ(w.z, 0.0f);
  EXPECT_FLOAT_EQ(w.x, 3.0f);
  EXPECT_FLOAT_EQ(w.y, -1.0f);

  Vec3f half{0.0f, 0.0f, -4.0f};
  ASSERT_TRUE(applyImpact(kFloor, 0.5f, 0.1f, kDt, &half));
  EXPECT_FLOAT_EQ(half.z, 2.0f);
}

TEST(Impact, LeavingParticlesAreNotBounced) {
  Vec3f v{1.0f, 0.0f, 2.0f};
  EXPECT_FALSE(applyImpact(kFloor, 0.5f, 0.1f, kDt, &v));
  EXPECT_FLOAT_EQ(v.z, 2.0f);
}

// Fig. 4: fast particles bounce as soon as they enter the field, slow ones only near L.
TEST(Impact, VelocityAwareThreshold) {
  const Contact entering{2.9f, {0.0f, 0.0f, 1.0f}}; // just inside a 3-unit band
  Vec3f fast{0.0f, 0.0f, -200.0f};                  // would travel 3.3 units this step
  Vec3f slow{0.0f, 0.0f, -1.0f};                    // would travel 0.017 units
  EXPECT_TRUE(applyImpact(entering, 0.5f, 0.1f, kDt, &fast));
  EXPECT_FALSE(applyImpact(entering, 0.5f, 0.1f, kDt, &slow));
  const Contact near_l{0.11f, {0.0f, 0.0f, 1.0f}};
  EXPECT_TRUE(applyImpact(near_l, 0.5f, 0.1f, kDt, &slow));
}

TEST(Spring, PushesOutAlongTheNormalMoreWhenDeeper) {
  Vec3f shallow{1.0f, 0.0f, -2.0f}, deep{1.0f, 0.0f, -2.0f};
  ASSERT_TRUE(applySpring({2.5f, {0, 0, 1}}, 400.0f, 3.0f, kDt, &shallow));
  ASSERT_TRUE(applySpring({0.5f, {0, 0, 1}}, 400.0f, 3.0f, kDt, &deep));
  EXPECT_GT(shallow.z, -2.0f);
  EXPECT_GT(deep.z, shallow.z);
  EXPECT_FLOAT_EQ(deep.x, 1.0f); // along the normal only
  Vec3f outside{0, 0, -2};
  EXPECT_FALSE(applySpring({3.5f, {0, 0, 1}}, 400.0f, 3.0f, kDt, &outside));
}

TEST(Drag, ReducesTangentialSpeedOnlyWithinTheta) {
  Vec3f v{4.0f, 3.0f, -1.0f};
  ASSERT_TRUE(applyDrag(kFloor, 2.0f, 1.0f, kDt, &v));
  EXPECT_FLOAT_EQ(v.z, -1.0f);
  EXPECT_LT(std::hypot(v.x, v.y), 5.0f);
  EXPECT_FLOAT_EQ(v.x / v.y, 4.0f / 3.0f); // direction kept
  Vec3f far_away{4.0f, 3.0f, -1.0f};
  EXPECT_FALSE(applyDrag({1.5f, {0, 0, 1}}, 2.0f, 1.0f, kDt, &far_away));
  // Implicit: even an absurd rate never reverses the tangential velocity.
  Vec3f stiff{4.0f, 0.0f, 0.0f};
  applyDrag(kFloor, 1e9f, 1.0f, kDt, &stiff);
  EXPECT_GE(stiff.x, 0.0f);
}

TEST(SurfaceFlow, ForceIsPerpendicularToVelocityAndPicksRhoBySide) {
  const Vec3f n{0.0f, 0.0f, 1.0f};
  for (const Vec3f v0 : {Vec3f{2.0f, 0.5f, -1.0f}, Vec3f{2.0f, 0.5f, 1.0f}}) {
    Vec3f v = v0;
    ASSERT_TRUE(applySurfaceFlow({0.5f, n}, 12.0f, 3.0f, 1.0f, kDt, &v));
    const Vec3f dv = v - v0;
    EXPECT_NEAR(dot(dv, v0), 0.0f, 1e-5f);
    const float expected_rho = dot(n, v0) < 0.0f ? 12.0f : 3.0f;
    EXPECT_NEAR(length(dv), expected_rho * kDt, 1e-5f);
    // E = |V|^2 N - (N.V) V: for positive rho the push has a component away from the surface.
    EXPECT_GT(dv.z, 0.0f);
  }
  Vec3f attract{2.0f, 0.0f, 1.0f};
  ASSERT_TRUE(applySurfaceFlow({0.5f, n}, 3.0f, -3.0f, 1.0f, kDt, &attract));
  EXPECT_LT(attract.z, 1.0f); // rho_out < 0 pulls leaving particles back towards the surface
  Vec3f head_on{0.0f, 0.0f, -2.0f};
  EXPECT_FALSE(applySurfaceFlow({0.5f, n}, 12.0f, 3.0f, 1.0f, kDt, &head_on)); // no tangential direction
  Vec3f beyond{2.0f, 0.0f, -1.0f};
  EXPECT_FALSE(applySurfaceFlow({1.5f, n}, 12.0f, 3.0f, 1.0f, kDt, &beyond));
}

TEST(Respond, CombinesTheMaterialsRulesInOrder) {
  Material m;
  m.restitution = 0.0f;
  m.collision_distance = 0.1f;
  m.drag = 2.0f;
  m.contact_distance = 1.0f;
  Vec3f v{4.0f, 0.0f, -3.0f};
  ASSERT_TRUE(respond(m, kFloor, 3.0f, kDt, &v));
  EXPECT_FLOAT_EQ(v.z, 0.0f); // bounced with beta = 0
  EXPECT_LT(v.x, 4.0f);       // and dragged
  m.response = Response::kNone;
  m.drag = 0.0f;
  Vec3f untouched{4.0f, 0.0f, -3.0f};
  EXPECT_FALSE(respond(m, kFloor, 3.0f, kDt, &untouched));
}

} // namespace
} // namespace dng
