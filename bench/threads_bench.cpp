// Threads: the city's 100,000 raindrops (city_scene.h) stepped through one shared BodyIndex, by 1
// thread on the whole span and by 2 threads on its two halves, in one run. The threads are a minimal
// job system's workers: started once, spinning between frames, the calling thread taking the first
// half itself (docs/INTEGRATION.md, "Threads"). Goal: 2 threads at least 1.8x the speed of 1 (the
// machine's cores may be shared: read the ratio with that in mind).
#include "bench_main.h"
#include "city_scene.h"
#include "dng/body_index.h"
#include "dng/forces.h"

#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdint>
#include <ctime>
#include <functional>
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

// A job system's workers as engines keep them: started once, spinning between frames (a worker
// put to sleep takes a scheduler wake-up, hundreds of microseconds on a virtual machine's idle core,
// to start its job), and the calling thread takes job 0 itself. run() returns when every job of the
// frame is done.
class Workers {
public:
  explicit Workers(std::size_t jobs) : jobs_(jobs) {
    for (std::size_t j = 1; j < jobs; ++j)
      threads_.emplace_back([this, j] { serve(j); });
  }
  ~Workers() {
    stop_.store(true, std::memory_order_release);
    for (std::thread& t : threads_)
      t.join();
  }
  void run(const std::function<void(std::size_t)>& job) {
    job_ = &job;
    pending_.store(jobs_ - 1, std::memory_order_relaxed);
    frame_.fetch_add(1, std::memory_order_release); // publishes job_ and pending_
    job(0);
    while (pending_.load(std::memory_order_acquire) != 0)
      std::this_thread::yield();
  }

private:
  void serve(std::size_t j) {
    std::uint64_t seen = 0;
    for (;;) {
      std::uint64_t frame = frame_.load(std::memory_order_acquire);
      while (frame == seen) {
        if (stop_.load(std::memory_order_acquire)) return;
        std::this_thread::yield();
        frame = frame_.load(std::memory_order_acquire);
      }
      seen = frame;
      (*job_)(j);
      pending_.fetch_sub(1, std::memory_order_release);
    }
  }
  std::size_t jobs_;
  std::vector<std::thread> threads_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::atomic<std::size_t> pending_{0};
  std::atomic<std::uint64_t> frame_{0};
  std::atomic<bool> stop_{false};
};

// Consecutive frames per iteration, each range stepped by the same worker every frame, as in a game:
// only the first frame after the untimed reset finds the raindrops in the resetting thread's cache.
constexpr int kFrames = 8;

// Argument: threads, each on an equal, disjoint range of the raindrops.
void BM_Threads(benchmark::State& state) {
  const bench::City& c = city();
  const std::size_t threads = std::size_t(state.range(0));
  BodyIndex index; // the bodies stay put: built once, shared read-only by every thread
  index.rebuild(c.buildings.data(), c.buildings.size(), kCityDt);
  bench::Raindrops rain = c.rain;
  const std::size_t count = rain.px.size();
  std::vector<double> cpu(threads, 0.0);
  Workers workers(threads);
  const std::function<void(std::size_t)> job = [&](std::size_t t) {
    stepRange(&rain, count * t / threads, count * (t + 1) / threads, index, &cpu[t]);
  };
  for (auto _ : state) {
    state.PauseTiming();
    rain = c.rain;
    state.ResumeTiming();
    for (int f = 0; f < kFrames; ++f)
      workers.run(job);
    benchmark::DoNotOptimize(rain.px.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
  // The busiest thread's CPU time per frame: the wall time the step would take if no other load ever
  // took its core. Its ratio between the rows is the speed-up the library allows.
  double busiest = 0.0;
  for (double seconds : cpu)
    busiest = seconds > busiest ? seconds : busiest;
  state.counters["cpu_ms_busiest_thread"] = 1e3 * busiest / double(state.iterations() * kFrames);
  state.counters["per_particle"] = benchmark::Counter(
      double(count * kFrames), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Threads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "threads_bench"); }
