// Internal: element n of a caller's strided float array (dng::ParticleSpan counts strides in bytes, so
// the same code reads packed structure-of-arrays and array-of-structures particles).
#pragma once

#include <cstddef>

namespace dng {

inline float& strided(float* base, std::size_t stride_bytes, std::size_t n) {
  return *reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(base) + n * stride_bytes);
}

} // namespace dng
