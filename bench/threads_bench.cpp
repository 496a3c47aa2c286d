// Threads: one step of the city's 100,000 raindrops (city_scene.h) through one shared BodyIndex, by
// 1 thread on the whole span and by 2 threads on its two halves, in one run. Each iteration starts the
// threads and joins them (std::thread), as the simplest job system would. Goal: 2 threads at least
// 1.8x the speed of 1 (the machine's cores may be shared: read the ratio with that in mind).
#include "city_scene.h"
#include "dng/body_index.h"
#include "dng/forces.h"

#include <benchmark/benchmark.h>

#include <ctime>
#include <thread>
#include <vector>

namespace {

using namespace dng;
using bench::city;
using bench::kCityDt;

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Gravity and one step for particles [begin, end): a job. Adds the CPU time its thread spent in it to
// *io_cpu, so that a slow iteration tells time on the CPU (contention, the work itself) from time
// spent descheduled by other load.
void stepRange(bench::Raindrops* rain, std::size_t begin, std::size_t end, const BodyIndex& index, double* io_cpu) {
  const double start = threadCpuSeconds();
  const bench::City& c = city();
  const ParticleSpan span = rain->span(begin, end);
  applyGravity(span, {0.0f, 0.0f, -9.81f}, kCityDt);
  stepParticles(span, kCityDt, c.buildings.data(), c.buildings.size(), index);
  *io_cpu += threadCpuSeconds() - start;
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
  std::vector<double> cpu(threads, 0.0); // per thread, summed over the iterations
  for (auto _ : state) {
    state.PauseTiming();
    rain = c.rain;
    state.ResumeTiming();
    for (std::size_t t = 0; t < threads; ++t)
      jobs.emplace_back(stepRange, &rain, count * t / threads, count * (t + 1) / threads, std::cref(index), &cpu[t]);
    for (std::thread& job : jobs)
      job.join();
    jobs.clear();
    benchmark::DoNotOptimize(rain.px.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
  // The busiest thread's CPU time per iteration: the wall time the step would take if no other load
  // ever took its core. Its ratio between the rows is the speed-up the library allows.
  double busiest = 0.0;
  for (double seconds : cpu)
    busiest = seconds > busiest ? seconds : busiest;
  state.counters["cpu_ms_busiest_thread"] = 1e3 * busiest / double(state.iterations());
  state.counters["per_particle"] =
      benchmark::Counter(double(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Threads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

BENCHMARK_MAIN();
