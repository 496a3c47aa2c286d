// Per-particle step cost with many bodies (paper Fig. 8): 100,000 raindrops in a city of 1,000
// buildings on a ground (city_scene.h), stepped through the broadphase (dng/body_index.h), against 1
// body in the same run. Goal: 1,000 bodies at most 2x the per-particle cost of 1 body. Two baselines:
//   - the 1,000 buildings without the ground against building 0 alone, each drop folded into building
//     0's frame (city_scene.h): the same field work per drop, so the ratio is what many bodies cost;
//   - the same raindrops against the ground alone: the city also has the buildings' field work (about
//     a quarter of the drops are inside a building's box and sample it).
// Both in random order and (the folded pair) in lattice order. The city without the broadphase shows
// what it saves.
#include "bench_main.h"
#include "city_scene.h"
#include "dng/body_index.h"
#include "dng/forces.h"

#include <benchmark/benchmark.h>

namespace {

using namespace dng;
using bench::city;
using bench::kCityDt;

void setPerParticle(benchmark::State& state, std::size_t particles) {
  state.counters["per_particle"] = benchmark::Counter(double(particles), benchmark::Counter::kIsIterationInvariantRate |
                                                                             benchmark::Counter::kInvert);
}

struct Mode {
  const char* label;
  std::size_t first, count; // bodies [first, first + count) of City::buildings (0 is the ground)
  bool folded;              // the raindrops folded onto building 0
  bool index;               // through a BodyIndex rebuilt every step (timed: engines pay it every frame)
  bool sorted;              // the raindrops in lattice order instead of random order
};
const Mode kModes[] = {
    {"ground alone (1 body)", 0, 1, false, false, false},
    {"city: 1,000 buildings + ground, broadphase", 0, 1001, false, true, false},
    {"city: 1,000 buildings + ground, every body per particle", 0, 1001, false, false, false},
    {"building 0 alone (1 body), folded drops", 1, 1, true, false, false},
    {"1,000 buildings, broadphase", 1, 1000, false, true, false},
    {"building 0 alone (1 body), folded drops, lattice order", 1, 1, true, false, true},
    {"1,000 buildings, broadphase, lattice order", 1, 1000, false, true, true},
};

// Argument: a row of kModes.
void BM_Rain(benchmark::State& state) {
  const bench::City& c = city();
  const Mode& mode = kModes[state.range(0)];
  const Body* bodies = c.buildings.data() + mode.first;
  const bench::Raindrops& start =
      mode.folded ? (mode.sorted ? c.folded_sorted : c.folded) : (mode.sorted ? c.rain_sorted : c.rain);
  bench::Raindrops rain = start;
  BodyIndex index;
  for (auto _ : state) {
    state.PauseTiming(); // every iteration steps the same raindrops from the same state
    rain = start;
    state.ResumeTiming();
    applyGravity(rain.span(), {0.0f, 0.0f, -9.81f}, kCityDt);
    if (mode.index) {
      index.rebuild(bodies, mode.count, kCityDt);
      stepParticles(rain.span(), kCityDt, bodies, mode.count, index);
    } else {
      stepParticles(rain.span(), kCityDt, bodies, mode.count);
    }
    benchmark::DoNotOptimize(rain.px.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(mode.label);
  setPerParticle(state, rain.px.size());
}
BENCHMARK(BM_Rain)->DenseRange(0, 6)->Unit(benchmark::kMillisecond)->UseRealTime();

// The per-frame rebuild alone, per body. Argument N: one body in N changes its velocity before each
// call, alternating between two values, as moving bodies would (1: all of them, so every call builds
// everything; 10: a tenth, whose numbers alone the rebuild computes again); 0: none, as a city at rest
// frame after frame, which the rebuild only compares.
void BM_Rebuild(benchmark::State& state) {
  std::vector<Body> bodies = city().buildings;
  const auto every = std::size_t(state.range(0));
  BodyIndex index;
  index.rebuild(bodies.data(), bodies.size(), kCityDt);
  bool odd = false;
  for (auto _ : state) {
    odd = !odd;
    for (std::size_t b = 0; every != 0 && b < bodies.size(); b += every)
      bodies[b].setVelocity({odd ? 0.5f : 0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
    index.rebuild(bodies.data(), bodies.size(), kCityDt);
    benchmark::ClobberMemory();
  }
  std::uint32_t dims[3];
  index.cellDims(dims);
  state.SetLabel(std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + " cells");
  state.counters["per_body"] = benchmark::Counter(double(bodies.size()), benchmark::Counter::kIsIterationInvariantRate |
                                                                             benchmark::Counter::kInvert);
}
BENCHMARK(BM_Rebuild)->Arg(1)->Arg(10)->Arg(0)->Unit(benchmark::kMicrosecond)->UseRealTime();

// What each stepParticles call with an index costs besides its particles: the arguments' checks and
// the index's, O(bodies). Jobs of fewer particles pay it more often (docs/INTEGRATION.md, "Threads").
void BM_CallOverhead(benchmark::State& state) {
  const bench::City& c = city();
  BodyIndex index;
  index.rebuild(c.buildings.data(), c.buildings.size(), kCityDt);
  bench::Raindrops one = c.rain;
  for (auto _ : state) {
    stepParticles(one.span(0, 1), kCityDt, c.buildings.data(), c.buildings.size(), index);
    benchmark::ClobberMemory();
  }
  state.SetLabel("1 particle, 1,001 bodies");
}
BENCHMARK(BM_CallOverhead)->Unit(benchmark::kMicrosecond)->UseRealTime();

} // namespace

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "many_bodies_bench"); }
