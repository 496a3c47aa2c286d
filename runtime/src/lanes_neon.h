// Internal: the aarch64 Advanced SIMD (NEON) lanes of lanes.h, 4 per register. Include lanes.h, not
// this file. Where NEON's own instruction rounds or treats NaN differently from the scalar code (its
// min and max return NaN when either side is NaN), the operation is built from a comparison and a
// select instead, so lanes stay bit for bit the scalar results.
#pragma once

#include <arm_neon.h>
#include <cstdint>

#define DNG_LANES_NS neon

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

constexpr int kWidth = 4;
/// One bit per lane (bits(), laneMask()).
using LaneBits = std::uint32_t;

struct F {
  float32x4_t v;
};
struct I {
  int32x4_t v;
};
struct M {
  uint32x4_t v;
};

// ---- floats ----
DNG_LANE_INLINE F splat(float x) { return {vdupq_n_f32(x)}; }
DNG_LANE_INLINE F load(const float* p) { return {vld1q_f32(p)}; }
DNG_LANE_INLINE void store(float* p, F a) { vst1q_f32(p, a.v); }
DNG_LANE_INLINE F operator+(F a, F b) { return {vaddq_f32(a.v, b.v)}; }
DNG_LANE_INLINE F operator-(F a, F b) { return {vsubq_f32(a.v, b.v)}; }
DNG_LANE_INLINE F operator*(F a, F b) { return {vmulq_f32(a.v, b.v)}; }
DNG_LANE_INLINE F operator/(F a, F b) { return {vdivq_f32(a.v, b.v)}; }
DNG_LANE_INLINE F sqrt(F a) { return {vsqrtq_f32(a.v)}; }
DNG_LANE_INLINE F floor(F a) { return {vrndmq_f32(a.v)}; }
/// a < b ? a : b, exactly like dng::minOf, NaN included.
DNG_LANE_INLINE F minOf(F a, F b) { return {vbslq_f32(vcltq_f32(a.v, b.v), a.v, b.v)}; }
DNG_LANE_INLINE F maxOf(F a, F b) { return {vbslq_f32(vcgtq_f32(a.v, b.v), a.v, b.v)}; }
DNG_LANE_INLINE F abs(F a) { return {vabsq_f32(a.v)}; }
DNG_LANE_INLINE F copysign(F mag, F sign) { return {vbslq_f32(vdupq_n_u32(0x80000000u), sign.v, mag.v)}; }

// ---- comparisons (ordered: false when either side is NaN) and masks ----
DNG_LANE_INLINE M operator<(F a, F b) { return {vcltq_f32(a.v, b.v)}; }
DNG_LANE_INLINE M operator<=(F a, F b) { return {vcleq_f32(a.v, b.v)}; }
DNG_LANE_INLINE M operator>(F a, F b) { return {vcgtq_f32(a.v, b.v)}; }
DNG_LANE_INLINE M operator>=(F a, F b) { return {vcgeq_f32(a.v, b.v)}; }
DNG_LANE_INLINE M operator!=(F a, F b) { return {vmvnq_u32(vceqq_f32(a.v, b.v))}; } // true for NaN
DNG_LANE_INLINE M allTrue() { return {vdupq_n_u32(~0u)}; }
DNG_LANE_INLINE M operator&(M a, M b) { return {vandq_u32(a.v, b.v)}; }
DNG_LANE_INLINE M operator|(M a, M b) { return {vorrq_u32(a.v, b.v)}; }
DNG_LANE_INLINE M operator~(M a) { return {vmvnq_u32(a.v)}; }
/// a and not b.
DNG_LANE_INLINE M andNot(M a, M b) { return {vbicq_u32(a.v, b.v)}; }
/// Bit n set when lane n is true.
DNG_LANE_INLINE LaneBits bits(M a) {
  const int32_t shifts[4] = {0, 1, 2, 3};
  return unsigned(vaddvq_u32(vshlq_u32(vshrq_n_u32(a.v, 31), vld1q_s32(shifts))));
}
DNG_LANE_INLINE bool any(M a) { return vmaxvq_u32(a.v) != 0; }
DNG_LANE_INLINE bool all(M a) { return vminvq_u32(a.v) != 0; }
/// m ? a : b per lane.
DNG_LANE_INLINE F select(M m, F a, F b) { return {vbslq_f32(m.v, a.v, b.v)}; }
DNG_LANE_INLINE M laneMask(LaneBits lane_bits) {
  std::uint32_t b[4];
  for (int n = 0; n < 4; ++n)
    b[n] = (lane_bits >> n) & 1u ? ~0u : 0u;
  return {vld1q_u32(b)};
}

// ---- integers ----
DNG_LANE_INLINE I splatI(std::int32_t x) { return {vdupq_n_s32(x)}; }
DNG_LANE_INLINE I operator+(I a, I b) { return {vaddq_s32(a.v, b.v)}; }
DNG_LANE_INLINE I operator*(I a, I b) { return {vmulq_s32(a.v, b.v)}; }
DNG_LANE_INLINE I operator&(I a, I b) { return {vandq_s32(a.v, b.v)}; }
DNG_LANE_INLINE I operator|(I a, I b) { return {vorrq_s32(a.v, b.v)}; }
DNG_LANE_INLINE I shiftLeft(I a, int n) { return {vshlq_s32(a.v, vdupq_n_s32(n))}; }
/// Logical: zeros come in from the left.
DNG_LANE_INLINE I shiftRight(I a, int n) {
  return {vreinterpretq_s32_u32(vshlq_u32(vreinterpretq_u32_s32(a.v), vdupq_n_s32(-n)))};
}
DNG_LANE_INLINE M operator==(I a, I b) { return {vceqq_s32(a.v, b.v)}; }
/// float -> int32 by truncation, as a C++ cast of a value in [0, 2^31).
DNG_LANE_INLINE I truncate(F a) { return {vcvtq_s32_f32(a.v)}; }
DNG_LANE_INLINE F toFloat(I a) { return {vcvtq_f32_s32(a.v)}; }
DNG_LANE_INLINE I select(M m, I a, I b) { return {vbslq_s32(m.v, a.v, b.v)}; }
/// Reinterprets integer bits as floats (a float stored in a 32-bit word).
DNG_LANE_INLINE F asFloat(I a) { return {vreinterpretq_f32_s32(a.v)}; }

// ---- gathers: lanes where `m` is false read nothing and give 0. NEON has no gather instruction ----
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  std::int32_t idx[4];
  float out[4];
  vst1q_s32(idx, index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n)
    out[n] = (on >> n) & 1u ? base[idx[n]] : 0.0f;
  return {vld1q_f32(out)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  std::int32_t idx[4], out[4];
  vst1q_s32(idx, index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n)
    out[n] = (on >> n) & 1u ? std::int32_t(base[idx[n]]) : 0;
  return {vld1q_s32(out)};
}
/// 64-bit words, returned as their low and high halves.
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  std::int32_t idx[4], lo[4], hi[4];
  vst1q_s32(idx, index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n) {
    const std::uint64_t word = (on >> n) & 1u ? base[idx[n]] : 0u;
    lo[n] = std::int32_t(std::uint32_t(word));
    hi[n] = std::int32_t(std::uint32_t(word >> 32));
  }
  out_lo->v = vld1q_s32(lo);
  out_hi->v = vld1q_s32(hi);
}

// ---- packed records: a few floats per lane, one lane after the other in memory ----
// A de-interleaving load and a transpose in registers in place of a transpose through an array, which
// moved every word with a scalar load and store: under qemu-user the bricked nearest sampleBatch runs
// about 6% fewer instructions (docs/RUNTIME.md, "SIMD"); not timed on an ARM CPU.

/// The lanes of packed xyz triples: lane n is (p[3n], p[3n + 1], p[3n + 2]). One de-interleaving load.
DNG_LANE_INLINE void loadTriples(const float* p, F* x, F* y, F* z) {
  const float32x4x3_t xyz = vld3q_f32(p);
  x->v = xyz.val[0], y->v = xyz.val[1], z->v = xyz.val[2];
}

/// Packed five-word records: word 5n + f of `out` is lane n of field[f] (copied as bytes, so the
/// records may be structs of floats and 32-bit integers). Each record is a 16-byte store of its
/// first four words, from a 4x4 transpose, and a one-lane store of its fifth.
DNG_LANE_INLINE void storeQuintuples(void* out, const F field[5]) {
  const float32x4x2_t ab = vtrnq_f32(field[0].v, field[1].v); // a0 b0 a2 b2, a1 b1 a3 b3
  const float32x4x2_t cd = vtrnq_f32(field[2].v, field[3].v); // c0 d0 c2 d2, c1 d1 c3 d3
  auto* words = static_cast<float*>(out);
  vst1q_f32(words, vcombine_f32(vget_low_f32(ab.val[0]), vget_low_f32(cd.val[0])));
  vst1q_f32(words + 5, vcombine_f32(vget_low_f32(ab.val[1]), vget_low_f32(cd.val[1])));
  vst1q_f32(words + 10, vcombine_f32(vget_high_f32(ab.val[0]), vget_high_f32(cd.val[0])));
  vst1q_f32(words + 15, vcombine_f32(vget_high_f32(ab.val[1]), vget_high_f32(cd.val[1])));
  vst1q_lane_f32(words + 4, field[4].v, 0);
  vst1q_lane_f32(words + 9, field[4].v, 1);
  vst1q_lane_f32(words + 14, field[4].v, 2);
  vst1q_lane_f32(words + 19, field[4].v, 3);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
