// A tiny particle-system loop for the samples: emit, apply forces, step against bodies, record.
// Everything a sample needs besides its own scene description; nothing here is hidden runtime API.
#pragma once

#include "dng/body.h"
#include "dng/particles.h"

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace dng {
namespace samples {

/// Particles as structure-of-arrays, the layout stepParticles likes best.
struct Swarm {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::uint8_t> contact;
  std::vector<std::int32_t> body;

  std::size_t size() const { return px.size(); }
  void add(Vec3f p, Vec3f v);
  Vec3f position(std::size_t n) const { return {px[n], py[n], pz[n]}; }
  Vec3f velocity(std::size_t n) const { return {vx[n], vy[n], vz[n]}; }
  ParticleSpan span();
};

/// Forces besides collisions, applied every step before stepParticles (paper §3.7, Fig. 8).
struct Forces {
  Vec3f gravity{0.0f, 0.0f, -9.81f};
  float air_drag = 0.0f; ///< 1/s, towards `wind`
  Vec3f wind;
  float explosion_strength = 0.0f; ///< world units/s^2 at the centre; 0 = none
  Vec3f explosion_centre;
  float explosion_radius = 1.0f;
  float explosion_seconds = 0.0f; ///< how long the push lasts
};

/// Makes one particle: position and velocity.
using Spawner = std::function<void(std::mt19937& rng, Vec3f* out_position, Vec3f* out_velocity)>;

struct SceneSetup {
  std::vector<Body> bodies;
  Forces forces;
  float dt = 1.0f / 60.0f;
  int steps = 240;
  Spawner spawn;
  int spawn_per_step = 100;
  int spawn_steps = 1; ///< spawn during the first steps only
  std::uint32_t seed = 1;
  /// The true shape, when the sample knows it (world frame): whether a point is inside any body. Then
  /// SceneStats::inside counts with it; otherwise with the bodies' fields.
  std::function<bool(Vec3f)> inside;
};

struct SceneStats {
  std::size_t particles = 0;
  int steps = 0;
  double step_seconds = 0.0;  ///< time inside stepParticles only
  std::uint64_t contacts = 0; ///< particle-steps in which a body acted
  std::size_t inside = 0;     ///< particles that end inside any body (SceneSetup::inside, else the fields)
  double particleStepsPerSecond() const;
  /// One line of JSON, e.g. for the samples' output.
  std::string json(const std::string& name) const;
};

/// Runs the scene. `on_step` (may be empty) sees the swarm after every step, e.g. to record trails.
SceneStats runScene(const SceneSetup& setup, Swarm* out_swarm,
                    const std::function<void(const Swarm&, int step)>& on_step = {});

/// Particles whose position lies inside any body: the body's field says distance < 0 there.
std::size_t countInside(const std::vector<Body>& bodies, const Swarm& swarm);

} // namespace samples
} // namespace dng
