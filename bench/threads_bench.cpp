// Threads: one step of the city's 100,000 raindrops (city_scene.h) through one shared BodyIndex, by
// 1 thread on the whole span and by 2 threads on its two halves, in one run. Each iteration starts the
// threads and joins them (std::thread), as the simplest job system would. Goal: 2 threads at least
// 1.8x the speed of 1 (the machine's cores may be shared: read the ratio with that in mind).
#include "city_scene.h"
#include "dng/body_index.h"
#include "dng/forces.h"

#include <benchmark/benchmark.h>

#include <thread>
#include <vector>

namespace {

using namespace dng;
using bench::city;
using bench::kCityDt;

// Gravity and one step for particles [begin, end): a job.
void stepRange(bench::Raindrops* rain, std::size_t begin, std::size_t end, const BodyIndex& index) {
  const bench::City& c = city();
  const ParticleSpan span = rain->span(begin, end);
  applyGravity(span, {0.0f, 0.0f, -9.81f}, kCityDt);
  stepParticles(span, kCityDt, c.buildings.data(), c.buildings.size(), index);
}

// Argument: threads, each on an equal, disjoint range of the raindrops.
void BM_Threads(benchmark::State& state) {
  const bench::City& c = city();
  const std::size_t threads = std::size_t(state.range(0));
  BodyIndex index; // the bodies stay put: built once, shared read-only by every thread
  index.rebuild(c.buildings.data(), c.buildings.size(), kCityDt);
  bench::Raindrops rain = c.rain;
  const std::size_t count = rain.px.size();
  std::vector<std::thread> jobs;
  for (auto _ : state) {
    state.PauseTiming();
    rain = c.rain;
    state.ResumeTiming();
    for (std::size_t t = 0; t < threads; ++t)
      jobs.emplace_back(stepRange, &rain, count * t / threads, count * (t + 1) / threads, std::cref(index));
    for (std::thread& job : jobs)
      job.join();
    jobs.clear();
    benchmark::DoNotOptimize(rain.px.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
  state.counters["per_particle"] =
      benchmark::Counter(double(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Threads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
