// Our XXH64 against the published reference values and, when installed, against libxxhash.
#include "dng/format/xxhash64.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#ifdef DNG_HAVE_LIBXXHASH
#include <xxhash.h>
#endif

namespace dng {
namespace {

TEST(XxHash64, EmptyInputMatchesReference) { EXPECT_EQ(format::xxhash64(nullptr, 0), 0xEF46DB3751D8E999ull); }

TEST(XxHash64, DependsOnEveryByteAndTheSeed) {
  std::vector<unsigned char> data(100, 7);
  const std::uint64_t base = format::xxhash64(data.data(), data.size());
  for (std::size_t i = 0; i < data.size(); ++i) {
    data[i] ^= 1;
    EXPECT_NE(format::xxhash64(data.data(), data.size()), base) << "byte " << i;
    data[i] ^= 1;
  }
  EXPECT_NE(format::xxhash64(data.data(), data.size(), 1), base);
}

#ifdef DNG_HAVE_LIBXXHASH
TEST(XxHash64, MatchesLibxxhashOnEveryLengthUpTo300AndUnalignedStarts) {
  std::mt19937 rng(42);
  std::vector<unsigned char> data(1024 + 3);
  for (auto& b : data)
    b = static_cast<unsigned char>(rng());
  for (std::size_t length = 0; length <= 300; ++length) {
    for (std::size_t start = 0; start < 3; ++start) {
      for (std::uint64_t seed : {0ull, 1ull, 0x9E3779B97F4A7C15ull}) {
        ASSERT_EQ(format::xxhash64(data.data() + start, length, seed), XXH64(data.data() + start, length, seed))
            << "length " << length << " start " << start << " seed " << seed;
      }
    }
  }
  EXPECT_EQ(format::xxhash64(data.data(), data.size()), XXH64(data.data(), data.size(), 0));
}
#else
TEST(XxHash64, MatchesLibxxhash) { GTEST_SKIP() << "libxxhash not installed: reference comparison skipped"; }
#endif

} // namespace
} // namespace dng
