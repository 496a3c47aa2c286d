// Internal: swept steps (beyond the paper; DESIGN.md §5).
#pragma once

#include "dng/body.h"
#include "dng/responses.h"

namespace dng {

/// Traces the world segment p -> p + delta through the body's field by sphere tracing: advance by the
/// sampled distance to the collision distance L, which no surface can be closer than. Returns true
/// with the segment fraction *out_t in [0, 1] and the contact there when the particle, moving towards
/// the surface, comes within L (plus a twentieth of a voxel) of it. Bounded: at most 256 samples.
bool sweepSegment(const Body& body, Vec3f p, Vec3f delta, float* out_t, Contact* out_contact);

} // namespace dng
