// Small helpers for the forces a particle system applies besides collisions: gravity, wind, air drag,
// explosions (paper §3.7, Fig. 8). Each updates velocities in place by one explicit step of dt.
//
// They follow stepParticles' contract: they take the same ParticleSpan, never allocate, and return
// kInvalidArgument (filling `out_diag` when given) without touching any particle when dt is not finite
// and > 0, a parameter is not finite or out of range, an array they need is null, or its stride is not
// a whole number of floats (at least one). They read only
// what they need: gravity and air drag read and write velocities only, so a span without positions
// works for them; explosions also read positions.
#pragma once

#include "dng/particles.h"

namespace dng {

/// v += g * dt.
Status applyGravity(const ParticleSpan& particles, Vec3f gravity, float dt, Diagnostic* out_diag = nullptr);

/// Air drag towards the wind velocity: v += (wind - v) * (1 - exp(-rate * dt)). rate in 1/s, >= 0;
/// with wind = 0 this is plain air resistance. Stable for any dt.
Status applyAirDrag(const ParticleSpan& particles, Vec3f wind, float rate, float dt, Diagnostic* out_diag = nullptr);

/// Radial push from `centre`: acceleration strength / (1 + (r / radius)^2) away from the centre
/// (world units/s^2; radius > 0). Particles exactly at the centre are left alone.
Status applyExplosion(const ParticleSpan& particles, Vec3f centre, float strength, float radius, float dt,
                      Diagnostic* out_diag = nullptr);

} // namespace dng
