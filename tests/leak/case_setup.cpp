#include "case_setup.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace dng {
namespace leak {

namespace {

constexpr float kScaledBody = 2.5f;
// Gravity adds at most this many design speeds over a 120-step run; spawn speeds leave room for it,
// so relative speeds stay within the case's limit.
constexpr float kGravityGain = 0.1f;
constexpr float kRestingGravityGain = 0.5f;
constexpr int kDesignSteps = 120;
constexpr float kRestingHeightVoxels = 0.15f;

Vec3f randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  for (;;) {
    const Vec3f v{gauss(rng), gauss(rng), gauss(rng)};
    if (length(v) > 1e-3f) return normalizeOrZero(v);
  }
}

float farthestVertex(const LeakMesh& mesh) {
  float r = 0.0f;
  for (const Vec3f& v : mesh.mesh.vertices)
    r = std::max(r, length(v));
  return r;
}

Material material(const Subject& subject, const CaseSpec& spec, const CaseSetup& setup) {
  const float voxel = subject.voxel * setup.scale; // world units
  Material m;
  m.restitution = 0.5f;
  m.collision_distance = 0.1f * voxel;
  m.swept = spec.swept;
  if (spec.responses == Responses::kImpactDragFlow) {
    m.drag = 2.0f;
    m.contact_distance = voxel;
    m.flow_in = m.flow_out = 3.0f * setup.design_speed;
    m.flow_distance = 2.0f * voxel;
  } else if (spec.responses == Responses::kSpring) {
    // k * band^2 >= V^2: the spring can stop a design-speed particle within the band.
    const float band = subject.file.view().grid().band * setup.scale;
    m.response = Response::kSpring;
    m.spring_stiffness = 2.0f * (setup.design_speed / band) * (setup.design_speed / band);
  } else if (spec.responses == Responses::kNone) {
    m.response = Response::kNone;
  }
  return m;
}

// Outside (any side of a sheet) and between 0.1 voxel and the guaranteed reach from the surface.
Vec3f spawnPoint(const Subject& s, std::mt19937& rng, Vec3f lo, Vec3f hi) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (;;) {
    const Vec3f p{lo.x + (hi.x - lo.x) * unit(rng), lo.y + (hi.y - lo.y) * unit(rng), lo.z + (hi.z - lo.z) * unit(rng)};
    const reference::Closest c = s.reference.closest(p, s.reach);
    if (!c.found || c.distance < 0.1f * s.voxel || c.distance >= s.reach) continue;
    if (s.mesh.closed && s.reference.inside(p)) continue;
    return p;
  }
}

// Just above an upward-facing part of the surface (the body is static in resting cases).
Vec3f restingPoint(const Subject& s, std::mt19937& rng, Vec3f lo, Vec3f hi) {
  for (;;) {
    const reference::Closest c = s.reference.closest(spawnPoint(s, rng, lo, hi));
    Vec3f n = s.reference.faceNormal(c.triangle);
    if (!s.mesh.closed && n.z < 0.0f) n = n * -1.0f; // a sheet: rest on whichever side is up
    if (n.z < 0.7f) continue;
    const Vec3f p = c.point + Vec3f{0, 0, kRestingHeightVoxels * s.voxel};
    if (s.reference.closest(p).distance < 0.1f * s.voxel) continue;
    if (s.mesh.closed && s.reference.inside(p)) continue;
    return p;
  }
}

} // namespace

CaseSetup makeSetup(const Subject& subject, const CaseSpec& spec) {
  CaseSetup s;
  s.scale = spec.motion == Motion::kScaled ? kScaledBody : 1.0f;
  s.design_speed = subject.reach * s.scale / kDt;
  const float v = s.design_speed;
  float surface_speed = 0.0f;
  if (spec.motion == Motion::kTranslating) {
    s.linear = normalizeOrZero({0.6f, -0.48f, 0.64f}) * (0.5f * v);
    surface_speed = 0.5f * v;
  } else if (spec.motion == Motion::kSpinning) {
    s.angular = normalizeOrZero({0.3f, 0.4f, 0.866f}) * (0.5f * v / (s.scale * farthestVertex(subject.mesh)));
    surface_speed = 0.5f * v;
  }
  const float gain = spec.start == Start::kResting ? kRestingGravityGain : kGravityGain;
  s.gravity = {0.0f, 0.0f, -gain * v / (float(kDesignSteps) * kDt)};
  s.speed_limit = spec.speed_factor * v;
  // A moving surface meets a particle at up to its own speed from any direction: leave room for it
  // (world speeds start below limit - surface speed - gravity's gain, so relative ones stay below the limit).
  s.spawn_speed = spec.start == Start::kResting ? 0.0f : s.speed_limit - surface_speed - kGravityGain * v;
  s.material = material(subject, spec, s);
  return s;
}

void placeBody(const CaseSetup& setup, float t, Body* body) {
  const float omega = length(setup.angular);
  const Vec3f axis = omega > 0.0f ? setup.angular * (1.0f / omega) : Vec3f{0, 0, 1};
  const float half = 0.5f * omega * t;
  const float q[4] = {std::cos(half), axis.x * std::sin(half), axis.y * std::sin(half), axis.z * std::sin(half)};
  (void)body->setTransform(setup.position + setup.linear * t, q, setup.scale);
  body->setVelocity(setup.linear, setup.angular);
}

testing::Swarm spawnParticles(const Subject& subject, const CaseSpec& spec, const CaseSetup& setup, const Body& body) {
  std::mt19937 rng(spec.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Vec3f lo, hi;
  meshBounds(subject.mesh, &lo, &hi);
  const Vec3f pad{subject.reach, subject.reach, subject.reach};
  lo = lo - pad, hi = hi + pad;
  testing::Swarm swarm;
  while (swarm.size() < spec.particles) {
    if (spec.start == Start::kResting) {
      swarm.add(body.toWorld(restingPoint(subject, rng, lo, hi)), {});
      continue;
    }
    const Vec3f local = spawnPoint(subject, rng, lo, hi);
    // Half aim at the surface (more impacts, the interesting part), half go anywhere.
    Vec3f direction = randomUnit(rng);
    if (unit(rng) < 0.5f) {
      const Vec3f towards = subject.reference.closest(local).point - local;
      direction = normalizeOrZero(normalizeOrZero(towards) + randomUnit(rng) * 0.5f);
    }
    const Vec3f world = body.toWorld(local);
    const float speed = setup.spawn_speed * (0.2f + 0.8f * unit(rng));
    swarm.add(world, body.rotateToWorld(direction) * speed);
  }
  return swarm;
}

} // namespace leak
} // namespace dng
