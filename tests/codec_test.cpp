// Bit codecs of the bricked encoding: precision of the octahedral normals and totality of every
// decoder (every bit pattern gives finite values), which the query path relies on.
#include "analytic_fields.h"
#include "dng/format/codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace dng {
namespace {

using namespace format;

std::vector<Vec3f> randomUnitVectors(std::size_t count) {
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  std::vector<Vec3f> out;
  while (out.size() < count) {
    const Vec3f v = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)});
    if (dot(v, v) > 0.0f) out.push_back(v);
  }
  // The folds of the octahedron are where encoders usually slip.
  for (Vec3f axis : {Vec3f{1, 0, 0}, Vec3f{-1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, -1, 0}, Vec3f{0, 0, 1}, Vec3f{0, 0, -1},
                     Vec3f{0.7071068f, 0.7071068f, 0}, Vec3f{-0.7071068f, 0, -0.7071068f}})
    out.push_back(axis);
  return out;
}

float maxOctError(int bits) {
  float worst = 0.0f;
  for (const Vec3f& n : randomUnitVectors(200000)) {
    std::uint32_t u = 0, v = 0;
    octEncode(n, bits, &u, &v);
    EXPECT_LT(u, 1u << bits);
    EXPECT_LT(v, 1u << bits);
    worst = std::max(worst, analytic::angleDegrees(n, octDecode(u, v, bits)));
  }
  return worst;
}

TEST(Octahedral, ElevenBitWordNormalsWithinATenthOfADegree) { EXPECT_LT(maxOctError(kWordOctBits), 0.1f); }

TEST(Octahedral, FifteenBitPlaneNormalsWithinOneHundredthOfADegree) { EXPECT_LT(maxOctError(kPlaneOctBits), 0.01f); }

TEST(Octahedral, EveryElevenBitPairDecodesToAFiniteUnitVector) {
  for (std::uint32_t u = 0; u < (1u << kWordOctBits); ++u) {
    for (std::uint32_t v = 0; v < (1u << kWordOctBits); ++v) {
      const Vec3f n = octDecode(u, v, kWordOctBits);
      ASSERT_NEAR(length(n), 1.0f, 1e-5f) << u << "," << v;
    }
  }
}

TEST(Octahedral, ZeroAndNonFiniteVectorsEncodePlusZ) {
  std::uint32_t u = 0, v = 0;
  octEncode({0, 0, 0}, kWordOctBits, &u, &v);
  EXPECT_LT(analytic::angleDegrees(octDecode(u, v, kWordOctBits), {0, 0, 1}), 0.1f);
  octEncode({NAN, 0, 0}, kWordOctBits, &u, &v);
  EXPECT_LT(analytic::angleDegrees(octDecode(u, v, kWordOctBits), {0, 0, 1}), 0.1f);
}

// octEncode picks, of the four codes around a normal, the one whose decoded normal makes the smallest
// angle with it as angleDegrees measures it (the first of equals): what it did when it compared the
// angles' atan2s, now mostly by products (smallerAngle). Random normals, the octahedron's folds, and
// +z from a zero vector, where the four candidates tie.
TEST(Octahedral, EncoderPicksTheCandidateWithTheSmallestPreciseAngle) {
  std::vector<Vec3f> normals = randomUnitVectors(100000);
  normals.push_back({0, 0, 0});
  for (const int bits : {kWordOctBits, kPlaneOctBits, kGradientOctBits}) {
    const std::uint32_t top = (1u << bits) - 1;
    for (const Vec3f& n : normals) {
      std::uint32_t u = 0, v = 0;
      octEncode(n, bits, &u, &v);
      // The same four candidates (octCell), compared by their angles in degrees.
      const Vec3f target = octTarget(n);
      std::uint32_t u0 = 0, v0 = 0;
      octCell(target, bits, &u0, &v0);
      double best = 360.0;
      std::uint32_t best_u = 0, best_v = 0;
      for (std::uint32_t du = 0; du < 2; ++du)
        for (std::uint32_t dv = 0; dv < 2; ++dv) {
          const std::uint32_t cu = std::min(u0 + du, top), cv = std::min(v0 + dv, top);
          const double angle = angleDegrees(octDecode(cu, cv, bits), target);
          if (angle < best) best = angle, best_u = cu, best_v = cv;
        }
      ASSERT_EQ(u, best_u) << bits << " bits, normal " << n.x << " " << n.y << " " << n.z;
      ASSERT_EQ(v, best_v) << bits << " bits, normal " << n.x << " " << n.y << " " << n.z;
    }
  }
}

// smallerAngle orders angles as their degrees do, near ties included.
TEST(Octahedral, SmallerAngleAgreesWithDegrees) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> jitter(-1e-6f, 1e-6f);
  const std::vector<Vec3f> normals = randomUnitVectors(20000);
  int decided = 0;
  for (std::size_t k = 0; k + 1 < normals.size(); ++k) {
    const Vec3f n = normals[k];
    // Nearly the same angle from either side, as a code's neighbours make.
    const Vec3f a = normalizeOrZero(n + Vec3f{jitter(rng), jitter(rng), jitter(rng)});
    const Vec3f b = normalizeOrZero(n + Vec3f{jitter(rng), jitter(rng), jitter(rng)});
    const Vec3f c = normals[k + 1];
    for (const auto& pair : {std::pair<Vec3f, Vec3f>{a, b}, {b, a}, {a, c}, {c, a}, {a, a}}) {
      const AngleParts x = angleParts(pair.first, n), y = angleParts(pair.second, n);
      ASSERT_EQ(smallerAngle(x, y), degreesOf(x) < degreesOf(y));
      decided += smallerAngle(x, y) ? 1 : 0;
    }
  }
  EXPECT_GT(decided, 20000); // both answers occur
}

// GRAD words (8 + 8 bits) round-trip within two thirds of a degree, and every word, including the ones a
// corrupted file may hold, decodes to a unit vector.
TEST(GradientWords, RoundTripWithinTwoThirdsOfADegreeAndEveryWordIsUnit) {
  float worst = 0.0f;
  for (const Vec3f& n : randomUnitVectors(200000))
    worst = std::max(worst, analytic::angleDegrees(n, gradientNormal(gradientWord(n))));
  EXPECT_LT(worst, 0.7f); // measured 0.63 degrees
  for (std::uint32_t word = 0; word <= 0xFFFFu; ++word)
    ASSERT_NEAR(length(gradientNormal(std::uint16_t(word))), 1.0f, 1e-5f) << word;
  EXPECT_LT(analytic::angleDegrees(gradientNormal(gradientWord({0, 0, 0})), {0, 0, 1}), 1.0f);
}

TEST(DistanceCodes, RangeEndsAndCodeEndsAreExact) {
  const float band = 3.7f;
  EXPECT_EQ(rangeValue(0, band), -band);
  EXPECT_EQ(rangeValue(kRangeMax, band), band);
  const float lo = rangeValue(1234, band);
  const float hi = rangeValue(54321, band);
  const float step = brickDistanceStep(lo, hi);
  EXPECT_EQ(wordDistance(packWord(5, 6, 0), lo, hi, step), lo);
  EXPECT_EQ(wordDistance(packWord(5, 6, kWordDistanceMax), lo, hi, step), hi);
}

TEST(DistanceCodes, EveryRangeAndCodeIsFiniteAndInsideTheBand) {
  const float band = 2.0f;
  for (std::uint32_t lo16 = 0; lo16 <= kRangeMax; lo16 += 97) {
    const std::uint32_t hi16 = kRangeMax - lo16 / 2; // covers hi < lo as in damaged files
    const float lo = rangeValue(lo16, band), hi = rangeValue(hi16, band);
    for (std::uint32_t code = 0; code <= kWordDistanceMax; code += 31) {
      const float d = wordDistance(packWord(0, 0, code), lo, hi, brickDistanceStep(lo, hi));
      ASSERT_TRUE(std::isfinite(d));
      ASSERT_LE(std::fabs(d), band * 1.0001f);
    }
  }
}

TEST(TopEntries, PackAndUnpackRoundTrip) {
  const std::uint64_t brick = packBrickEntry(kMaxPoolBricks - 1, 17, 65535);
  EXPECT_EQ(entryKind(brick), TileKind::kBrick);
  EXPECT_EQ(entryPoolIndex(brick), kMaxPoolBricks - 1);
  EXPECT_EQ(entryLo16(brick), 17u);
  EXPECT_EQ(entryHi16(brick), 65535u);

  std::uint32_t u = 0, v = 0;
  octEncode(normalizeOrZero({0.3f, -0.5f, -0.8f}), kPlaneOctBits, &u, &v);
  const std::uint64_t plane = packPlaneEntry(u, v, -1.25f);
  EXPECT_EQ(entryKind(plane), TileKind::kPlane);
  EXPECT_EQ(entryPlaneDistance(plane), -1.25f);
  EXPECT_LT(analytic::angleDegrees(entryPlaneNormal(plane), {0.3f, -0.5f, -0.8f}), 0.01f);

  EXPECT_EQ(entryKind(packFarEntry(TileKind::kFarInside)), TileKind::kFarInside);
  EXPECT_EQ(packFarEntry(TileKind::kFarOutside), 0u);
}

// PLN2 words (docs/FORMAT.md §5.5) keep the promise of the plane they were given: the decoded plane is
// nowhere in the voxel's cell above it (checked at the cell's corners, where a difference of two planes
// peaks), and it gives away little. Distances too low for a code, or not numbers, give no plane.
TEST(SecondPlaneWords, NeverRiseAboveTheirPlaneOverTheCell) {
  const float band = 3.5f, h = 0.25f, step = secondPlaneStep(band);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> distance(-band + 2.0f * step, band);
  float given_away = 0.0f;
  for (const Vec3f& n : randomUnitVectors(5000)) {
    const float d = distance(rng);
    const std::uint32_t word = secondPlaneWord(n, d, band, h);
    ASSERT_TRUE(hasSecondPlane(word)) << d;
    const Vec3f decoded_n = wordNormal(word);
    const float decoded_d = secondPlaneDistance(word, band, step);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3f s = Vec3f{corner & 1 ? 0.5f : -0.5f, corner & 2 ? 0.5f : -0.5f, corner & 4 ? 0.5f : -0.5f} * h;
      const float given = d + dot(n, s), stored = decoded_d + dot(decoded_n, s);
      ASSERT_LE(stored, given + 1e-6f * band) << d;
      given_away = std::max(given_away, given - stored);
    }
  }
  EXPECT_LT(given_away, step + 0.002f * h); // one code step, and the 11-bit normal's tilt
  EXPECT_EQ(secondPlaneWord({0, 0, 1}, -band, band, h), 0u);
  EXPECT_EQ(secondPlaneWord({0, 0, 1}, std::nanf(""), band, h), 0u);
  EXPECT_EQ(secondPlaneDistance(secondPlaneWord({0, 0, 1}, 2.0f * band, band, h), band, step), band);
}

TEST(SecondPlaneWords, EveryWordDecodesToAFiniteDistanceInTheBand) {
  const float band = 2.0f, step = secondPlaneStep(band);
  for (std::uint32_t code = 0; code <= kWordDistanceMax; ++code) {
    const std::uint32_t word = code << (2 * kWordOctBits) | 0x2ABCDu;
    EXPECT_EQ(hasSecondPlane(word), code != 0);
    const float d = secondPlaneDistance(word, band, step);
    ASSERT_TRUE(std::isfinite(d));
    ASSERT_GE(d, -band);
    ASSERT_LE(d, band);
  }
}

// A pair's record keeps the plane word in its low bits and rounds the raise down to a code, so the
// raised first plane it stands for never rises above the one given.
TEST(SecondPlaneWords, PairsRoundTheirRaiseDown) {
  const float band = 3.0f, h = 0.5f, step = secondPlaneRaiseStep(band);
  const std::uint32_t word = secondPlaneWord(normalizeOrZero({0.2f, -0.3f, 0.9f}), 0.4f, band, h);
  ASSERT_TRUE(hasSecondPlane(word));
  EXPECT_EQ(secondPlaneRecord(word, -1.0f, band), std::uint64_t(word)); // a plane alone
  EXPECT_EQ(secondPlaneRecord(word, std::nanf(""), band), std::uint64_t(word));
  EXPECT_EQ(secondPlaneRecord(0, 0.5f, band), 0u); // no plane, no pair
  for (float raise : {0.0f, 1e-5f, 0.123456f, 1.0f, 2.99f, 3.0f, 7.0f}) {
    const std::uint64_t record = secondPlaneRecord(word, raise, band);
    ASSERT_TRUE(isSecondPlanePair(record)) << raise;
    EXPECT_EQ(std::uint32_t(record), word);
    EXPECT_LE(secondPlaneRaise(record, step), raise) << raise;
    EXPECT_GT(secondPlaneRaise(record, step), std::min(raise, band) - 2.0f * step) << raise;
    EXPECT_EQ(record >> 49, 0u); // reserved bits
  }
}

TEST(BitCount, CountsEveryBit) {
  std::mt19937_64 rng(5);
  for (int n = 0; n < 1000; ++n) {
    const std::uint64_t x = n == 0 ? 0 : n == 1 ? ~std::uint64_t(0) : rng() & rng();
    std::uint32_t expected = 0;
    for (int b = 0; b < 64; ++b)
      expected += std::uint32_t((x >> b) & 1u);
    ASSERT_EQ(bitCount(x), expected) << x;
  }
}

} // namespace
} // namespace dng
