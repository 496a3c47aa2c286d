// What the stepping samples share about their particles: the store, structure-of-arrays, the layout
// stepParticles reads fastest (docs/RUNTIME.md, "Stepping"), in std::vectors (an engine keeps its own
// arrays and hands the runtime a span over them the same way span() does), and the tally of a run's
// steps that every sample prints. Header-only.
#pragma once

#include "sample_io.h"

#include "dng/particles.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace dng {
namespace samples {

/// Positions, velocities and each particle's contact flag, one array per component.
struct Particles {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::uint8_t> contact; ///< 1 when a body acted on the particle in the last step

  void add(Vec3f p, Vec3f v) {
    px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
    vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
    contact.push_back(0);
  }
  std::size_t size() const { return px.size(); }
  Vec3f position(std::size_t n) const { return {px[n], py[n], pz[n]}; }
  Vec3f velocity(std::size_t n) const { return {vx[n], vy[n], vz[n]}; }

  /// The span stepParticles reads and writes; valid until the next add().
  ParticleSpan span() {
    ParticleSpan s;
    s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
    s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
    s.count = px.size();
    s.out_contact = contact.data();
    return s;
  }
};

/// A run's steps, counted as each sample's JSON line reports them.
struct StepTally {
  double seconds = 0.0;             ///< wall time inside stepParticles
  std::uint64_t particle_steps = 0; ///< the live particles, summed over the steps (emitters add as they go)
  std::uint64_t contacts = 0;       ///< particle-steps where a body acted

  /// stepParticles on `span`, timed and counted; a failed call stops the sample (exit 2, its message).
  void step(const ParticleSpan& span, float dt, const Body* bodies, std::size_t body_count) {
    Diagnostic diag;
    const auto start = std::chrono::steady_clock::now();
    const Status status = stepParticles(span, dt, bodies, body_count, &diag);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    require(status, diag);
    particle_steps += span.count;
    for (std::size_t n = 0; span.out_contact != nullptr && n < span.count; ++n)
      contacts += span.out_contact[n];
  }
  double particleStepsPerSecond() const { return seconds > 0.0 ? double(particle_steps) / seconds : 0.0; }
};

/// A float drawn uniformly from [lo, hi).
inline float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

} // namespace samples
} // namespace dng
