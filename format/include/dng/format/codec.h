// Bit-level codecs of the bricked encoding: octahedral normals, brick-top entries and pool words.
//
// Octahedral normal mapping after Cigolle et al., "A Survey of Efficient Representations for
// Independent Unit Vectors", JCGT 3(2), 2014. Decoding is total: every bit pattern yields a finite
// unit vector and a finite distance, so a validated file needs no per-query checks (docs/DESIGN.md §3).
//
// Top entry (64 bits), kind in bits 0-1 (TileKind):
//   far outside / far inside: bits 2-63 zero
//   plane: bits 2-16 octahedral u (15 bits), bits 17-31 v (15 bits), bits 32-63 float32 d_c
//   brick: bits 2-31 pool index, bits 32-47 lo16, bits 48-63 hi16 (distance range, see below)
// Pool word (32 bits): bits 0-10 octahedral u, bits 11-21 v, bits 22-31 distance q10. PLN2 records (64
// bits) start with such a word, over the range [-band, band] and q10 = 0 meaning "no plane", then a
// 16-bit raise and a pair flag (bit 48).
// Distance range: lo = -band + lo16 * (2 band / 65535), likewise hi; voxel distance
// d = lo + q10 * (hi - lo) / 1023, where q10 = 1023 gives hi and lo16/hi16 = 65535 give +band exactly.
#pragma once

#include "dng/format/layout.h"
#include "dng/format/vec3.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace dng {
namespace format {

inline constexpr int kPlaneOctBits = 15;
inline constexpr int kWordOctBits = 11;
inline constexpr int kWordDistanceBits = 10;
inline constexpr std::uint32_t kWordDistanceMax = (1u << kWordDistanceBits) - 1; // 1023
inline constexpr std::uint32_t kRangeMax = 65535;
inline constexpr std::uint32_t kMaxPoolBricks = 1u << 30;

/// Octahedral decode of two `bits`-wide integers. Total: every input gives a finite unit vector.
/// Correctly rounded sqrt and division only, so results are identical on every IEEE-754 host (a
/// hardware rsqrt estimate was measured no faster here and would differ between CPU models).
DNG_FORCE_INLINE Vec3f octDecode(std::uint32_t qu, std::uint32_t qv, int bits) {
  const float scale = 2.0f / float((1u << bits) - 1);
  float x = float(qu) * scale - 1.0f;
  float y = float(qv) * scale - 1.0f;
  const float z = 1.0f - std::fabs(x) - std::fabs(y);
  // Unfold the lower hemisphere without a branch (half of all normals take it, so a branch would
  // mispredict): x - sgn(x) * max(-z, 0) equals (1 - |y|) * sgn(x) when z < 0, x otherwise.
  const float t = -z > 0.0f ? -z : 0.0f; // not std::fmax: that is a libm call without -ffast-math
  x -= std::copysign(t, x);
  y -= std::copysign(t, y);
  // |x| + |y| + |z| == 1 here, so the length is at least 1/sqrt(3): never a division by zero.
  const float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
  return {x * inv, y * inv, z * inv};
}

/// The vector octEncode encodes: `n`, or +z when `n` is zero or not finite.
inline Vec3f octTarget(Vec3f n) {
  const float l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  return l1 > 0.0f && std::isfinite(l1) ? n : Vec3f{0.0f, 0.0f, 1.0f};
}

/// The lower corner (u0, v0) of the lattice cell that holds `n` (non-zero, finite), whose four corners
/// (clamped to the lattice) octEncode chooses among.
inline void octCell(Vec3f n, int bits, std::uint32_t* out_u0, std::uint32_t* out_v0) {
  const float inv_l1 = 1.0f / (std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z));
  float x = n.x * inv_l1;
  float y = n.y * inv_l1;
  if (n.z < 0.0f) {
    const float fx = (1.0f - std::fabs(y)) * (x >= 0.0f ? 1.0f : -1.0f);
    const float fy = (1.0f - std::fabs(x)) * (y >= 0.0f ? 1.0f : -1.0f);
    x = fx;
    y = fy;
  }
  const float max_q = float((1u << bits) - 1);
  const float fu = std::fmin(std::fmax((x + 1.0f) * 0.5f * max_q, 0.0f), max_q);
  const float fv = std::fmin(std::fmax((y + 1.0f) * 0.5f * max_q, 0.0f), max_q);
  *out_u0 = std::uint32_t(std::floor(fu));
  *out_v0 = std::uint32_t(std::floor(fv));
}

/// Octahedral encode of a unit vector to the nearest of the four surrounding lattice points
/// (the "precise" variant: it minimises the decoded angle error). A zero or non-finite vector
/// encodes +z. Used by writers only; not on any query path.
inline void octEncode(Vec3f n, int bits, std::uint32_t* out_u, std::uint32_t* out_v) {
  n = octTarget(n);
  std::uint32_t u0 = 0, v0 = 0;
  octCell(n, bits, &u0, &v0);
  const std::uint32_t top = (1u << bits) - 1;
  AngleParts best{};
  for (std::uint32_t du = 0; du < 2; ++du) {
    for (std::uint32_t dv = 0; dv < 2; ++dv) {
      const std::uint32_t u = u0 + du > top ? top : u0 + du;
      const std::uint32_t v = v0 + dv > top ? top : v0 + dv;
      // Candidates differ by less than a float cosine can resolve: compare precise angles.
      const AngleParts angle = angleParts(octDecode(u, v, bits), n);
      if ((du == 0 && dv == 0) || smallerAngle(angle, best)) {
        best = angle;
        *out_u = u;
        *out_v = v;
      }
    }
  }
}

/// Packs a far tile.
inline std::uint64_t packFarEntry(TileKind kind) { return std::uint64_t(kind); }

/// Packs a plane tile: quantized normal and the signed distance at the tile centre.
inline std::uint64_t packPlaneEntry(std::uint32_t qu, std::uint32_t qv, float d_centre) {
  std::uint32_t bits;
  std::memcpy(&bits, &d_centre, 4);
  return std::uint64_t(TileKind::kPlane) | std::uint64_t(qu) << 2 | std::uint64_t(qv) << (2 + kPlaneOctBits) |
         std::uint64_t(bits) << 32;
}

/// Packs a brick reference: pool index (< kMaxPoolBricks) and the quantized distance range.
inline std::uint64_t packBrickEntry(std::uint32_t pool_index, std::uint32_t lo16, std::uint32_t hi16) {
  return std::uint64_t(TileKind::kBrick) | std::uint64_t(pool_index) << 2 | std::uint64_t(lo16) << 32 |
         std::uint64_t(hi16) << 48;
}

inline TileKind entryKind(std::uint64_t entry) { return TileKind(entry & 3u); }
inline std::uint32_t entryPoolIndex(std::uint64_t entry) { return std::uint32_t(entry >> 2) & (kMaxPoolBricks - 1); }
inline std::uint32_t entryLo16(std::uint64_t entry) { return std::uint32_t(entry >> 32) & 0xFFFFu; }
inline std::uint32_t entryHi16(std::uint64_t entry) { return std::uint32_t(entry >> 48); }

inline Vec3f entryPlaneNormal(std::uint64_t entry) {
  constexpr std::uint32_t mask = (1u << kPlaneOctBits) - 1;
  return octDecode(std::uint32_t(entry >> 2) & mask, std::uint32_t(entry >> (2 + kPlaneOctBits)) & mask, kPlaneOctBits);
}

/// The plane's distance at the tile centre. May be non-finite in a damaged file: the loader rejects
/// such files, so queries on a validated view never see one.
inline float entryPlaneDistance(std::uint64_t entry) {
  const std::uint32_t bits = std::uint32_t(entry >> 32);
  float d;
  std::memcpy(&d, &bits, 4);
  return d;
}

/// Step between consecutive 16-bit range codes for a given band; readers compute it once.
inline float rangeStep(float band) { return 2.0f * band / float(kRangeMax); }

/// Dequantizes a 16-bit range end: -band .. +band in 65535 steps of rangeStep(band). Both ends are
/// exact, so voxels clamped to +-band decode to exactly +-band and stay "far".
inline float rangeValue(std::uint32_t q16, float band, float step) {
  return q16 >= kRangeMax ? band : -band + float(q16) * step;
}
inline float rangeValue(std::uint32_t q16, float band) { return rangeValue(q16, band, rangeStep(band)); }

/// Step of the LIFT section's int16 codes (since 1.2): lifts reach +-2 band, which undoes any lowering
/// (lowered values stop above -band) in steps of band / 16384, about 1e-4 voxel for a typical band.
inline float liftStep(float band) { return band * (1.0f / 16384.0f); }

/// The code for a lift, rounded to nearest and clamped to the int16 range (lifts are for accuracy,
/// not for bounds: rounding either way is fine).
inline std::int16_t liftCode(float lift, float band) {
  const float code = std::round(lift / liftStep(band));
  return std::int16_t(code > 32767.0f ? 32767.0f : code < -32767.0f ? -32767.0f : code);
}

/// GRAD and SHAD words (since 1.2 and 1.3): octahedral u in bits 0-7 and v in bits 8-15, so every word is a valid unit
/// normal. Within 0.63 degrees (tests/codec_test.cpp): the accurate query's half-plane correction scales a normal's
/// error by at most half a voxel, and measured on real meshes 8 bits a side read as 16 do (bench/accuracy_bench).
inline constexpr int kGradientOctBits = 8;

/// The GRAD or SHAD word of a normal; a zero or non-finite normal (a far voxel's) encodes +z.
inline std::uint16_t gradientWord(Vec3f n) {
  std::uint32_t qu = 0, qv = 0;
  octEncode(n, kGradientOctBits, &qu, &qv);
  return std::uint16_t(qu | qv << kGradientOctBits);
}

inline Vec3f gradientNormal(std::uint16_t word) {
  return octDecode(word & 0xFFu, std::uint32_t(word) >> kGradientOctBits, kGradientOctBits);
}

/// PLN2 (since 1.3): a tile's slot when it has no block of second planes.
inline constexpr std::uint32_t kNoSecondPlanes = 0xFFFFFFFFu;

/// PLN2 mask words per block: one bit per voxel of a tile of 2^log2 voxels a side.
inline constexpr std::uint32_t secondPlaneMaskWords(std::uint32_t log2) { return (1u << (3 * log2)) / 64u; }

/// Bits set in `x` (what std::popcount does in C++20), without a table or a CPU feature.
constexpr std::uint32_t bitCount(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ull);
  x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return std::uint32_t((x * 0x0101010101010101ull) >> 56);
}

/// Step between consecutive distance codes of PLN2 words: their range is the whole band, [-b, b].
inline float secondPlaneStep(float band) { return 2.0f * band / float(kWordDistanceMax); }

/// Whether a PLN2 record holds a plane: distance code 0 is "none" (a plane reading -band at the voxel
/// centre bounds nothing a first plane does not).
inline bool hasSecondPlane(std::uint64_t record) { return ((record >> (2 * kWordOctBits)) & kWordDistanceMax) != 0; }

/// A PLN2 record's plane distance at its voxel centre: -band + code * step, code 1023 giving +band exactly.
inline float secondPlaneDistance(std::uint64_t record, float band, float step) {
  const std::uint32_t code = std::uint32_t(record >> (2 * kWordOctBits)) & kWordDistanceMax;
  return code == kWordDistanceMax ? band : -band + float(code) * step;
}

/// A PLN2 record's plane normal (wordNormal of its low 32 bits).
inline Vec3f secondPlaneNormal(std::uint64_t record) {
  constexpr std::uint32_t mask = (1u << kWordOctBits) - 1;
  return octDecode(std::uint32_t(record) & mask, std::uint32_t(record >> kWordOctBits) & mask, kWordOctBits);
}

/// PLN2 record bit 48: the bound is a pair, the smaller of the voxel's own plane raised by the record's
/// raise and the record's plane (beside a concave crease), instead of the record's plane alone.
inline constexpr std::uint64_t kSecondPlanePair = std::uint64_t(1) << 48;
inline bool isSecondPlanePair(std::uint64_t record) { return (record & kSecondPlanePair) != 0; }

/// Step of a pair's 16-bit raise code (bits 32-47): up to the band in 65,535 steps.
inline float secondPlaneRaiseStep(float band) { return band / 65535.0f; }
inline float secondPlaneRaise(std::uint64_t record, float step) { return float((record >> 32) & 0xFFFFu) * step; }

/// The plane part (bits 0-31) of a PLN2 record: a plane with normal `normal` (unit) reading `distance`
/// at the voxel centre, the normal quantized as pool words quantize theirs (secondPlaneNormal decodes
/// it), the distance rounded down after lowering it by what the quantized normal's tilt can add over
/// the cell, so the stored plane never rises above the given one (docs/FORMAT.md §5.5). A distance too
/// low for any code (or not a number) gives 0: no plane.
inline std::uint32_t secondPlaneWord(Vec3f normal, float distance, float band, float voxel_size) {
  std::uint32_t qu = 0, qv = 0;
  octEncode(normal, kWordOctBits, &qu, &qv);
  const std::uint32_t mask = (1u << kWordOctBits) - 1;
  const Vec3f tilt = octDecode(qu & mask, qv & mask, kWordOctBits) - normal;
  const float target = distance - (std::fabs(tilt.x) + std::fabs(tilt.y) + std::fabs(tilt.z)) * 0.5f * voxel_size;
  const float step = secondPlaneStep(band);
  if (!(target >= -band + step)) return 0;
  std::uint32_t code = target >= band ? kWordDistanceMax : std::uint32_t(std::floor((target + band) / step));
  code = code < 1 ? 1 : code > kWordDistanceMax ? kWordDistanceMax : code;
  const auto word = [&](std::uint32_t c) { return qu | qv << kWordOctBits | c << (2 * kWordOctBits); };
  while (code > 1 && secondPlaneDistance(word(code), band, step) > target)
    --code;
  return secondPlaneDistance(word(code), band, step) > target ? 0 : word(code);
}

/// A PLN2 record: the plane alone (`raise` not a number or negative), or a pair with the voxel's own
/// plane raised by `raise` (rounded down to a code, so the pair never rises above the given one).
inline std::uint64_t secondPlaneRecord(std::uint32_t plane_word, float raise, float band) {
  if (plane_word == 0 || !(raise >= 0.0f)) return plane_word;
  const float code = std::floor(raise / secondPlaneRaiseStep(band));
  const auto r = std::uint64_t(code > 65535.0f ? 65535.0f : code);
  return std::uint64_t(plane_word) | r << 32 | kSecondPlanePair;
}

/// Step between consecutive 10-bit distance codes of a brick whose range is [lo, hi].
inline float brickDistanceStep(float lo, float hi) { return (hi - lo) * (1.0f / float(kWordDistanceMax)); }

/// Distance of a voxel word in a brick with range [lo, hi] and step brickDistanceStep(lo, hi).
/// Code 0 gives lo and code 1023 gives hi exactly.
inline float wordDistance(std::uint32_t word, float lo, float hi, float step) {
  const std::uint32_t code = word >> (2 * kWordOctBits);
  return code == kWordDistanceMax ? hi : lo + float(code) * step;
}

inline std::uint32_t packWord(std::uint32_t qu, std::uint32_t qv, std::uint32_t qd) {
  return qu | qv << kWordOctBits | qd << (2 * kWordOctBits);
}

inline Vec3f wordNormal(std::uint32_t word) {
  constexpr std::uint32_t mask = (1u << kWordOctBits) - 1;
  return octDecode(word & mask, (word >> kWordOctBits) & mask, kWordOctBits);
}

} // namespace format
} // namespace dng
