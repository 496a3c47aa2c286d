// Internal: a body's placement at one instant, and where its motion takes it within a step.
#pragma once

#include "dng/body.h"

#include <cmath>

namespace dng {

/// A rigid placement with uniform scale: world = t + s * R * local, R row-major and orthonormal.
struct Pose {
  float r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3f t;
  float scale = 1.0f;
  float inv_scale = 1.0f;

  Vec3f toLocal(Vec3f world) const {
    const Vec3f d = world - t; // R^T d / s
    return Vec3f{r[0] * d.x + r[3] * d.y + r[6] * d.z, r[1] * d.x + r[4] * d.y + r[7] * d.z,
                 r[2] * d.x + r[5] * d.y + r[8] * d.z} *
           inv_scale;
  }
  Vec3f rotateToWorld(Vec3f v) const {
    return {r[0] * v.x + r[1] * v.y + r[2] * v.z, r[3] * v.x + r[4] * v.y + r[5] * v.z,
            r[6] * v.x + r[7] * v.y + r[8] * v.z};
  }
  Vec3f toWorld(Vec3f local) const { return t + rotateToWorld(local * scale); }
};

/// The body's pose now (the start of a step).
inline Pose currentPose(const Body& body) {
  Pose pose;
  for (int n = 0; n < 9; ++n)
    pose.r[n] = body.rotation()[n];
  pose.t = body.translation();
  pose.scale = body.scale();
  pose.inv_scale = 1.0f / body.scale();
  return pose;
}

/// The body's pose after moving for `dt` at its linear and angular velocity: translated by v dt and
/// turned by |w| dt about w through its origin (Rodrigues' formula), exact for constant velocities.
inline Pose poseAfter(const Body& body, float dt) {
  Pose pose = currentPose(body);
  pose.t = pose.t + body.linearVelocity() * dt;
  const Vec3f w = body.angularVelocity();
  const float angle = length(w) * dt;
  if (!(angle > 0.0f)) return pose;
  const Vec3f k = w * (dt / angle);
  const float s = std::sin(angle), c = 1.0f - std::cos(angle);
  const float turn[9] = {
      1 - c * (k.y * k.y + k.z * k.z), -s * k.z + c * k.x * k.y,        s * k.y + c * k.x * k.z,
      s * k.z + c * k.x * k.y,         1 - c * (k.x * k.x + k.z * k.z), -s * k.x + c * k.y * k.z,
      -s * k.y + c * k.x * k.z,        s * k.x + c * k.y * k.z,         1 - c * (k.x * k.x + k.y * k.y)};
  const Pose before = pose;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      pose.r[3 * row + col] =
          turn[3 * row] * before.r[col] + turn[3 * row + 1] * before.r[3 + col] + turn[3 * row + 2] * before.r[6 + col];
  return pose;
}

} // namespace dng
