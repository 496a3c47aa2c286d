// Per-particle step cost for 1M particles near a sphere: the full step (gravity + stepParticles)
// with a sphere body against the same step with no body, in one run (issue #3's goal: collision
// overhead <= 1.3x the no-collision step; the paper's compressed grid cost 1.44x, Table 1).
#include "bench_main.h"
#include "dng/forces.h"
#include "dng/instruction_set.h"
#include "dng/particles.h"
#include "sphere_scene.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

namespace {

using namespace dng;

constexpr std::size_t kParticles = 1 << 20;
constexpr float kDt = 1.0f / 60.0f;

// Particles within 2 voxels of the sphere, moving in random directions at up to 1 voxel per step.
struct Swarm {
  std::vector<float> px, py, pz, vx, vy, vz;
  ParticleSpan span() {
    ParticleSpan s;
    s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
    s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
    s.count = px.size();
    return s;
  }
};

// The same particles sorted by the voxel they are in (z, then y, then x): what a caller gains by
// keeping particles in spatial order.
Swarm sortedSwarm(const Swarm& in) {
  std::vector<std::size_t> order(in.px.size());
  for (std::size_t n = 0; n < order.size(); ++n)
    order[n] = n;
  auto cell = [&](std::size_t n) {
    return std::make_tuple(int(std::floor(in.pz[n])), int(std::floor(in.py[n])), int(std::floor(in.px[n])));
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return cell(a) < cell(b); });
  Swarm out;
  for (std::size_t n : order) {
    out.px.push_back(in.px[n]), out.py.push_back(in.py[n]), out.pz.push_back(in.pz[n]);
    out.vx.push_back(in.vx[n]), out.vy.push_back(in.vy[n]), out.vz.push_back(in.vz[n]);
  }
  return out;
}

const Swarm& pristineSwarm() {
  static const Swarm* swarm = [] {
    auto* s = new Swarm;
    std::mt19937 rng(17);
    std::normal_distribution<float> gauss;
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    while (s->px.size() < kParticles) {
      const Vec3f dir = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)});
      const Vec3f p = Vec3f{0.3f, 0.2f, 0.1f} + dir * (bench::kRadius + 0.1f + 1.9f * unit(rng));
      const Vec3f v = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)}) * (unit(rng) / kDt);
      s->px.push_back(p.x), s->py.push_back(p.y), s->pz.push_back(p.z);
      s->vx.push_back(v.x), s->vy.push_back(v.y), s->vz.push_back(v.z);
    }
    return s;
  }();
  return *swarm;
}

Material materialFor(int responses) {
  Material m;
  m.restitution = 0.5f;
  m.collision_distance = 0.1f;
  if (responses >= 2) {
    m.drag = 2.0f, m.contact_distance = 1.0f;
    m.flow_in = 12.0f, m.flow_out = 3.0f, m.flow_distance = 2.0f;
  }
  m.swept = responses == 3;
  return m;
}

// Arguments: encoding (0 dense, 1 bricked, 2 no body), responses (1 impact, 2 impact+drag+flow, 3 the same,
// swept), order (0 as emitted: random, 1 sorted by voxel).
void stepBench(benchmark::State& state, InstructionSet set) {
  if (setInstructionSet(set) != Status::kOk) {
    state.SkipWithError("instruction set not available");
    return;
  }
  const auto& scene = bench::sphereScene();
  static const Swarm sorted = sortedSwarm(pristineSwarm());
  const Swarm& start = state.range(2) == 1 ? sorted : pristineSwarm();
  Swarm swarm = start;
  Body body;
  const bool with_body = state.range(0) != 2;
  if (with_body)
    Body::create(state.range(0) == 0 ? &scene.dense : &scene.bricked, materialFor(int(state.range(1))), &body);
  for (auto _ : state) {
    state.PauseTiming(); // every iteration steps the same particles from the same state
    swarm = start;
    state.ResumeTiming();
    applyGravity(swarm.span(), {0.0f, 0.0f, -9.81f}, kDt);
    stepParticles(swarm.span(), kDt, with_body ? &body : nullptr, with_body ? 1 : 0);
    benchmark::DoNotOptimize(swarm.px.data());
    benchmark::ClobberMemory();
  }
  static const char* const kResponses[] = {"", "impact", "impact+drag+flow", "impact+drag+flow swept"};
  state.SetLabel((with_body ? std::string(state.range(0) ? "bricked " : "dense ") + kResponses[state.range(1)]
                            : std::string("no collision")) +
                 (state.range(2) ? ", sorted" : ", random"));
  state.counters["per_particle"] = benchmark::Counter(
      double(kParticles), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  setInstructionSet(bestInstructionSet());
}

// The step as shipped: the best SIMD kernels this CPU has (dng/instruction_set.h).
void BM_Step(benchmark::State& state) { stepBench(state, bestInstructionSet()); }
// The same with the scalar reference path, in the same run.
void BM_StepScalar(benchmark::State& state) { stepBench(state, InstructionSet::kScalar); }

BENCHMARK(BM_StepScalar)->ArgsProduct({{0, 1}, {1, 2, 3}, {0}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Step)
    ->Args({2, 0, 0})
    ->Args({2, 0, 1})
    ->ArgsProduct({{0, 1}, {1, 2, 3}, {0}})
    ->Args({1, 2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

} // namespace

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "particle_step_bench"); }
