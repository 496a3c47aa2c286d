// The paper's Table 1 (Ilmonen, Takala & Laitinen: cost per particle of collision against a 12,000-
// triangle object, all particles close to it), redone against today's peers on real meshes:
// no collision; dngrid dense and bricked (impact, impact+drag+flow, swept); Embree ray casting of
// each step's segment (rtcIntersect1 and 4/8/16-ray packets); a NanoVDB level set of the same mesh.
// Every method runs the same loop (respawn, gravity, its step; table1_methods.h) on one thread, and
// also reports its crossings of the mesh (judged untimed on the triangles) and the memory it holds.
// Then the same on more meshes, to show what the cost does as the triangle count grows.
//
//   table1_bench [benchmark flags] --table=MESH [--particles=N,...] [--sweep=MESH,...]
//                [--sweep_particles=N] [--judge=PARTICLE_STEPS]
//
// bench/run.sh runs it and bench/report.py turns the JSON into docs/PERFORMANCE.md's Table 1.
#include "bench_main.h"
#include "table1_methods.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace {

using namespace dng;
using namespace dng::table1;

struct Options {
  std::string table;                                   ///< the table's mesh (fandisk)
  std::vector<std::size_t> particles{100000, 1000000}; ///< the table's swarm sizes
  std::vector<std::string> sweep;                      ///< more meshes, fewer methods
  std::size_t sweep_particles = 100000;
  std::uint64_t judge = 2000000; ///< particle-steps judged per case (at least one step)
};

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

bool parse(int argc, char** argv, Options* o) {
  for (int n = 1; n < argc; ++n) {
    const std::string arg = argv[n];
    const auto value = [&](const char* flag) {
      const std::string prefix = std::string(flag) + "=";
      return arg.rfind(prefix, 0) == 0 ? arg.substr(prefix.size()) : std::string();
    };
    if (!value("--table").empty()) {
      o->table = value("--table");
    } else if (!value("--particles").empty()) {
      o->particles.clear();
      for (const std::string& s : split(value("--particles")))
        o->particles.push_back(std::stoul(s));
    } else if (!value("--sweep").empty()) {
      o->sweep = split(value("--sweep"));
    } else if (!value("--sweep_particles").empty()) {
      o->sweep_particles = std::stoul(value("--sweep_particles"));
    } else if (!value("--judge").empty()) {
      o->judge = std::stoull(value("--judge"));
    } else {
      std::fprintf(stderr, "table1_bench: unknown argument %s\n", arg.c_str());
      return false;
    }
  }
  return !o->table.empty() && !o->particles.empty();
}

// The bricked impact+drag+flow step from spawn points the field proves outside: a point just outside a
// detail the field cannot resolve is blocked where it spawns, and its walk runs every step it lives.
Case provenSpawns() {
  Case c{Method::kImpactDragFlow};
  c.proven = true;
  return c;
}

// The table: every method on the table's mesh.
std::vector<Case> tableCases() {
  std::vector<Case> cases{{Method::kPlain}, {Method::kNoBody}};
  for (const bool dense : {true, false})
    for (const Method m : {Method::kImpact, Method::kImpactDragFlow, Method::kImpactDragFlowSwept})
      cases.push_back({m, dense});
  // The same step through an exact-mode bake: the planes are the same as the default's, but it has no
  // shading normals to gather and more plane tiles (docs/BAKING.md, "Which mode").
  cases.push_back({Method::kImpactDragFlow, false, true});
  // Where the best kernels are AVX-512, the same step with the AVX2 ones: what a CPU without AVX-512 runs.
  if (bestInstructionSet() == InstructionSet::kAvx512) cases.push_back({Method::kImpactDragFlow, false, false, true});
  cases.push_back(provenSpawns());
  for (const Method m : {Method::kEmbree1, Method::kEmbree4, Method::kEmbree8, Method::kEmbree16,
                         Method::kLevelSetNearest, Method::kLevelSetTrilinear})
    cases.push_back({m});
  // And Embree on a device limited to AVX2, the peer of the AVX2 lanes on such a CPU.
  if (bestInstructionSet() == InstructionSet::kAvx512)
    for (const Method m : {Method::kEmbree1, Method::kEmbree4, Method::kEmbree8, Method::kEmbree16}) {
      Case c{m};
      c.avx2 = true;
      cases.push_back(c);
    }
  return cases;
}

// The sweep: the baseline, the bricked field (and the same step through an exact-mode bake, and from
// proven spawn points) and every peer on each further mesh.
std::vector<Case> sweepCases() {
  return {{Method::kPlain},
          {Method::kImpact},
          {Method::kImpactDragFlow},
          {Method::kImpactDragFlow, false, true},
          provenSpawns(),
          {Method::kEmbree1},
          {Method::kEmbree4},
          {Method::kEmbree8},
          {Method::kEmbree16},
          {Method::kLevelSetNearest},
          {Method::kLevelSetTrilinear}};
}

// Each case's simulation after its warm-up, and its judgement: made once per benchmark, as Google
// Benchmark calls the function once per repetition (and the 1M-particle warm-up takes seconds).
struct Prepared {
  Simulation warm;
  Judgement judgement;
};

const Prepared* prepared(const std::string& name, const MeshScene& scene, const Case& c, std::size_t particles,
                         std::uint64_t budget) {
  static std::map<std::string, Prepared> done;
  auto it = done.find(name);
  if (it == done.end()) {
    Simulation sim(scene, c, particles);
    if (!sim.stepper) return nullptr;
    sim.warmUp();
    const Judgement judgement = judgeCase(scene, sim, budget);
    it = done.emplace(name, Prepared{std::move(sim), judgement}).first;
  }
  return &it->second;
}

void runCase(benchmark::State& state, const std::string& name, const std::string& path, Case c, std::size_t particles,
             std::uint64_t budget) {
  std::string error;
  const MeshScene* scene = meshScene(path, {c.dense, c.exact, c.usesEmbree() && c.avx2}, &error);
  if (scene == nullptr) {
    state.SkipWithError(error.c_str());
    return;
  }
  const Prepared* ready = prepared(name, *scene, c, particles, budget);
  if (ready == nullptr) {
    state.SkipWithError("cannot make the method's stepper");
    return;
  }
  Simulation sim = ready->warm;
  for (auto _ : state) {
    sim.step();
    benchmark::DoNotOptimize(sim.swarm.px.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(caseLabel(c));
  // Per particle-step, from the benchmark thread's CPU time: the machine is shared, and time spent
  // descheduled is not the method's.
  state.counters["per_particle"] = benchmark::Counter(double(particles), benchmark::Counter::kIsIterationInvariantRate |
                                                                             benchmark::Counter::kInvert);
  state.counters["crossings"] = double(ready->judgement.crossings);
  state.counters["judged"] = double(ready->judgement.segments);
  state.counters["bytes"] = double(caseBytes(*scene, c));
  state.counters["triangles"] = double(scene->triangles.size());
}

void registerCases(const std::string& path, const std::vector<Case>& cases, std::size_t particles,
                   std::uint64_t budget) {
  const std::string stem = path.substr(path.find_last_of('/') + 1);
  const std::string mesh = stem.substr(0, stem.find_last_of('.'));
  for (const Case& c : cases) {
    const std::string name = "table1/" + mesh + "/" + std::to_string(particles) + "/" + caseId(c);
    // Beside the median, each row's fastest repetition: on a shared machine the other tenants' load
    // weighs on the methods unequally (the AVX-512 kernels more than Embree's traversal), and the fastest
    // repetition is the closest to the method alone.
    benchmark::RegisterBenchmark(name.c_str(),
                                 [=](benchmark::State& state) { runCase(state, name, path, c, particles, budget); })
        ->Unit(benchmark::kMillisecond)
        ->ComputeStatistics("min", [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); });
  }
}

} // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
#if defined(__x86_64__)
  // Denormals flushed to zero, as Embree's documentation asks of its callers for speed; every method
  // runs on this thread under the same mode.
  _mm_setcsr(_mm_getcsr() | 0x8040); // FTZ (bit 15) and DAZ (bit 6)
#endif
  Options options;
  if (!parse(argc, argv, &options)) {
    std::fprintf(stderr, "usage: table1_bench [benchmark flags] --table=MESH [--particles=N,...] [--sweep=MESH,...] "
                         "[--sweep_particles=N] [--judge=PARTICLE_STEPS]\n");
    return 1;
  }
  for (const std::size_t n : options.particles)
    registerCases(options.table, tableCases(), n, options.judge);
  for (const std::string& mesh : options.sweep)
    registerCases(mesh, sweepCases(), options.sweep_particles, options.judge);
  dng::bench::addInstructionSetContext();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return dng::bench::finishReport("table1_bench");
}
