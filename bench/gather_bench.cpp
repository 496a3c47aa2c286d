// What a gather costs with some of its lanes masked off: the question behind regathering a register's
// few late lanes into full registers (the step's cell walks, docs/RUNTIME.md "Tried ... and not kept").
// Each iteration is two dependent gathers of 32-bit words from a 2 MB table at random places (a
// sample's brick-top entry, then its pool word), with 16, 8, 4 or 1 lanes on (AVX-512) or 8, 4, 2 or 1
// (AVX2). Compare the rows of one run: the cost with one lane on against every lane.
//
// x86-64 only; a set this CPU lacks is reported as skipped.
#include "bench_main.h"

#include <cstdint>
#include <random>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>

namespace {

constexpr std::uint32_t kTableWords = 1u << 19; // 2 MB
constexpr std::size_t kIndices = 1u << 16;

struct Data {
  std::vector<std::int32_t> table, indices;
  Data() : table(kTableWords), indices(kIndices) {
    std::mt19937 random(7);
    for (std::int32_t& word : table)
      word = std::int32_t(random() & (kTableWords - 1));
    for (std::int32_t& index : indices)
      index = std::int32_t(random() & (kTableWords - 1));
  }
};

const Data& data() {
  static const Data d;
  return d;
}

__attribute__((target("avx512f"))) std::int32_t gatherPairs512(const Data& d, std::uint32_t mask) {
  const __m512i wrap = _mm512_set1_epi32(std::int32_t(kTableWords - 1)), zero = _mm512_setzero_si512();
  __m512i sum = zero;
  for (std::size_t i = 0; i < kIndices; i += 16) {
    const __m512i at = _mm512_loadu_si512(d.indices.data() + i);
    const __m512i first = _mm512_mask_i32gather_epi32(zero, __mmask16(mask), at, d.table.data(), 4);
    const __m512i second =
        _mm512_mask_i32gather_epi32(zero, __mmask16(mask), _mm512_and_si512(first, wrap), d.table.data(), 4);
    sum = _mm512_add_epi32(sum, second);
  }
  alignas(64) std::int32_t out[16];
  _mm512_store_si512(out, sum);
  return out[0] + out[15];
}

__attribute__((target("avx2"))) std::int32_t gatherPairs256(const Data& d, std::uint32_t mask) {
  const __m256i wrap = _mm256_set1_epi32(std::int32_t(kTableWords - 1)), zero = _mm256_setzero_si256();
  alignas(32) std::int32_t on[8];
  for (int lane = 0; lane < 8; ++lane)
    on[lane] = (mask >> lane) & 1u ? -1 : 0;
  const __m256i lanes = _mm256_load_si256(reinterpret_cast<const __m256i*>(on));
  __m256i sum = zero;
  for (std::size_t i = 0; i < kIndices; i += 8) {
    const __m256i at = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(d.indices.data() + i));
    const __m256i first = _mm256_mask_i32gather_epi32(zero, d.table.data(), at, lanes, 4);
    const __m256i second = _mm256_mask_i32gather_epi32(zero, d.table.data(), _mm256_and_si256(first, wrap), lanes, 4);
    sum = _mm256_add_epi32(sum, second);
  }
  alignas(32) std::int32_t out[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(out), sum);
  return out[0] + out[7];
}

// range(0): the lanes on (the lowest ones) of a register of kLanes; `supported`: this CPU has the set,
// else the row is skipped with `missing` as its reason. The table is made before the timed loop.
template <std::int32_t (*kPairs)(const Data&, std::uint32_t), int kLanes>
void gatherPairs(benchmark::State& state, bool supported, const char* missing) {
  if (!supported) return state.SkipWithError(missing);
  const Data& d = data();
  const std::uint32_t mask = (1u << state.range(0)) - 1u;
  for (auto _ : state)
    benchmark::DoNotOptimize(kPairs(d, mask));
  state.counters["ns_per_pair"] = benchmark::Counter(double(kIndices / kLanes) * double(state.iterations()),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_GatherPair512(benchmark::State& state) {
  gatherPairs<gatherPairs512, 16>(state, __builtin_cpu_supports("avx512f"), "this CPU has no AVX-512F");
}
BENCHMARK(BM_GatherPair512)->Arg(16)->Arg(8)->Arg(4)->Arg(1);
void BM_GatherPair256(benchmark::State& state) {
  gatherPairs<gatherPairs256, 8>(state, __builtin_cpu_supports("avx2"), "this CPU has no AVX2");
}
BENCHMARK(BM_GatherPair256)->Arg(8)->Arg(4)->Arg(2)->Arg(1);

} // namespace
#endif

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "gather_bench"); }
