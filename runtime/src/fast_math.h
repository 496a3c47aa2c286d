// Internal: min and max that compile to single instructions (std::fmin/fmax are libm calls without
// -ffast-math, and the query and step paths call these per particle).
#pragma once

namespace dng {

inline float minOf(float a, float b) { return a < b ? a : b; }
inline float maxOf(float a, float b) { return a > b ? a : b; }

} // namespace dng
