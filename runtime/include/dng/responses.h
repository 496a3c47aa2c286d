// The paper's particle responses as pure functions (Ilmonen, Takala & Laitinen, §3.3-3.6).
//
// Each takes the contact (distance and unit normal in the world frame, from a DN field sample) and a
// velocity relative to the body's surface, and changes that velocity for one step of dt. They return
// true when they acted. stepParticles calls them; engines with their own particle loops may too.
// Header-only, inline, no allocation, no branches on anything but the rules themselves.
#pragma once

#include "dng/body.h"
#include "dng/format/vec3.h"

#include <cmath>

namespace dng {

/// A particle's view of a surface: signed distance (world units, negative inside) and unit normal.
struct Contact {
  float distance = 0.0f;
  Vec3f normal;
};

/// Impact, §3.4 and Fig. 4: when the particle moves towards the surface (V.N < 0) and would reach
/// the collision distance L within this step (d <= L + |V.N| dt), reflect: W = V - (1 + beta)(V.N)N.
/// Fast particles therefore bounce as soon as they enter the field, slow ones close to L.
inline bool applyImpact(const Contact& c, float restitution, float collision_distance, float dt, Vec3f* io_velocity) {
  const float vn = dot(*io_velocity, c.normal);
  if (!(vn < 0.0f) || c.distance > collision_distance - vn * dt) return false;
  *io_velocity = *io_velocity - c.normal * ((1.0f + restitution) * vn);
  return true;
}

/// Spring, §3.3: inside `reach` of the surface, accelerate along N by stiffness * (reach - d).
inline bool applySpring(const Contact& c, float stiffness, float reach, float dt, Vec3f* io_velocity) {
  if (!(c.distance < reach)) return false;
  *io_velocity = *io_velocity + c.normal * (stiffness * (reach - c.distance) * dt);
  return true;
}

/// Drag, §3.5: within contact distance theta, the tangential velocity decays at rate delta. Implicit
/// (v_t / (1 + delta dt)) so it is stable for any dt; the normal component is untouched.
inline bool applyDrag(const Contact& c, float delta, float theta, float dt, Vec3f* io_velocity) {
  if (!(c.distance < theta) || delta <= 0.0f) return false;
  const Vec3f normal_part = c.normal * dot(*io_velocity, c.normal);
  const Vec3f tangential = *io_velocity - normal_part;
  *io_velocity = normal_part + tangential * (1.0f / (1.0f + delta * dt));
  return true;
}

/// Surface flow, §3.6: gamma = N.V; E = (V x N) x V; F = rho_in E/|E| if gamma < 0 else rho_out E/|E|.
/// F is perpendicular to V and turns the particle onto a path tangential to the surface.
inline bool applySurfaceFlow(const Contact& c, float rho_in, float rho_out, float reach, float dt, Vec3f* io_velocity) {
  if (!(c.distance < reach)) return false;
  const Vec3f v = *io_velocity;
  const float gamma = dot(c.normal, v);
  const Vec3f e = cross(cross(v, c.normal), v);
  const float e_length = length(e);
  if (!(e_length > 1e-20f)) return false; // V parallel to N, or at rest: no tangential direction
  const float rho = gamma < 0.0f ? rho_in : rho_out;
  *io_velocity = v + e * (rho * dt / e_length);
  return true;
}

/// All of a material's responses in the paper's order: bounce (impact or spring), then drag, then
/// surface flow. `field_band` (world units) is the spring's reach when the material leaves it 0.
inline bool respond(const Material& m, const Contact& c, float field_band, float dt, Vec3f* io_velocity) {
  bool acted = false;
  if (m.response == Response::kImpact) {
    acted |= applyImpact(c, m.restitution, m.collision_distance, dt, io_velocity);
  } else if (m.response == Response::kSpring) {
    const float reach = m.spring_distance > 0.0f ? m.spring_distance : field_band;
    acted |= applySpring(c, m.spring_stiffness, reach, dt, io_velocity);
  }
  acted |= applyDrag(c, m.drag, m.contact_distance, dt, io_velocity);
  if (m.flow_in != 0.0f || m.flow_out != 0.0f)
    acted |= applySurfaceFlow(c, m.flow_in, m.flow_out, m.flow_distance, dt, io_velocity);
  return acted;
}

} // namespace dng
