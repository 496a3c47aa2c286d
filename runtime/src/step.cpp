// stepParticles: responses per body (paper §3.3-3.6), then integration, optionally swept.
//
// Everything happens in the world frame: only the particle position goes into a body's frame for the
// field lookup, and the distance (times the body's scale) and the normal (rotated) come back out. So
// velocities are never transformed and a uniformly scaled body behaves like the same scene built at
// that scale (tests/particles_test.cpp checks it).
#include "diagnostic.h"
#include "dng/particles.h"
#include "dng/responses.h"
#include "sweep.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace dng {

namespace {

struct ParticleState {
  Vec3f position;
  Vec3f velocity;
};

float* at(float* base, std::size_t stride, std::size_t n) {
  return reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(base) + n * stride);
}

ParticleState load(const ParticleSpan& s, std::size_t n) {
  return {{*at(s.position_x, s.position_stride, n), *at(s.position_y, s.position_stride, n),
           *at(s.position_z, s.position_stride, n)},
          {*at(s.velocity_x, s.velocity_stride, n), *at(s.velocity_y, s.velocity_stride, n),
           *at(s.velocity_z, s.velocity_stride, n)}};
}

void store(const ParticleSpan& s, std::size_t n, const ParticleState& p) {
  *at(s.position_x, s.position_stride, n) = p.position.x;
  *at(s.position_y, s.position_stride, n) = p.position.y;
  *at(s.position_z, s.position_stride, n) = p.position.z;
  *at(s.velocity_x, s.velocity_stride, n) = p.velocity.x;
  *at(s.velocity_y, s.velocity_stride, n) = p.velocity.y;
  *at(s.velocity_z, s.velocity_stride, n) = p.velocity.z;
}

bool insideBounds(const Body& b, Vec3f p) {
  const Vec3f lo = b.boundsMin(), hi = b.boundsMax();
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// Which body touched the particle, if any: the nearest of those that acted.
struct Touch {
  std::int32_t body = -1;
  float distance = std::numeric_limits<float>::infinity();
  void record(std::size_t index, float d) {
    if (d < distance) {
      distance = d;
      body = std::int32_t(index);
    }
  }
};

// The nearest body whose band the particle started the step in, for the contact guard.
struct Guard {
  std::int32_t body = -1;
  float distance = std::numeric_limits<float>::infinity(); // world units, at the start of the step
};

// The body's surface as seen from world point `p`, when p lies within the body's band: distance
// scaled to world units, normal rotated to world. False outside the bounds or the band.
bool contactAt(const Body& body, Vec3f p, Contact* out) {
  if (!insideBounds(body, p)) return false;
  const Sample s = body.field()->sample(body.toLocal(p));
  if (s.status != SampleStatus::kInBand) return false;
  *out = {s.distance * body.scale(), body.rotateToWorld(s.normal)};
  return true;
}

// Samples one body at the particle and applies its material to the velocity relative to its surface.
void respondToBody(const Body& body, std::size_t index, float dt, ParticleState* io, Touch* io_touch, Guard* io_guard) {
  Contact contact;
  if (!contactAt(body, io->position, &contact)) return;
  if (contact.distance < io_guard->distance) *io_guard = {std::int32_t(index), contact.distance};
  const Vec3f surface = body.surfaceVelocity(io->position);
  Vec3f relative = io->velocity - surface;
  if (respond(body.material(), contact, body.field()->grid().band * body.scale(), dt, &relative)) {
    io->velocity = relative + surface;
    io_touch->record(index, contact.distance);
  }
}

// Moves the particle by v dt, stopping it at the earliest swept body its segment reaches.
void integrate(const Body* bodies, std::size_t body_count, bool any_swept, float dt, ParticleState* io,
               Touch* io_touch) {
  const Vec3f step = io->velocity * dt;
  if (any_swept) {
    float earliest = 2.0f;
    std::size_t hit_body = 0;
    Contact hit_contact;
    for (std::size_t b = 0; b < body_count; ++b) {
      if (!bodies[b].material().swept) continue;
      const Vec3f relative_step = step - bodies[b].surfaceVelocity(io->position) * dt;
      float t = 0.0f;
      Contact contact;
      if (sweepSegment(bodies[b], io->position, relative_step, &t, &contact) && t < earliest) {
        earliest = t;
        hit_body = b;
        hit_contact = contact;
      }
    }
    if (earliest <= 1.0f) {
      // Stop at the hit point for the rest of the step and bounce off the body's surface there.
      io->position = io->position + step * earliest;
      const Body& body = bodies[hit_body];
      const Vec3f surface = body.surfaceVelocity(io->position);
      Vec3f relative = io->velocity - surface;
      const float vn = dot(relative, hit_contact.normal);
      if (vn < 0.0f) relative = relative - hit_contact.normal * ((1.0f + body.material().restitution) * vn);
      io->velocity = relative + surface;
      io_touch->record(hit_body, hit_contact.distance);
      return;
    }
  }
  io->position = io->position + step;
}

// Contact guard. Near sharp edges a voxel can carry the other face's normal, so a bounce may miss
// (the DN field cannot resolve which side of an edge a point is on within one voxel). For convex
// regions the plane-refined distance never overestimates, so "the field says outside" means outside:
// a step that takes a particle from field distance >= 0 to < 0, both within the band, crossed the
// surface. Refuse it: the particle stays where it was and its velocity relative to the surface
// reverses with the body's restitution. Deep jumps (far inside) are tunnelling: swept mode's job.
void guardContact(const Body* bodies, const Guard& guard, Vec3f start, ParticleState* io, Touch* io_touch) {
  if (guard.body < 0 || guard.distance < 0.0f) return;
  const Body& body = bodies[guard.body];
  if (body.material().response != Response::kImpact) return; // springs may dive (§3.3); kNone passes through
  // No shortcut by "moved less than its distance": the true distance is 1-Lipschitz, but the
  // sampled one is not across an edge voxel (seen: +1.06 to -0.66 over a 1.05 move), and it is the
  // sampled distance that the next step's bounce will trust.
  Contact after;
  if (!contactAt(body, io->position, &after) || after.distance >= 0.0f) return;
  const Vec3f surface = body.surfaceVelocity(start);
  io->position = start;
  io->velocity = surface - (io->velocity - surface) * body.material().restitution;
  io_touch->record(std::size_t(guard.body), guard.distance);
}

Status checkStep(const ParticleSpan& s, float dt, const Body* bodies, std::size_t body_count, Diagnostic* diag) {
  if (!(dt > 0.0f) || !std::isfinite(dt))
    return writeDiagnostic(diag, Status::kInvalidArgument, "dt must be finite and > 0, got %g", double(dt));
  if (body_count > 0 && bodies == nullptr)
    return writeDiagnostic(diag, Status::kInvalidArgument, "bodies is null but body_count is %zu", body_count);
  for (std::size_t b = 0; b < body_count; ++b) {
    if (!bodies[b].valid()) return writeDiagnostic(diag, Status::kInvalidArgument, "body %zu is not valid", b);
  }
  if (s.count == 0) return Status::kOk;
  if (!s.position_x || !s.position_y || !s.position_z || !s.velocity_x || !s.velocity_y || !s.velocity_z)
    return writeDiagnostic(diag, Status::kInvalidArgument, "particle position and velocity pointers must be set");
  if (s.position_stride < sizeof(float) || s.velocity_stride < sizeof(float))
    return writeDiagnostic(diag, Status::kInvalidArgument, "particle strides must be at least 4 bytes");
  return Status::kOk;
}

} // namespace

Status stepParticles(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
                     Diagnostic* out_diag) {
  const Status status = checkStep(particles, dt, bodies, body_count, out_diag);
  if (status != Status::kOk) return status;
  bool any_swept = false;
  for (std::size_t b = 0; b < body_count; ++b)
    any_swept = any_swept || bodies[b].material().swept;

  for (std::size_t n = 0; n < particles.count; ++n) {
    ParticleState state = load(particles, n);
    const Vec3f start = state.position;
    Touch touch;
    Guard guard;
    for (std::size_t b = 0; b < body_count; ++b)
      respondToBody(bodies[b], b, dt, &state, &touch, &guard);
    integrate(bodies, body_count, any_swept, dt, &state, &touch);
    guardContact(bodies, guard, start, &state, &touch);
    store(particles, n, state);
    if (particles.out_contact != nullptr) particles.out_contact[n] = touch.body >= 0 ? 1 : 0;
    if (particles.out_body != nullptr) particles.out_body[n] = touch.body;
  }
  return Status::kOk;
}

} // namespace dng
