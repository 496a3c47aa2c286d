// Internal: the AVX-512 lanes of lanes.h, 16 per register, with the booleans in mask registers
// (AVX-512F, DQ for the float logic). Include lanes.h, not this file.
//
// Sixteen lanes halve the instructions per particle of the 8-lane AVX2 kernels wherever the lanes do
// the same work, and mask registers make the step's many selects and mask operations single
// instructions. Every operation is still the IEEE operation the scalar code uses (floor by rounding
// towards minus infinity, no fused multiply-adds), so the lanes stay bit for bit the scalar results.
#pragma once

#include <cstdint>
#include <immintrin.h>

#define DNG_LANES_NS avx512

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

constexpr int kWidth = 16;

/// Lanes of float.
struct F {
  __m512 v;
};
/// Lanes of 32-bit integers (signed or unsigned by use).
struct I {
  __m512i v;
};
/// Lanes of booleans: one bit per lane in a mask register.
struct M {
  __mmask16 v;
};

// ---- floats ----
DNG_LANE_INLINE F splat(float x) { return {_mm512_set1_ps(x)}; }
DNG_LANE_INLINE F load(const float* p) { return {_mm512_loadu_ps(p)}; }
DNG_LANE_INLINE void store(float* p, F a) { _mm512_storeu_ps(p, a.v); }
DNG_LANE_INLINE F operator+(F a, F b) { return {_mm512_add_ps(a.v, b.v)}; }
DNG_LANE_INLINE F operator-(F a, F b) { return {_mm512_sub_ps(a.v, b.v)}; }
DNG_LANE_INLINE F operator*(F a, F b) { return {_mm512_mul_ps(a.v, b.v)}; }
DNG_LANE_INLINE F operator/(F a, F b) { return {_mm512_div_ps(a.v, b.v)}; }
DNG_LANE_INLINE F sqrt(F a) { return {_mm512_sqrt_ps(a.v)}; }
/// a < b ? a : b, exactly like dng::minOf (and std::min(b, a)), NaN included: vminps returns its
/// second operand when either is NaN, as the x86 sets below do.
DNG_LANE_INLINE F minOf(F a, F b) { return {_mm512_min_ps(a.v, b.v)}; }
DNG_LANE_INLINE F maxOf(F a, F b) { return {_mm512_max_ps(a.v, b.v)}; }
DNG_LANE_INLINE F floor(F a) { return {_mm512_roundscale_ps(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)}; }
DNG_LANE_INLINE F abs(F a) { return {_mm512_andnot_ps(_mm512_set1_ps(-0.0f), a.v)}; }
/// The magnitude of `mag` with the sign of `sign` (std::copysign).
DNG_LANE_INLINE F copysign(F mag, F sign) {
  const __m512 bit = _mm512_set1_ps(-0.0f);
  return {_mm512_or_ps(_mm512_andnot_ps(bit, mag.v), _mm512_and_ps(bit, sign.v))};
}

// ---- comparisons (ordered: false when either side is NaN) and masks ----
DNG_LANE_INLINE M operator<(F a, F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
DNG_LANE_INLINE M operator<=(F a, F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
DNG_LANE_INLINE M operator>(F a, F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
DNG_LANE_INLINE M operator>=(F a, F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GE_OQ)}; }
DNG_LANE_INLINE M operator!=(F a, F b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)}; }
DNG_LANE_INLINE M allTrue() { return {__mmask16(0xFFFF)}; }
DNG_LANE_INLINE M operator&(M a, M b) { return {_mm512_kand(a.v, b.v)}; }
DNG_LANE_INLINE M operator|(M a, M b) { return {_mm512_kor(a.v, b.v)}; }
DNG_LANE_INLINE M operator~(M a) { return {_mm512_knot(a.v)}; }
/// a and not b.
DNG_LANE_INLINE M andNot(M a, M b) { return {_mm512_kandn(b.v, a.v)}; }
/// Bit n set when lane n is true.
DNG_LANE_INLINE unsigned bits(M a) { return unsigned(a.v); }
DNG_LANE_INLINE bool any(M a) { return a.v != 0; }
DNG_LANE_INLINE bool all(M a) { return a.v == 0xFFFF; }
/// m ? a : b per lane.
DNG_LANE_INLINE F select(M m, F a, F b) { return {_mm512_mask_blend_ps(m.v, b.v, a.v)}; }
/// Lane n true when bit n is set.
DNG_LANE_INLINE M laneMask(unsigned lane_bits) { return {__mmask16(lane_bits)}; }

// ---- integers ----
DNG_LANE_INLINE I splatI(std::int32_t x) { return {_mm512_set1_epi32(x)}; }
DNG_LANE_INLINE I operator+(I a, I b) { return {_mm512_add_epi32(a.v, b.v)}; }
DNG_LANE_INLINE I operator*(I a, I b) { return {_mm512_mullo_epi32(a.v, b.v)}; }
DNG_LANE_INLINE I operator&(I a, I b) { return {_mm512_and_si512(a.v, b.v)}; }
DNG_LANE_INLINE I operator|(I a, I b) { return {_mm512_or_si512(a.v, b.v)}; }
DNG_LANE_INLINE I shiftLeft(I a, int n) { return {_mm512_sll_epi32(a.v, _mm_cvtsi32_si128(n))}; }
DNG_LANE_INLINE I shiftRight(I a, int n) { return {_mm512_srl_epi32(a.v, _mm_cvtsi32_si128(n))}; }
DNG_LANE_INLINE M operator==(I a, I b) { return {_mm512_cmpeq_epi32_mask(a.v, b.v)}; }
/// float -> int32 by truncation, as a C++ cast of a value in [0, 2^31).
DNG_LANE_INLINE I truncate(F a) { return {_mm512_cvttps_epi32(a.v)}; }
DNG_LANE_INLINE F toFloat(I a) { return {_mm512_cvtepi32_ps(a.v)}; }
DNG_LANE_INLINE I select(M m, I a, I b) { return {_mm512_mask_blend_epi32(m.v, b.v, a.v)}; }
/// Reinterprets integer bits as floats (a float stored in a 32-bit word).
DNG_LANE_INLINE F asFloat(I a) { return {_mm512_castsi512_ps(a.v)}; }

// ---- gathers: lanes where `m` is false read nothing and give 0 ----
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  return {_mm512_mask_i32gather_ps(_mm512_setzero_ps(), m.v, index.v, base, 4)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  return {_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m.v, index.v, base, 4)};
}
/// 64-bit words, returned as their low and high halves.
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  // Each 64-bit gather takes eight lanes, under its half of the mask.
  const __m512i first =
      _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(m.v), _mm512_castsi512_si256(index.v), base, 8);
  const __m512i second = _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(m.v >> 8),
                                                     _mm512_extracti64x4_epi64(index.v, 1), base, 8);
  // Even 32-bit words are low halves, odd ones high; indices 16 and up pick from `second`.
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  out_lo->v = _mm512_permutex2var_epi32(first, even, second);
  out_hi->v = _mm512_permutex2var_epi32(first, odd, second);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
