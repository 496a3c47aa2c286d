// Stepping particles against bodies: the paper's responses (§3.3-3.6) and integration, one batch call
// per time step.
#pragma once

#include "dng/body.h"
#include "dng/status.h"

#include <cstddef>
#include <cstdint>

namespace dng {

/// Caller-owned particle data, structure-of-arrays or array-of-structures alike: particle n's x
/// position is at byte offset n * position_stride from position_x, and so on. Strides are in bytes,
/// multiples of 4 (4 for packed SoA arrays, sizeof(YourParticle) for AoS). Positions and velocities are world-frame.
/// No two particles' numbers may share a float (e.g. x of one particle is never y of another): the
/// SIMD step writes whole registers of one coordinate at a time, so overlapping arrays give results
/// that differ from the scalar path's (only the span's own floats are ever written).
struct ParticleSpan {
  float* position_x = nullptr;
  float* position_y = nullptr;
  float* position_z = nullptr;
  std::size_t position_stride = sizeof(float);
  float* velocity_x = nullptr;
  float* velocity_y = nullptr;
  float* velocity_z = nullptr;
  std::size_t velocity_stride = sizeof(float);
  std::size_t count = 0;
  /// Optional outputs (may be null): per particle, 1 when a body affected it this step, else 0; and
  /// the index (into the bodies array) of the nearest body that did, else -1.
  std::uint8_t* out_contact = nullptr;
  std::int32_t* out_body = nullptr;
};

/// One time step for every particle: for each body whose bounds contain the particle, sample its
/// field and apply the body's material (bounce, drag, surface flow) to the velocity relative to the
/// body's surface; then move the particle by velocity * dt, walked through every colliding body near
/// the move in the body's frame from its pose now to its pose after dt at its velocities, stopping
/// where the field no longer proves the way clear (docs/RUNTIME.md, "The walk"): a blocked particle
/// bounces off the blocking plane and slides along it. Bodies' transforms are their poses at the start
/// of the step. Gravity and other forces are the caller's: add them to the velocities first (see
/// dng/forces.h).
///
/// No allocation, no exceptions, no virtual calls. Particles are independent, so callers may split a
/// span across threads. Fails without touching any particle when dt is not finite and > 0, a body is
/// invalid or its velocities give no finite motion over dt, a required pointer is null, or a stride is
/// not a whole number of floats (at least one).
Status stepParticles(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
                     Diagnostic* out_diag = nullptr);

} // namespace dng
