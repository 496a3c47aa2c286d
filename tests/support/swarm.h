// Particles for the tests: structure-of-arrays storage with the contact and body outputs, and the
// ParticleSpan that hands it to stepParticles and the force helpers.
#pragma once

#include "dng/particles.h"

#include <cstdint>
#include <vector>

namespace dng {
namespace testing {

/// Particles as structure-of-arrays, the layout stepParticles reads fastest. Copy it to run the same
/// particles twice. span() points into the vectors: call it again after add().
struct Swarm {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::uint8_t> contact; ///< stepParticles' out_contact
  std::vector<std::int32_t> body;    ///< stepParticles' out_body

  std::size_t size() const { return px.size(); }
  void add(Vec3f p, Vec3f v);
  Vec3f position(std::size_t n) const { return {px[n], py[n], pz[n]}; }
  Vec3f velocity(std::size_t n) const { return {vx[n], vy[n], vz[n]}; }
  ParticleSpan span();
};

/// A span over an array of particle structs (an engine's layout) with `position[3]` and `velocity[3]`
/// members: strided, whatever else the struct holds between them. `particles` must not be empty.
template <class Particle> ParticleSpan structSpan(std::vector<Particle>* particles) {
  Particle& first = particles->front();
  ParticleSpan s;
  s.position_x = &first.position[0], s.position_y = &first.position[1], s.position_z = &first.position[2];
  s.velocity_x = &first.velocity[0], s.velocity_y = &first.velocity[1], s.velocity_z = &first.velocity[2];
  s.position_stride = s.velocity_stride = sizeof(Particle);
  s.count = particles->size();
  return s;
}

} // namespace testing

} // namespace dng
