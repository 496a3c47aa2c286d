// Internal: a small SIMD layer for the batch kernels, in the spirit of Jolt's Vec4/Vec8. One interface
// serves every instruction set: the translation unit that includes this header defines
// DNG_LANES_AVX512 (32 lanes in two registers), DNG_LANES_AVX2 (16 lanes in two registers), DNG_LANES_SSE41 (4 lanes)
// or DNG_LANES_NEON (4 lanes, aarch64) and is
// compiled for that set (runtime/CMakeLists.txt). Each set gets its own namespace, so the builds of
// the kernels never meet at link time.
//
// Every operation is the IEEE operation the scalar code uses (no FMA, no reciprocal estimates), so a
// lane computes bit for bit what the scalar path computes for the same particle: the scalar code stays
// the reference, and tests compare the two exactly.
//
// The interface: F (floats), I (32-bit integers), M (booleans) with arithmetic, comparisons, select,
// masks, gathers, and packed records (loadTriples: lane n is the point p[3n..3n+2]; storeQuintuples:
// word 5n + f of the output is lane n of field f), each set with its own shuffles; V3 below is written
// once on top of it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#define DNG_LANE_INLINE inline __attribute__((always_inline))
// The same for a lambda handed to an inlined kernel (after its parameter list).
#define DNG_LANE_LAMBDA __attribute__((always_inline))

#if defined(DNG_LANES_AVX512)
#include "lanes_avx512.h"
#elif defined(DNG_LANES_AVX2)
#include "lanes_avx2_pair.h"
#elif defined(DNG_LANES_SSE41)
#include "lanes_x86.h"
#elif defined(DNG_LANES_NEON)
#include "lanes_neon.h"
#else
#error "define DNG_LANES_AVX512, DNG_LANES_AVX2, DNG_LANES_SSE41 or DNG_LANES_NEON before including lanes.h"
#endif

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

/// The lanes whose bit is set in a LaneBits (bits(), laneMask()): lane n is bit n.
DNG_LANE_INLINE LaneBits laneBit(int lane) { return LaneBits(1) << lane; }
/// Every lane's bit.
DNG_LANE_INLINE LaneBits allLanes() { return LaneBits(~LaneBits(0)) >> (8 * sizeof(LaneBits) - kWidth); }
/// The bits of lanes 0 to n - 1, for n in [1, kWidth].
DNG_LANE_INLINE LaneBits firstLanes(int n) { return LaneBits(~LaneBits(0)) >> (8 * sizeof(LaneBits) - unsigned(n)); }
/// The lowest lane whose bit is set in `on`, which is not zero.
DNG_LANE_INLINE int lowestLane(LaneBits on) {
  return sizeof(LaneBits) > sizeof(unsigned) ? __builtin_ctzll(on) : __builtin_ctz(unsigned(on));
}

/// How many lanes' bits are set in `on`.
DNG_LANE_INLINE int laneCount(LaneBits on) { return __builtin_popcountll(static_cast<unsigned long long>(on)); }

/// Three lanes of floats: a point or a vector per lane.
struct V3 {
  F x, y, z;
};
DNG_LANE_INLINE V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
DNG_LANE_INLINE V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
DNG_LANE_INLINE V3 operator*(V3 a, F s) { return {a.x * s, a.y * s, a.z * s}; }
// Same association as dng::dot and dng::cross, so lanes round like the scalar code.
DNG_LANE_INLINE F dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
DNG_LANE_INLINE V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
DNG_LANE_INLINE F length(V3 a) { return sqrt(dot(a, a)); }
DNG_LANE_INLINE V3 select(M m, V3 a, V3 b) { return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)}; }
DNG_LANE_INLINE V3 splat(float x, float y, float z) { return {splat(x), splat(y), splat(z)}; }

/// Arrays of a register's lanes are aligned to a whole register of the widest set.
constexpr std::size_t kLaneAlign = 64;

/// Three arrays of a register's floats, lane by lane: a V3 stored for scalar code.
struct Lanes3 {
  alignas(kLaneAlign) float x[kWidth], y[kWidth], z[kWidth];
};

/// Each lane's own number: lane n holds n (for indexing arrays laid out lane by lane).
DNG_LANE_INLINE I laneNumbers() {
  alignas(kLaneAlign) static constexpr std::int32_t kNumbers[32] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                                                                    11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
                                                                    22, 23, 24, 25, 26, 27, 28, 29, 30, 31};
  static_assert(kWidth <= 32, "a number for every lane");
  I out;
  std::memcpy(&out, kNumbers, sizeof out);
  return out;
}

/// The smallest of the lanes of `x`.
DNG_LANE_INLINE std::int32_t lowestValue(I x) {
  alignas(kLaneAlign) std::int32_t lane[kWidth];
  std::memcpy(lane, &x, sizeof lane);
  std::int32_t low = lane[0];
  for (int n = 1; n < kWidth; ++n)
    low = lane[n] < low ? lane[n] : low;
  return low;
}

/// Each lane's base[index] and base[index + 1], for lanes of `m` (the others get 0). Sets with 64-bit
/// gathers (DNG_LANES_PAIR_GATHER) load both words at once, half the elements of two gathers: a dense
/// field's step, whose voxels are four floats, ran 10% faster with the AVX-512 kernels and 5% with the
/// AVX2 ones (bench/swarm_hash, fandisk, an AMD EPYC). Any index will do: a 64-bit gather needs no
/// alignment.
#ifdef DNG_LANES_PAIR_GATHER
DNG_LANE_INLINE void gatherPair(const float* base, I index, M m, F* first, F* second) {
  I a, b;
  gatherWordPair(base, index, m, &a, &b);
  *first = asFloat(a), *second = asFloat(b);
}
DNG_LANE_INLINE void gatherPair(const std::uint32_t* base, I index, M m, I* first, I* second) {
  gatherWordPair(base, index, m, first, second);
}
#else
DNG_LANE_INLINE void gatherPair(const float* base, I index, M m, F* first, F* second) {
  *first = gather(base, index, m), *second = gather(base, index + splatI(1), m);
}
DNG_LANE_INLINE void gatherPair(const std::uint32_t* base, I index, M m, I* first, I* second) {
  *first = gather(base, index, m), *second = gather(base, index + splatI(1), m);
}
#endif

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
