// Internal: the AVX-512 lanes of lanes.h (F, DQ, BW, VL), 32 per chunk as two registers of 16, the
// booleans in mask registers. Include lanes.h, not this file.
//
// Mask registers make the step's many selects and mask operations one instruction each. Two registers
// per operation: a chunk's step is one long chain of dependent work (the response's gathers, its
// rules, the end of the move, the walk's gathers), and an AVX-512 gather takes about 9 ns from issue
// to result on an AMD EPYC (6 ns apart when independent; on an Intel Xeon, from the first-level
// cache, 7.8 ns and 1.7 ns), so each operation issues the same instruction on two independent
// registers and one register's chain runs while the other's waits (bench/swarm_hash on a Table 1
// load, on the EPYC: 29.5 -> 23.7 ns per particle-step against one register; on the Xeon 23.5 -> 19.3).
// Four registers per operation measured no faster on either (Xeon: 19.9 against 19.4).
// Every operation is the IEEE operation the scalar code uses (floor by rounding towards minus infinity,
// no fused multiply-adds; vminps and vmaxps return their second operand when either is NaN, as
// dng::minOf does), so the lanes stay bit for bit the scalar results.
#pragma once

#include <cstdint>
#include <immintrin.h>

#define DNG_LANES_NS avx512

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

constexpr int kWidth = 32;
/// One bit per lane (bits(), laneMask()).
using LaneBits = std::uint32_t;

/// Lanes of float: lanes 0-15 in a, 16-31 in b.
struct F {
  __m512 a, b;
};
/// Lanes of 32-bit integers (signed or unsigned by use).
struct I {
  __m512i a, b;
};
/// Lanes of booleans: one bit per lane in two mask registers.
struct M {
  __mmask16 a, b;
};

// ---- floats ----
DNG_LANE_INLINE F splat(float x) {
  const __m512 v = _mm512_set1_ps(x);
  return {v, v};
}
DNG_LANE_INLINE F load(const float* p) { return {_mm512_loadu_ps(p), _mm512_loadu_ps(p + 16)}; }
DNG_LANE_INLINE void store(float* p, F x) { _mm512_storeu_ps(p, x.a), _mm512_storeu_ps(p + 16, x.b); }
DNG_LANE_INLINE F operator+(F x, F y) { return {_mm512_add_ps(x.a, y.a), _mm512_add_ps(x.b, y.b)}; }
DNG_LANE_INLINE F operator-(F x, F y) { return {_mm512_sub_ps(x.a, y.a), _mm512_sub_ps(x.b, y.b)}; }
DNG_LANE_INLINE F operator*(F x, F y) { return {_mm512_mul_ps(x.a, y.a), _mm512_mul_ps(x.b, y.b)}; }
DNG_LANE_INLINE F operator/(F x, F y) { return {_mm512_div_ps(x.a, y.a), _mm512_div_ps(x.b, y.b)}; }
DNG_LANE_INLINE F sqrt(F x) { return {_mm512_sqrt_ps(x.a), _mm512_sqrt_ps(x.b)}; }
DNG_LANE_INLINE F minOf(F x, F y) { return {_mm512_min_ps(x.a, y.a), _mm512_min_ps(x.b, y.b)}; }
DNG_LANE_INLINE F maxOf(F x, F y) { return {_mm512_max_ps(x.a, y.a), _mm512_max_ps(x.b, y.b)}; }
DNG_LANE_INLINE F floor(F x) {
  return {_mm512_roundscale_ps(x.a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC),
          _mm512_roundscale_ps(x.b, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)};
}
DNG_LANE_INLINE F abs(F x) {
  const __m512 bit = _mm512_set1_ps(-0.0f);
  return {_mm512_andnot_ps(bit, x.a), _mm512_andnot_ps(bit, x.b)};
}
DNG_LANE_INLINE F copysign(F mag, F sign) {
  const __m512 bit = _mm512_set1_ps(-0.0f);
  return {_mm512_or_ps(_mm512_andnot_ps(bit, mag.a), _mm512_and_ps(bit, sign.a)),
          _mm512_or_ps(_mm512_andnot_ps(bit, mag.b), _mm512_and_ps(bit, sign.b))};
}

// ---- comparisons (ordered: false when either side is NaN) and masks ----
DNG_LANE_INLINE M operator<(F x, F y) {
  return {_mm512_cmp_ps_mask(x.a, y.a, _CMP_LT_OQ), _mm512_cmp_ps_mask(x.b, y.b, _CMP_LT_OQ)};
}
DNG_LANE_INLINE M operator<=(F x, F y) {
  return {_mm512_cmp_ps_mask(x.a, y.a, _CMP_LE_OQ), _mm512_cmp_ps_mask(x.b, y.b, _CMP_LE_OQ)};
}
DNG_LANE_INLINE M operator>(F x, F y) {
  return {_mm512_cmp_ps_mask(x.a, y.a, _CMP_GT_OQ), _mm512_cmp_ps_mask(x.b, y.b, _CMP_GT_OQ)};
}
DNG_LANE_INLINE M operator>=(F x, F y) {
  return {_mm512_cmp_ps_mask(x.a, y.a, _CMP_GE_OQ), _mm512_cmp_ps_mask(x.b, y.b, _CMP_GE_OQ)};
}
DNG_LANE_INLINE M operator!=(F x, F y) {
  return {_mm512_cmp_ps_mask(x.a, y.a, _CMP_NEQ_UQ), _mm512_cmp_ps_mask(x.b, y.b, _CMP_NEQ_UQ)};
}
DNG_LANE_INLINE M allTrue() { return {__mmask16(0xFFFF), __mmask16(0xFFFF)}; }
DNG_LANE_INLINE M operator&(M x, M y) { return {_mm512_kand(x.a, y.a), _mm512_kand(x.b, y.b)}; }
DNG_LANE_INLINE M operator|(M x, M y) { return {_mm512_kor(x.a, y.a), _mm512_kor(x.b, y.b)}; }
DNG_LANE_INLINE M operator~(M x) { return {_mm512_knot(x.a), _mm512_knot(x.b)}; }
/// x and not y.
DNG_LANE_INLINE M andNot(M x, M y) { return {_mm512_kandn(y.a, x.a), _mm512_kandn(y.b, x.b)}; }
/// Bit n set when lane n is true. Both halves meet in a mask register (kunpckwd, kortestw): moved out
/// to general registers half by half, each test took four instructions.
DNG_LANE_INLINE LaneBits bits(M x) { return _cvtmask32_u32(_mm512_kunpackw(__mmask32(x.b), __mmask32(x.a))); }
DNG_LANE_INLINE bool any(M x) { return _kortestz_mask16_u8(x.a, x.b) == 0; }
DNG_LANE_INLINE bool all(M x) { return (x.a & x.b) == 0xFFFF; }
/// m ? x : y per lane.
DNG_LANE_INLINE F select(M m, F x, F y) {
  return {_mm512_mask_blend_ps(m.a, y.a, x.a), _mm512_mask_blend_ps(m.b, y.b, x.b)};
}
/// Lane n true when bit n is set.
DNG_LANE_INLINE M laneMask(LaneBits lane_bits) { return {__mmask16(lane_bits), __mmask16(lane_bits >> 16)}; }

// ---- integers ----
DNG_LANE_INLINE I splatI(std::int32_t x) {
  const __m512i v = _mm512_set1_epi32(x);
  return {v, v};
}
DNG_LANE_INLINE I operator+(I x, I y) { return {_mm512_add_epi32(x.a, y.a), _mm512_add_epi32(x.b, y.b)}; }
DNG_LANE_INLINE I operator*(I x, I y) { return {_mm512_mullo_epi32(x.a, y.a), _mm512_mullo_epi32(x.b, y.b)}; }
DNG_LANE_INLINE I operator&(I x, I y) { return {_mm512_and_si512(x.a, y.a), _mm512_and_si512(x.b, y.b)}; }
DNG_LANE_INLINE I operator|(I x, I y) { return {_mm512_or_si512(x.a, y.a), _mm512_or_si512(x.b, y.b)}; }
DNG_LANE_INLINE I shiftLeft(I x, int n) {
  const __m128i c = _mm_cvtsi32_si128(n);
  return {_mm512_sll_epi32(x.a, c), _mm512_sll_epi32(x.b, c)};
}
DNG_LANE_INLINE I shiftRight(I x, int n) {
  const __m128i c = _mm_cvtsi32_si128(n);
  return {_mm512_srl_epi32(x.a, c), _mm512_srl_epi32(x.b, c)};
}
DNG_LANE_INLINE M operator==(I x, I y) {
  return {_mm512_cmpeq_epi32_mask(x.a, y.a), _mm512_cmpeq_epi32_mask(x.b, y.b)};
}
/// float -> int32 by truncation, as a C++ cast of a value in [0, 2^31).
DNG_LANE_INLINE I truncate(F x) { return {_mm512_cvttps_epi32(x.a), _mm512_cvttps_epi32(x.b)}; }
DNG_LANE_INLINE F toFloat(I x) { return {_mm512_cvtepi32_ps(x.a), _mm512_cvtepi32_ps(x.b)}; }
DNG_LANE_INLINE I select(M m, I x, I y) {
  return {_mm512_mask_blend_epi32(m.a, y.a, x.a), _mm512_mask_blend_epi32(m.b, y.b, x.b)};
}
/// Reinterprets integer bits as floats (a float stored in a 32-bit word).
DNG_LANE_INLINE F asFloat(I x) { return {_mm512_castsi512_ps(x.a), _mm512_castsi512_ps(x.b)}; }

// ---- gathers: lanes where `m` is false read nothing and give 0 ----
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  return {_mm512_mask_i32gather_ps(_mm512_setzero_ps(), m.a, index.a, base, 4),
          _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m.b, index.b, base, 4)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  return {_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m.a, index.a, base, 4),
          _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m.b, index.b, base, 4)};
}
// 16 lanes of 64-bit words at base + kScale * index bytes, as their low and high halves: each 64-bit
// gather takes eight lanes, under its half of the mask; even 32-bit words are low halves, odd ones
// high (indices 16 and up pick from the second).
template <int kScale>
DNG_LANE_INLINE void gather64(const void* base, __m512i index, __mmask16 m, __m512i* lo, __m512i* hi) {
  const __m512i first =
      _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(m), _mm512_castsi512_si256(index), base, kScale);
  const __m512i second = _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), __mmask8(m >> 8),
                                                     _mm512_extracti64x4_epi64(index, 1), base, kScale);
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  *lo = _mm512_permutex2var_epi32(first, even, second);
  *hi = _mm512_permutex2var_epi32(first, odd, second);
}
/// base[index] = x in the lanes of `m` (indices distinct). Only this set has a scatter instruction.
#define DNG_LANES_SCATTER 1
DNG_LANE_INLINE void scatter(float* base, I index, M m, F x) {
  _mm512_mask_i32scatter_ps(base, m.a, index.a, x.a, 4);
  _mm512_mask_i32scatter_ps(base, m.b, index.b, x.b, 4);
}
/// 64-bit words, returned as their low and high halves.
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  gather64<8>(base, index.a, m.a, &out_lo->a, &out_hi->a);
  gather64<8>(base, index.b, m.b, &out_lo->b, &out_hi->b);
}
/// The 32-bit words base[index] and base[index + 1] of each lane, as one 64-bit load (lanes.h
/// gatherPair): half the gathered elements of two gathers.
#define DNG_LANES_PAIR_GATHER 1
DNG_LANE_INLINE void gatherWordPair(const void* base, I index, M m, I* first, I* second) {
  gather64<4>(base, index.a, m.a, &first->a, &second->a);
  gather64<4>(base, index.b, m.b, &first->b, &second->b);
}

// ---- packed records: a few floats per lane, one lane after the other in memory ----
// Lane permutes in place of a transpose through the stack: written lane by lane and read back as a
// register, that transpose stalls on store forwarding (perf, bricked nearest sampleBatch on coherent
// points: a fifth of the time was spent loading the points).

namespace records {
// For 16 records of `kWords` words, register o of the stored words (words 16o to 16o + 15) draws word
// w = 16o + q from lane w / kWords of field w % kWords. permutex2var picks lane L of a pair of
// registers (fields 2f and 2f + 1) with index L + 16 (field & 1); permutexvar reads only the low four
// bits, so the same index serves a fifth field. Loading is the reverse: field f of lane q is word
// kWords q + f, from the pair of registers (words 0-31) or the third (32-47, index less 32).
template <int kWords> struct Table {
  alignas(64) std::int32_t index[kWords][16] = {};
  std::uint16_t mask[kWords][2] = {}; // storing: fields 2-3, field 4; loading: from the third register
};
constexpr Table<5> storeTable() {
  Table<5> t;
  for (int o = 0; o < 5; ++o)
    for (int q = 0; q < 16; ++q) {
      const int w = 16 * o + q, lane = w / 5, field = w % 5;
      t.index[o][q] = lane + (field < 4 ? 16 * (field & 1) : 0);
      if (field == 2 || field == 3) t.mask[o][0] |= std::uint16_t(1u << q);
      if (field == 4) t.mask[o][1] |= std::uint16_t(1u << q);
    }
  return t;
}
constexpr Table<3> loadTable() {
  Table<3> t;
  for (int f = 0; f < 3; ++f)
    for (int q = 0; q < 16; ++q) {
      const int w = 3 * q + f;
      t.index[f][q] = w < 32 ? w : w - 32;
      if (w >= 32) t.mask[f][0] |= std::uint16_t(1u << q);
    }
  return t;
}
inline constexpr Table<5> kStore = storeTable();
inline constexpr Table<3> kLoad = loadTable();

DNG_LANE_INLINE void loadTriples16(const float* p, __m512* x, __m512* y, __m512* z) {
  const __m512 r0 = _mm512_loadu_ps(p), r1 = _mm512_loadu_ps(p + 16), r2 = _mm512_loadu_ps(p + 32);
  __m512* out[3] = {x, y, z};
  for (int f = 0; f < 3; ++f) {
    const __m512i index = _mm512_load_si512(kLoad.index[f]);
    *out[f] = _mm512_mask_permutexvar_ps(_mm512_permutex2var_ps(r0, index, r1), kLoad.mask[f][0], index, r2);
  }
}
DNG_LANE_INLINE void storeQuintuples16(float* out, const __m512 field[5]) {
  for (int o = 0; o < 5; ++o) {
    const __m512i index = _mm512_load_si512(kStore.index[o]);
    const __m512 low = _mm512_permutex2var_ps(field[0], index, field[1]);
    const __m512 high = _mm512_permutex2var_ps(field[2], index, field[3]);
    const __m512 words = _mm512_mask_blend_ps(kStore.mask[o][0], low, high);
    _mm512_storeu_ps(out + 16 * o, _mm512_mask_permutexvar_ps(words, kStore.mask[o][1], index, field[4]));
  }
}
} // namespace records

/// The lanes of packed xyz triples: lane n is (p[3n], p[3n + 1], p[3n + 2]).
DNG_LANE_INLINE void loadTriples(const float* p, F* x, F* y, F* z) {
  records::loadTriples16(p, &x->a, &y->a, &z->a);
  records::loadTriples16(p + 48, &x->b, &y->b, &z->b);
}
/// Packed five-word records: word 5n + f of `out` is lane n of field[f].
DNG_LANE_INLINE void storeQuintuples(void* out, const F field[5]) {
  const __m512 a[5] = {field[0].a, field[1].a, field[2].a, field[3].a, field[4].a};
  const __m512 b[5] = {field[0].b, field[1].b, field[2].b, field[3].b, field[4].b};
  records::storeQuintuples16(static_cast<float*>(out), a);
  records::storeQuintuples16(static_cast<float*>(out) + 80, b);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
