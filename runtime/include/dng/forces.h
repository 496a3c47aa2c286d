// Small helpers for the forces a particle system applies besides collisions: gravity, wind, air drag,
// explosions (paper §3.7, Fig. 8). Each updates velocities in place by one explicit step of dt.
// They take the same ParticleSpan as stepParticles and never allocate.
#pragma once

#include "dng/particles.h"

namespace dng {

/// v += g * dt.
void applyGravity(const ParticleSpan& particles, Vec3f gravity, float dt);

/// Air drag towards the wind velocity: v += (wind - v) * (1 - exp(-rate * dt)). rate in 1/s; with
/// wind = 0 this is plain air resistance. Stable for any dt.
void applyAirDrag(const ParticleSpan& particles, Vec3f wind, float rate, float dt);

/// Radial push from `centre`: acceleration strength / (1 + (r / radius)^2) away from the centre
/// (world units/s^2). Particles exactly at the centre are left alone.
void applyExplosion(const ParticleSpan& particles, Vec3f centre, float strength, float radius, float dt);

} // namespace dng
