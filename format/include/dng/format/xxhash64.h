// XXH64, the 64-bit xxHash (Yann Collet), written from the published algorithm description.
//
// Why our own copy: the runtime must not depend on libxxhash, yet reader and writer must agree on
// every bit. One implementation serves both, and tests/hash_test.cpp checks it against libxxhash's
// XXH64 on many lengths and seeds whenever that library is installed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace dng {
namespace format {

namespace xxh64_detail {

inline constexpr std::uint64_t kPrime1 = 0x9E3779B185EBCA87ull;
inline constexpr std::uint64_t kPrime2 = 0xC2B2AE3D27D4EB4Full;
inline constexpr std::uint64_t kPrime3 = 0x165667B19E3779F9ull;
inline constexpr std::uint64_t kPrime4 = 0x85EBCA77C2B2AE63ull;
inline constexpr std::uint64_t kPrime5 = 0x27D4EB2F165667C5ull;

inline std::uint64_t rotl(std::uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }

inline std::uint64_t read64(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v; // the format is little-endian only; hosts are checked before hashing matters
}

inline std::uint32_t read32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

inline std::uint64_t round(std::uint64_t acc, std::uint64_t input) {
  acc += input * kPrime2;
  return rotl(acc, 31) * kPrime1;
}

inline std::uint64_t mergeRound(std::uint64_t acc, std::uint64_t lane) {
  acc ^= round(0, lane);
  return acc * kPrime1 + kPrime4;
}

inline std::uint64_t avalanche(std::uint64_t h) {
  h ^= h >> 33;
  h *= kPrime2;
  h ^= h >> 29;
  h *= kPrime3;
  h ^= h >> 32;
  return h;
}

/// Consumes 32-byte stripes with four lanes; returns the merged accumulator.
inline std::uint64_t stripes(const unsigned char*& p, const unsigned char* end, std::uint64_t seed) {
  std::uint64_t v1 = seed + kPrime1 + kPrime2;
  std::uint64_t v2 = seed + kPrime2;
  std::uint64_t v3 = seed;
  std::uint64_t v4 = seed - kPrime1;
  while (end - p >= 32) {
    v1 = round(v1, read64(p));
    v2 = round(v2, read64(p + 8));
    v3 = round(v3, read64(p + 16));
    v4 = round(v4, read64(p + 24));
    p += 32;
  }
  std::uint64_t h = rotl(v1, 1) + rotl(v2, 7) + rotl(v3, 12) + rotl(v4, 18);
  h = mergeRound(h, v1);
  h = mergeRound(h, v2);
  h = mergeRound(h, v3);
  return mergeRound(h, v4);
}

} // namespace xxh64_detail

/// XXH64 of `size` bytes at `data` (which may be null when size is 0). Pure function, thread-safe,
/// any alignment.
inline std::uint64_t xxhash64(const void* data, std::size_t size, std::uint64_t seed = 0) {
  using namespace xxh64_detail;
  const auto* p = static_cast<const unsigned char*>(data);
  const unsigned char* end = p + size;
  std::uint64_t h = size >= 32 ? stripes(p, end, seed) : seed + kPrime5;
  h += static_cast<std::uint64_t>(size);
  while (end - p >= 8) {
    h ^= round(0, read64(p));
    h = rotl(h, 27) * kPrime1 + kPrime4;
    p += 8;
  }
  if (end - p >= 4) {
    h ^= static_cast<std::uint64_t>(read32(p)) * kPrime1;
    h = rotl(h, 23) * kPrime2 + kPrime3;
    p += 4;
  }
  while (p < end) {
    h ^= static_cast<std::uint64_t>(*p) * kPrime5;
    h = rotl(h, 11) * kPrime1;
    ++p;
  }
  return avalanche(h);
}

} // namespace format
} // namespace dng
