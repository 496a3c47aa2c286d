// Internal: the x86 lanes of lanes.h, for SSE4.1 (4 lanes) and AVX2 (8 lanes, which lanes_avx2_pair.h
// takes two at a time). Include lanes.h, not this file.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(DNG_LANES_AVX2)
#include <immintrin.h>
#define DNG_LANES_NS avx2
#elif defined(DNG_LANES_SSE41)
#include <smmintrin.h>
#define DNG_LANES_NS sse41
#endif

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

#if defined(DNG_LANES_AVX2)
constexpr int kWidth = 8;
using RawF = __m256;
using RawI = __m256i;
#define DNG_PS(op) _mm256_##op##_ps
#define DNG_PD(op) _mm256_##op##_pd
#define DNG_EPI32(op) _mm256_##op##_epi32
#define DNG_SI(op) _mm256_##op##_si256
#define DNG_CAST_PS(x) _mm256_castsi256_ps(x)
#define DNG_CVTT(x) _mm256_cvttps_epi32(x)
#else
constexpr int kWidth = 4;
using RawF = __m128;
using RawI = __m128i;
#define DNG_PS(op) _mm_##op##_ps
#define DNG_PD(op) _mm_##op##_pd
#define DNG_EPI32(op) _mm_##op##_epi32
#define DNG_SI(op) _mm_##op##_si128
#define DNG_CAST_PS(x) _mm_castsi128_ps(x)
#define DNG_CVTT(x) _mm_cvttps_epi32(x)
#endif

/// One bit per lane (bits(), laneMask()).
using LaneBits = std::uint32_t;

/// Lanes of float.
struct F {
  RawF v;
};
/// Lanes of 32-bit integers (signed or unsigned by use).
struct I {
  RawI v;
};
/// Lanes of booleans: all bits set or clear, in a float register.
struct M {
  RawF v;
};

// ---- floats ----
DNG_LANE_INLINE F splat(float x) { return {DNG_PS(set1)(x)}; }
DNG_LANE_INLINE F load(const float* p) { return {DNG_PS(loadu)(p)}; }
DNG_LANE_INLINE void store(float* p, F a) { DNG_PS(storeu)(p, a.v); }
DNG_LANE_INLINE F operator+(F a, F b) { return {DNG_PS(add)(a.v, b.v)}; }
DNG_LANE_INLINE F operator-(F a, F b) { return {DNG_PS(sub)(a.v, b.v)}; }
DNG_LANE_INLINE F operator*(F a, F b) { return {DNG_PS(mul)(a.v, b.v)}; }
DNG_LANE_INLINE F operator/(F a, F b) { return {DNG_PS(div)(a.v, b.v)}; }
DNG_LANE_INLINE F sqrt(F a) { return {DNG_PS(sqrt)(a.v)}; }
/// a < b ? a : b, exactly like dng::minOf (and std::min(b, a)), NaN included.
DNG_LANE_INLINE F minOf(F a, F b) { return {DNG_PS(min)(a.v, b.v)}; }
DNG_LANE_INLINE F maxOf(F a, F b) { return {DNG_PS(max)(a.v, b.v)}; }
DNG_LANE_INLINE F floor(F a) { return {DNG_PS(floor)(a.v)}; }
DNG_LANE_INLINE F abs(F a) { return {DNG_PS(andnot)(DNG_PS(set1)(-0.0f), a.v)}; }
/// The magnitude of `mag` with the sign of `sign` (std::copysign).
DNG_LANE_INLINE F copysign(F mag, F sign) {
  const RawF bit = DNG_PS(set1)(-0.0f);
  return {DNG_PS(or)(DNG_PS(andnot)(bit, mag.v), DNG_PS(and)(bit, sign.v))};
}

// ---- comparisons (ordered: false when either side is NaN) and masks ----
#if defined(DNG_LANES_AVX2)
DNG_LANE_INLINE M operator<(F a, F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
DNG_LANE_INLINE M operator<=(F a, F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
DNG_LANE_INLINE M operator>(F a, F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
DNG_LANE_INLINE M operator>=(F a, F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GE_OQ)}; }
DNG_LANE_INLINE M operator!=(F a, F b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)}; }
DNG_LANE_INLINE M allTrue() { return {_mm256_castsi256_ps(_mm256_set1_epi32(-1))}; }
#else
DNG_LANE_INLINE M operator<(F a, F b) { return {_mm_cmplt_ps(a.v, b.v)}; }
DNG_LANE_INLINE M operator<=(F a, F b) { return {_mm_cmple_ps(a.v, b.v)}; }
DNG_LANE_INLINE M operator>(F a, F b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
DNG_LANE_INLINE M operator>=(F a, F b) { return {_mm_cmpge_ps(a.v, b.v)}; }
DNG_LANE_INLINE M operator!=(F a, F b) { return {_mm_cmpneq_ps(a.v, b.v)}; }
DNG_LANE_INLINE M allTrue() { return {_mm_castsi128_ps(_mm_set1_epi32(-1))}; }
#endif
DNG_LANE_INLINE M operator&(M a, M b) { return {DNG_PS(and)(a.v, b.v)}; }
DNG_LANE_INLINE M operator|(M a, M b) { return {DNG_PS(or)(a.v, b.v)}; }
DNG_LANE_INLINE M operator~(M a) { return {DNG_PS(xor)(a.v, allTrue().v)}; }
/// a and not b.
DNG_LANE_INLINE M andNot(M a, M b) { return {DNG_PS(andnot)(b.v, a.v)}; }
/// Bit n set when lane n is true.
DNG_LANE_INLINE LaneBits bits(M a) { return LaneBits(DNG_PS(movemask)(a.v)); }
DNG_LANE_INLINE bool any(M a) { return bits(a) != 0; }
DNG_LANE_INLINE bool all(M a) { return bits(a) == (1u << kWidth) - 1; }
/// m ? a : b per lane.
DNG_LANE_INLINE F select(M m, F a, F b) { return {DNG_PS(blendv)(b.v, a.v, m.v)}; }
/// Lane n true when bit n is set. Each lane tests its own bit in one compare: the kernels build a mask
/// per slot of bodies, and a loop over the lanes cost more than the slot's box tests.
DNG_LANE_INLINE M laneMask(LaneBits lane_bits) {
#if defined(DNG_LANES_AVX2)
  const RawI lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
#else
  const RawI lane_bit = _mm_setr_epi32(1, 2, 4, 8);
#endif
  const RawI set = DNG_SI(and)(DNG_EPI32(set1)(std::int32_t(lane_bits)), lane_bit);
  return {DNG_CAST_PS(DNG_EPI32(cmpeq)(set, lane_bit))};
}

// ---- integers ----
DNG_LANE_INLINE I splatI(std::int32_t x) { return {DNG_EPI32(set1)(x)}; }
DNG_LANE_INLINE I operator+(I a, I b) { return {DNG_EPI32(add)(a.v, b.v)}; }
DNG_LANE_INLINE I operator*(I a, I b) { return {DNG_EPI32(mullo)(a.v, b.v)}; }
DNG_LANE_INLINE I operator&(I a, I b) { return {DNG_SI(and)(a.v, b.v)}; }
DNG_LANE_INLINE I operator|(I a, I b) { return {DNG_SI(or)(a.v, b.v)}; }
DNG_LANE_INLINE I shiftLeft(I a, int n) { return {DNG_EPI32(sll)(a.v, _mm_cvtsi32_si128(n))}; }
DNG_LANE_INLINE I shiftRight(I a, int n) { return {DNG_EPI32(srl)(a.v, _mm_cvtsi32_si128(n))}; }
DNG_LANE_INLINE M operator==(I a, I b) { return {DNG_CAST_PS(DNG_EPI32(cmpeq)(a.v, b.v))}; }
/// float -> int32 by truncation, as a C++ cast of a value in [0, 2^31).
DNG_LANE_INLINE I truncate(F a) { return {DNG_CVTT(a.v)}; }
#if defined(DNG_LANES_AVX2)
DNG_LANE_INLINE F toFloat(I a) { return {_mm256_cvtepi32_ps(a.v)}; }
DNG_LANE_INLINE I select(M m, I a, I b) {
  return {_mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(b.v), _mm256_castsi256_ps(a.v), m.v))};
}
#else
DNG_LANE_INLINE F toFloat(I a) { return {_mm_cvtepi32_ps(a.v)}; }
DNG_LANE_INLINE I select(M m, I a, I b) {
  return {_mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b.v), _mm_castsi128_ps(a.v), m.v))};
}
#endif
/// Reinterprets integer bits as floats (a float stored in a 32-bit word).
DNG_LANE_INLINE F asFloat(I a) { return {DNG_CAST_PS(a.v)}; }

// ---- gathers: lanes where `m` is false read nothing and give 0 ----
#if defined(DNG_LANES_AVX2)
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  return {_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, index.v, m.v, 4)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  return {_mm256_mask_i32gather_epi32(_mm256_setzero_si256(), reinterpret_cast<const int*>(base), index.v,
                                      _mm256_castps_si256(m.v), 4)};
}
// 64-bit words at base + kScale * index bytes, as their low and high halves.
template <int kScale> DNG_LANE_INLINE void gather64(const void* base, I index, M m, I* out_lo, I* out_hi) {
  const auto* b = static_cast<const long long*>(base);
  const __m256i mi = _mm256_castps_si256(m.v);
  // Each 64-bit gather takes four lanes; its mask is the 32-bit mask widened.
  const __m256i first = _mm256_mask_i32gather_epi64(_mm256_setzero_si256(), b, _mm256_castsi256_si128(index.v),
                                                    _mm256_cvtepi32_epi64(_mm256_castsi256_si128(mi)), kScale);
  const __m256i second = _mm256_mask_i32gather_epi64(_mm256_setzero_si256(), b, _mm256_extracti128_si256(index.v, 1),
                                                     _mm256_cvtepi32_epi64(_mm256_extracti128_si256(mi, 1)), kScale);
  // Even 32-bit words are low halves, odd ones high: sort each register into [lo x4 | hi x4].
  const __m256i split = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
  const __m256i a = _mm256_permutevar8x32_epi32(first, split);
  const __m256i c = _mm256_permutevar8x32_epi32(second, split);
  out_lo->v = _mm256_permute2x128_si256(a, c, 0x20);
  out_hi->v = _mm256_permute2x128_si256(a, c, 0x31);
}
/// 64-bit words, returned as their low and high halves.
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  gather64<8>(base, index, m, out_lo, out_hi);
}
/// The 32-bit words base[index] and base[index + 1] of each lane, as one 64-bit load (lanes.h
/// gatherPair): half the gathered elements of two gathers.
#define DNG_LANES_PAIR_GATHER 1
DNG_LANE_INLINE void gatherWordPair(const void* base, I index, M m, I* first, I* second) {
  gather64<4>(base, index, m, first, second);
}
#else
// SSE4.1 has no gather instruction: four scalar loads.
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  alignas(16) std::int32_t idx[4];
  alignas(16) float out[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(idx), index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n)
    out[n] = (on >> n) & 1u ? base[idx[n]] : 0.0f;
  return {_mm_load_ps(out)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  alignas(16) std::int32_t idx[4];
  alignas(16) std::uint32_t out[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(idx), index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n)
    out[n] = (on >> n) & 1u ? base[idx[n]] : 0u;
  return {_mm_load_si128(reinterpret_cast<const __m128i*>(out))};
}
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  alignas(16) std::int32_t idx[4];
  alignas(16) std::uint32_t lo[4], hi[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(idx), index.v);
  const unsigned on = bits(m);
  for (int n = 0; n < 4; ++n) {
    const std::uint64_t word = (on >> n) & 1u ? base[idx[n]] : 0u;
    lo[n] = std::uint32_t(word);
    hi[n] = std::uint32_t(word >> 32);
  }
  out_lo->v = _mm_load_si128(reinterpret_cast<const __m128i*>(lo));
  out_hi->v = _mm_load_si128(reinterpret_cast<const __m128i*>(hi));
}
#endif

// ---- packed records: a few floats per lane, one lane after the other in memory ----
// Shuffles within each 128-bit half in place of a transpose through an array, which moved every word
// with a scalar load and store: the bricked nearest sampleBatch ran about a quarter fewer instructions
// (callgrind) and was faster on an AMD EPYC without AVX-512 (docs/RUNTIME.md, "SIMD on CPUs without
// AVX-512"), where lane-crossing permutes like lanes_avx512.h's had been slower than the array.

namespace records {
// 4x4 transpose within each 128-bit half: out[r] holds (a, b, c, d) of lane r, and of lane r + 4 in
// the upper half of an AVX2 register.
DNG_LANE_INLINE void transpose4(RawF a, RawF b, RawF c, RawF d, RawF out[4]) {
  // The 64-bit halves of x and y interleaved: (x0 x1 y0 y1) and (x2 x3 y2 y3), per 128-bit half.
  const auto lows = [](RawF x, RawF y) DNG_LANE_LAMBDA {
    return DNG_PS(castpd)(DNG_PD(unpacklo)(DNG_PD(castps)(x), DNG_PD(castps)(y)));
  };
  const auto highs = [](RawF x, RawF y) DNG_LANE_LAMBDA {
    return DNG_PS(castpd)(DNG_PD(unpackhi)(DNG_PD(castps)(x), DNG_PD(castps)(y)));
  };
  const RawF ab_lo = DNG_PS(unpacklo)(a, b), ab_hi = DNG_PS(unpackhi)(a, b); // a0 b0 a1 b1, a2 b2 a3 b3
  const RawF cd_lo = DNG_PS(unpacklo)(c, d), cd_hi = DNG_PS(unpackhi)(c, d);
  out[0] = lows(ab_lo, cd_lo), out[1] = highs(ab_lo, cd_lo);
  out[2] = lows(ab_hi, cd_hi), out[3] = highs(ab_hi, cd_hi);
}
// Stores word kLane of `w` at *at (one vextractps).
template <int kLane> DNG_LANE_INLINE void storeWord(float* at, __m128 w) {
  const int word = _mm_extract_ps(w, kLane);
  std::memcpy(at, &word, sizeof word);
}
// Stores the four words of `w` as the fifth words of records 0-3 from `words`.
DNG_LANE_INLINE void storeFifths(float* words, __m128 w) {
  storeWord<0>(words + 4, w), storeWord<1>(words + 9, w), storeWord<2>(words + 14, w), storeWord<3>(words + 19, w);
}
} // namespace records

/// The lanes of packed xyz triples: lane n is (p[3n], p[3n + 1], p[3n + 2]).
DNG_LANE_INLINE void loadTriples(const float* p, F* x, F* y, F* z) {
  // Four points per 128-bit half, as three quadruples: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3.
#if defined(DNG_LANES_AVX2)
  const __m256 m0 = _mm256_loadu2_m128(p + 12, p), m1 = _mm256_loadu2_m128(p + 16, p + 4),
               m2 = _mm256_loadu2_m128(p + 20, p + 8);
#else
  const __m128 m0 = _mm_loadu_ps(p), m1 = _mm_loadu_ps(p + 4), m2 = _mm_loadu_ps(p + 8);
#endif
  const RawF xy = DNG_PS(shuffle)(m1, m2, _MM_SHUFFLE(2, 1, 3, 2)); // x2 y2 x3 y3
  const RawF yz = DNG_PS(shuffle)(m0, m1, _MM_SHUFFLE(1, 0, 2, 1)); // y0 z0 y1 z1
  x->v = DNG_PS(shuffle)(m0, xy, _MM_SHUFFLE(2, 0, 3, 0));
  y->v = DNG_PS(shuffle)(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));
  z->v = DNG_PS(shuffle)(yz, m2, _MM_SHUFFLE(3, 0, 3, 1));
}

/// Packed five-word records: word 5n + f of `out` is lane n of field[f] (copied as bytes, so the
/// records may be structs of floats and 32-bit integers). Each record is a 16-byte store of its
/// first four words and a 4-byte store of its fifth.
DNG_LANE_INLINE void storeQuintuples(void* out, const F field[5]) {
  RawF record[4];
  records::transpose4(field[0].v, field[1].v, field[2].v, field[3].v, record);
  auto* words = static_cast<float*>(out);
#if defined(DNG_LANES_AVX2)
  for (int r = 0; r < 4; ++r)
    _mm256_storeu2_m128(words + 5 * (r + 4), words + 5 * r, record[r]);
  records::storeFifths(words, _mm256_castps256_ps128(field[4].v));
  records::storeFifths(words + 20, _mm256_extractf128_ps(field[4].v, 1));
#else
  for (int r = 0; r < 4; ++r)
    _mm_storeu_ps(words + 5 * r, record[r]);
  records::storeFifths(words, field[4].v);
#endif
}

#undef DNG_PS
#undef DNG_PD
#undef DNG_EPI32
#undef DNG_SI
#undef DNG_CAST_PS
#undef DNG_CVTT

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
