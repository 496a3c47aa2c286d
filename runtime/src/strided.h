// Internal: element n of a caller's strided float array (dng::ParticleSpan counts strides in bytes, so
// the same code reads packed structure-of-arrays and array-of-structures particles), and a particle's
// optional outputs.
#pragma once

#include "dng/particles.h"

#include <cstddef>
#include <cstdint>

namespace dng {

/// A stride the spans accept: whole floats (a float read at any other offset is misaligned), at least one.
inline bool validStride(std::size_t stride_bytes) {
  return stride_bytes >= sizeof(float) && stride_bytes % sizeof(float) == 0;
}

/// Whether `count` elements `stride_bytes` apart fit in the address space (a larger count cannot describe
/// a caller's array, and its last offset would wrap around).
inline bool spanFits(std::size_t count, std::size_t stride_bytes) {
  return stride_bytes == 0 || count <= SIZE_MAX / stride_bytes;
}

inline float& strided(float* base, std::size_t stride_bytes, std::size_t n) {
  return *reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(base) + n * stride_bytes);
}

/// ParticleSpan::out_contact's byte for a touched body (-1: none).
inline std::uint8_t contactFlag(std::int32_t body) { return body >= 0 ? 1 : 0; }

/// Particle n's optional outputs: the body that acted on or blocked it (-1: none), and whether one did.
inline void writeTouch(const ParticleSpan& s, std::size_t n, std::int32_t body) {
  if (s.out_contact != nullptr) s.out_contact[n] = contactFlag(body);
  if (s.out_body != nullptr) s.out_body[n] = body;
}

} // namespace dng
