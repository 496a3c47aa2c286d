// The one small vector type shared by the format, the runtime and the tools.
#pragma once

#include <cmath>

/// Forces inlining on the query paths, where a call costs as much as the work (measured: dense
/// nearest went from 27 to 10 ns per query, bench/field_query_bench.cpp).
#if defined(__GNUC__) || defined(__clang__)
#define DNG_FORCE_INLINE inline __attribute__((always_inline))
#else
#define DNG_FORCE_INLINE inline
#endif

namespace dng {

/// Three floats, no invariants. Plain aggregate so arrays of it can be memcpy'd and mapped.
struct Vec3f {
  float x = 0.0f;
  float y = 0.0f;
  float z = 0.0f;
};

inline Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3f operator*(float s, Vec3f a) { return a * s; }
inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
/// Whether every component is finite (no NaN, no infinity).
inline bool isFinite(Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Component `axis` (0 x, 1 y, 2 z; anything else z) of a vector, for code that loops over axes.
inline float component(const Vec3f& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
inline float& component(Vec3f& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }

/// The angle between `a` and `b` as its sine and cosine times |a| |b|: |a x b| and a . b, in double
/// precision (angleDegrees takes their atan2).
struct AngleParts {
  double sine, cosine;
};
inline AngleParts angleParts(Vec3f a, Vec3f b) {
  const double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  return {std::sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz};
}

/// The angle of `p` in degrees, as angleDegrees answers it.
inline double degreesOf(AngleParts p) {
  if (p.sine == 0.0 && p.cosine == 0.0) return 0.0;
  return std::atan2(p.sine, p.cosine) * 57.29577951308232;
}

/// Angle between `a` and `b` in degrees, 0 when either is zero. Uses atan2 of |a x b| and a . b in
/// double precision, which stays accurate for tiny angles where acos of a float cosine cannot.
inline double angleDegrees(Vec3f a, Vec3f b) { return degreesOf(angleParts(a, b)); }

/// degreesOf(x) < degreesOf(y), mostly without the atan2s: for angles in [0, 180] degrees, x is the
/// smaller when sin(y - x) > 0, which the parts give by two products. Only where those are too close
/// to call in doubles (far below any difference that matters) are the atan2s taken, so the answer is
/// always the atan2s'.
inline bool smallerAngle(AngleParts x, AngleParts y) {
  if (x.sine == y.sine && x.cosine == y.cosine) return false; // a tie, as between mirrored candidates
  const double ys_xc = y.sine * x.cosine, yc_xs = y.cosine * x.sine;
  const double difference = ys_xc - yc_xs;
  if (std::fabs(difference) > 1e-12 * (std::fabs(ys_xc) + std::fabs(yc_xs))) return difference > 0.0;
  return degreesOf(x) < degreesOf(y);
}

/// Unit vector along `a`, or the zero vector when `a` is zero or not finite-length.
inline Vec3f normalizeOrZero(Vec3f a) {
  const float len = length(a);
  return len > 0.0f && std::isfinite(len) ? a * (1.0f / len) : Vec3f{};
}

} // namespace dng
