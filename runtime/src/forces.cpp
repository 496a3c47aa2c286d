// Non-collision forces for particle systems (dng/forces.h).
#include "dng/forces.h"

#include <cmath>

namespace dng {

namespace {

float& component(float* base, std::size_t stride, std::size_t n) {
  return *reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(base) + n * stride);
}

template <class Change> void updateVelocities(const ParticleSpan& s, Change change) {
  for (std::size_t n = 0; n < s.count; ++n) {
    float& vx = component(s.velocity_x, s.velocity_stride, n);
    float& vy = component(s.velocity_y, s.velocity_stride, n);
    float& vz = component(s.velocity_z, s.velocity_stride, n);
    const Vec3f p{component(s.position_x, s.position_stride, n), component(s.position_y, s.position_stride, n),
                  component(s.position_z, s.position_stride, n)};
    const Vec3f v = change(p, Vec3f{vx, vy, vz});
    vx = v.x;
    vy = v.y;
    vz = v.z;
  }
}

} // namespace

void applyGravity(const ParticleSpan& particles, Vec3f gravity, float dt) {
  const Vec3f dv = gravity * dt;
  updateVelocities(particles, [dv](Vec3f, Vec3f v) { return v + dv; });
}

void applyAirDrag(const ParticleSpan& particles, Vec3f wind, float rate, float dt) {
  const float blend = 1.0f - std::exp(-rate * dt);
  updateVelocities(particles, [wind, blend](Vec3f, Vec3f v) { return v + (wind - v) * blend; });
}

void applyExplosion(const ParticleSpan& particles, Vec3f centre, float strength, float radius, float dt) {
  const float inv_radius_sq = 1.0f / (radius * radius);
  updateVelocities(particles, [=](Vec3f p, Vec3f v) {
    const Vec3f r = p - centre;
    const float r_sq = dot(r, r);
    if (!(r_sq > 0.0f)) return v;
    const float accel = strength / (1.0f + r_sq * inv_radius_sq);
    return v + r * (accel * dt / std::sqrt(r_sq));
  });
}

} // namespace dng
