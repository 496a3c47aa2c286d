// Internal: the AVX2 lanes of lanes.h, 16 per chunk as two registers of 8 (lanes_x86.h's) side by
// side. Include lanes.h, not this file.
//
// The same reason as the AVX-512 lanes' two registers (lanes_avx512.h): a chunk's step is one long
// chain of dependent work around its gathers, and with every operation issued on two independent
// registers one register's chain runs while the other's waits. Measured with bench/swarm_hash on a
// Table 1 load (fandisk, `--isa avx2`, runs in turn): 52.9 -> 42.9 ns per particle-step, the same
// hashes. Each operation is the one-register operation twice, so the lanes stay bit for bit the
// scalar results.
#pragma once

#include "lanes_x86.h" // the one-register AVX2 lanes, namespace avx2

#undef DNG_LANES_NS
#define DNG_LANES_NS avx2x2

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

namespace one = ::dng::lanes::avx2;

constexpr int kWidth = 2 * one::kWidth;
/// One bit per lane (bits(), laneMask()): lanes 0-7 are the first register's.
using LaneBits = std::uint32_t;

/// Lanes 0-7 in a, 8-15 in b.
struct F {
  one::F a, b;
};
struct I {
  one::I a, b;
};
struct M {
  one::M a, b;
};

// Each operation on both registers.
#define DNG_PAIR_UNARY(R, op, T)                                                                                       \
  DNG_LANE_INLINE R op(T x) { return {one::op(x.a), one::op(x.b)}; }
#define DNG_PAIR_BINARY(R, op, T)                                                                                      \
  DNG_LANE_INLINE R op(T x, T y) { return {one::op(x.a, y.a), one::op(x.b, y.b)}; }

// ---- floats ----
DNG_LANE_INLINE F splat(float x) {
  const one::F v = one::splat(x);
  return {v, v};
}
DNG_LANE_INLINE F load(const float* p) { return {one::load(p), one::load(p + one::kWidth)}; }
DNG_LANE_INLINE void store(float* p, F x) { one::store(p, x.a), one::store(p + one::kWidth, x.b); }
DNG_PAIR_BINARY(F, operator+, F)
DNG_PAIR_BINARY(F, operator-, F)
DNG_PAIR_BINARY(F, operator*, F)
DNG_PAIR_BINARY(F, operator/, F)
DNG_PAIR_UNARY(F, sqrt, F)
DNG_PAIR_BINARY(F, minOf, F)
DNG_PAIR_BINARY(F, maxOf, F)
DNG_PAIR_UNARY(F, floor, F)
DNG_PAIR_UNARY(F, abs, F)
DNG_PAIR_BINARY(F, copysign, F)

// ---- comparisons and masks ----
DNG_PAIR_BINARY(M, operator<, F)
DNG_PAIR_BINARY(M, operator<=, F)
DNG_PAIR_BINARY(M, operator>, F)
DNG_PAIR_BINARY(M, operator>=, F)
DNG_PAIR_BINARY(M, operator!=, F)
DNG_LANE_INLINE M allTrue() {
  const one::M t = one::allTrue();
  return {t, t};
}
DNG_PAIR_BINARY(M, operator&, M)
DNG_PAIR_BINARY(M, operator|, M)
DNG_PAIR_UNARY(M, operator~, M)
DNG_PAIR_BINARY(M, andNot, M)
DNG_LANE_INLINE LaneBits bits(M x) { return one::bits(x.a) | one::bits(x.b) << one::kWidth; }
DNG_LANE_INLINE bool any(M x) { return bits(x) != 0; }
DNG_LANE_INLINE bool all(M x) { return bits(x) == (LaneBits(1) << kWidth) - 1; }
DNG_LANE_INLINE F select(M m, F x, F y) { return {one::select(m.a, x.a, y.a), one::select(m.b, x.b, y.b)}; }
DNG_LANE_INLINE M laneMask(LaneBits lane_bits) {
  constexpr LaneBits kOne = (LaneBits(1) << one::kWidth) - 1;
  return {one::laneMask(lane_bits & kOne), one::laneMask(lane_bits >> one::kWidth)};
}

// ---- integers ----
DNG_LANE_INLINE I splatI(std::int32_t x) {
  const one::I v = one::splatI(x);
  return {v, v};
}
DNG_PAIR_BINARY(I, operator+, I)
DNG_PAIR_BINARY(I, operator*, I)
DNG_PAIR_BINARY(I, operator&, I)
DNG_PAIR_BINARY(I, operator|, I)
DNG_LANE_INLINE I shiftLeft(I x, int n) { return {one::shiftLeft(x.a, n), one::shiftLeft(x.b, n)}; }
DNG_LANE_INLINE I shiftRight(I x, int n) { return {one::shiftRight(x.a, n), one::shiftRight(x.b, n)}; }
DNG_PAIR_BINARY(M, operator==, I)
DNG_PAIR_UNARY(I, truncate, F)
DNG_PAIR_UNARY(F, toFloat, I)
DNG_LANE_INLINE I select(M m, I x, I y) { return {one::select(m.a, x.a, y.a), one::select(m.b, x.b, y.b)}; }
DNG_PAIR_UNARY(F, asFloat, I)

// ---- gathers: lanes where `m` is false read nothing and give 0 ----
DNG_LANE_INLINE F gather(const float* base, I index, M m) {
  return {one::gather(base, index.a, m.a), one::gather(base, index.b, m.b)};
}
DNG_LANE_INLINE I gather(const std::uint32_t* base, I index, M m) {
  return {one::gather(base, index.a, m.a), one::gather(base, index.b, m.b)};
}
/// 64-bit words, returned as their low and high halves.
DNG_LANE_INLINE void gather(const std::uint64_t* base, I index, M m, I* out_lo, I* out_hi) {
  one::gather(base, index.a, m.a, &out_lo->a, &out_hi->a);
  one::gather(base, index.b, m.b, &out_lo->b, &out_hi->b);
}
DNG_LANE_INLINE void gatherWordPair(const void* base, I index, M m, I* first, I* second) {
  one::gatherWordPair(base, index.a, m.a, &first->a, &second->a);
  one::gatherWordPair(base, index.b, m.b, &first->b, &second->b);
}

// ---- packed records (lanes_x86.h's, one register's records after the other's) ----
DNG_LANE_INLINE void loadTriples(const float* p, F* x, F* y, F* z) {
  one::loadTriples(p, &x->a, &y->a, &z->a);
  one::loadTriples(p + 3 * one::kWidth, &x->b, &y->b, &z->b);
}
DNG_LANE_INLINE void storeQuintuples(void* out, const F field[5]) {
  const one::F a[5] = {field[0].a, field[1].a, field[2].a, field[3].a, field[4].a};
  const one::F b[5] = {field[0].b, field[1].b, field[2].b, field[3].b, field[4].b};
  one::storeQuintuples(out, a);
  one::storeQuintuples(static_cast<float*>(out) + 5 * one::kWidth, b);
}

#undef DNG_PAIR_UNARY
#undef DNG_PAIR_BINARY

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
