#include "scene.h"

#include "dng/forces.h"

#include <chrono>
#include <cstdio>

namespace dng {
namespace samples {

void Swarm::add(Vec3f p, Vec3f v) {
  px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
  vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
  contact.push_back(0), body.push_back(-1);
}

ParticleSpan Swarm::span() {
  ParticleSpan s;
  s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
  s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
  s.count = size();
  s.out_contact = contact.data();
  s.out_body = body.data();
  return s;
}

double SceneStats::particleStepsPerSecond() const {
  return step_seconds > 0.0 ? double(particles) * steps / step_seconds : 0.0;
}

std::string SceneStats::json(const std::string& name) const {
  char line[512];
  std::snprintf(line, sizeof line,
                "{\"sample\":\"%s\",\"particles\":%zu,\"steps\":%d,\"step_seconds\":%.4f,"
                "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}",
                name.c_str(), particles, steps, step_seconds, particleStepsPerSecond(), (unsigned long long)contacts,
                inside);
  return line;
}

std::size_t countInside(const std::vector<Body>& bodies, const Swarm& swarm) {
  std::size_t inside = 0;
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    for (const Body& b : bodies) {
      const Sample s = b.field()->sample(b.toLocal(swarm.position(n)));
      if (s.status != SampleStatus::kNoField && s.distance < 0.0f) {
        ++inside;
        break;
      }
    }
  }
  return inside;
}

SceneStats runScene(const SceneSetup& setup, Swarm* swarm, const std::function<void(const Swarm&, int)>& on_step) {
  std::mt19937 rng(setup.seed);
  SceneStats stats;
  stats.steps = setup.steps;
  const Forces& f = setup.forces;
  for (int step = 0; step < setup.steps; ++step) {
    if (step < setup.spawn_steps && setup.spawn) {
      for (int i = 0; i < setup.spawn_per_step; ++i) {
        Vec3f p, v;
        setup.spawn(rng, &p, &v);
        swarm->add(p, v);
      }
    }
    const ParticleSpan span = swarm->span();
    applyGravity(span, f.gravity, setup.dt);
    if (f.air_drag > 0.0f) applyAirDrag(span, f.wind, f.air_drag, setup.dt);
    if (f.explosion_strength > 0.0f && float(step) * setup.dt < f.explosion_seconds)
      applyExplosion(span, f.explosion_centre, f.explosion_strength, f.explosion_radius, setup.dt);
    const auto start = std::chrono::steady_clock::now();
    stepParticles(span, setup.dt, setup.bodies.data(), setup.bodies.size());
    stats.step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (std::uint8_t c : swarm->contact)
      stats.contacts += c;
    if (on_step) on_step(*swarm, step);
  }
  stats.particles = swarm->size();
  if (setup.inside) {
    for (std::size_t n = 0; n < swarm->size(); ++n)
      stats.inside += setup.inside(swarm->position(n)) ? 1 : 0;
  } else {
    stats.inside = countInside(setup.bodies, *swarm);
  }
  return stats;
}

} // namespace samples
} // namespace dng
