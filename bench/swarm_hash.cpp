// swarm_hash: steps a fixed swarm near the surface of a baked field and prints a hash of every step's
// result and the stepping thread's CPU time per particle-step.
//
// A tool for work on the step, not a benchmark with a goal: a change that must not change results
// (a faster kernel, a refactor) gives the same hash before and after, on any real mesh, and the time
// is a quick A/B between two builds run in turn. Its fixed load is also a steady target for profilers
// (perf, callgrind) without the bake that table1_bench does first.
//
//   swarm_hash FIELD.dng [--particles N] [--steps N] [--lifetime N] [--near V] [--speed V] [--swept]
//              [--structs] [--isa scalar|sse4.1|avx2|avx512|neon]
//
// The swarm: points drawn uniformly in the field's box, kept where the field reads 0 (or --near V
// voxels) to 2 voxels outside, with random velocities up to 1.5 (or --speed V) voxels per step on each
// axis, gravity of 0.02 voxel per step squared, impact (beta 0.5) with drag and flow as in
// table1_bench. With --lifetime N every particle goes back to its spawn state after N steps (a 1/N
// slice each step, as table1_bench respawns), so the swarm stays near the surface; without it the
// swarm spreads out and most late steps are far from it. `--lifetime 8 --near 0.1 --speed 0.6` is
// close to Table 1's load (spawned 0.1 to 2 voxels out, 8 steps each, about half a voxel per step).
// With --structs the step reads and writes the particles as an array of structs (position, velocity and
// two floats of padding: strided spans of 32 bytes), as many engines keep them; the hash must not change.
// A point spawned where the field reads below a hundredth of a voxel is one the field cannot prove
// outside, and stays where it is (docs/RUNTIME.md, "Limits"). Exit codes: 0 done, 1 bad arguments or
// unreadable field, 2 a step failed, 3 this machine lacks the --isa set.
#include "dng/body.h"
#include "dng/file.h"
#include "dng/instruction_set.h"
#include "dng/particles.h"
#include "standard_output.h"
#include "swarm.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace dng;

constexpr float kDt = 1.0f / 60.0f;

struct Options {
  const char* field = nullptr;
  std::size_t particles = 200000;
  int steps = 40;
  int lifetime = 0;   ///< 0: never respawn
  float near = 0.0f;  ///< spawn where the field reads at least this many voxels
  float speed = 1.5f; ///< voxels per step, the most on each axis
  bool swept = false;
  bool structs = false; ///< step an array of structs (strided spans) instead of arrays
  InstructionSet isa = bestInstructionSet();
};

bool parseIsa(const char* name, InstructionSet* out) {
  for (InstructionSet set : kInstructionSets) {
    if (std::strcmp(name, instructionSetName(set)) == 0) {
      *out = set;
      return true;
    }
  }
  return false;
}

bool parse(int argc, char** argv, Options* out) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--particles" && has_value) {
      out->particles = std::strtoul(argv[++i], nullptr, 10);
    } else if (arg == "--steps" && has_value) {
      out->steps = std::atoi(argv[++i]);
    } else if (arg == "--lifetime" && has_value) {
      out->lifetime = std::atoi(argv[++i]);
    } else if (arg == "--near" && has_value) {
      out->near = std::strtof(argv[++i], nullptr);
    } else if (arg == "--speed" && has_value) {
      out->speed = std::strtof(argv[++i], nullptr);
    } else if (arg == "--swept") {
      out->swept = true;
    } else if (arg == "--structs") {
      out->structs = true;
    } else if (arg == "--isa" && has_value) {
      if (!parseIsa(argv[++i], &out->isa)) return false;
    } else if (out->field == nullptr && arg[0] != '-') {
      out->field = argv[i];
    } else {
      return false;
    }
  }
  return out->field != nullptr && out->particles > 0 && out->steps > 0 && out->lifetime >= 0 && out->near >= 0.0f &&
         out->near < 2.0f && out->speed >= 0.0f;
}

struct Swarm {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::int32_t> body;
  ParticleSpan span() {
    ParticleSpan s;
    s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
    s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
    s.count = px.size();
    s.out_body = body.data();
    return s;
  }
};

// The swarm as an engine's array of particle structs: the same numbers, 32 bytes per particle.
struct ParticleStruct {
  float position[3], velocity[3], padding[2];
};
std::vector<ParticleStruct> toStructs(const Swarm& s) {
  std::vector<ParticleStruct> out(s.px.size());
  for (std::size_t n = 0; n < out.size(); ++n)
    out[n] = {{s.px[n], s.py[n], s.pz[n]}, {s.vx[n], s.vy[n], s.vz[n]}, {0.0f, 0.0f}};
  return out;
}
void fromStructs(const std::vector<ParticleStruct>& in, Swarm* io) {
  for (std::size_t n = 0; n < in.size(); ++n) {
    io->px[n] = in[n].position[0], io->py[n] = in[n].position[1], io->pz[n] = in[n].position[2];
    io->vx[n] = in[n].velocity[0], io->vy[n] = in[n].velocity[1], io->vz[n] = in[n].velocity[2];
  }
}
ParticleSpan structSpan(std::vector<ParticleStruct>* particles, std::int32_t* body) {
  ParticleSpan s = testing::structSpan(particles);
  s.out_body = body;
  return s;
}

Swarm spawn(const View& view, std::size_t count, float near, float voxels_per_step) {
  const GridInfo& g = view.grid();
  const float h = g.voxel_size, speed = voxels_per_step * h / kDt;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.0f, 1.0f);
  Swarm s;
  while (s.px.size() < count) {
    const Vec3f p{g.origin.x + unit(rng) * float(g.dims[0]) * h, g.origin.y + unit(rng) * float(g.dims[1]) * h,
                  g.origin.z + unit(rng) * float(g.dims[2]) * h};
    const Sample at = view.sample(p);
    if (at.status != SampleStatus::kInBand || at.distance < near * h || at.distance > 2.0f * h) continue;
    s.px.push_back(p.x), s.py.push_back(p.y), s.pz.push_back(p.z);
    s.vx.push_back(signed_unit(rng) * speed), s.vy.push_back(signed_unit(rng) * speed);
    s.vz.push_back(signed_unit(rng) * speed);
  }
  s.body.assign(count, -1);
  return s;
}

// The slice of particles whose lifetime ends before this step starts again from its spawn state.
void respawn(const Swarm& born, int step, std::size_t lifetime, Swarm* io) {
  for (std::size_t n = std::size_t(step) % lifetime; n < born.px.size(); n += lifetime) {
    io->px[n] = born.px[n], io->py[n] = born.py[n], io->pz[n] = born.pz[n];
    io->vx[n] = born.vx[n], io->vy[n] = born.vy[n], io->vz[n] = born.vz[n];
  }
}

Material materialFor(float h, bool swept) {
  Material m;
  m.restitution = 0.5f;
  m.collision_distance = 0.1f * h;
  m.drag = 2.0f, m.contact_distance = h;
  m.flow_in = 12.0f * h, m.flow_out = 3.0f * h, m.flow_distance = 2.0f * h;
  m.swept = swept;
  return m;
}

// FNV-1a over raw bytes: any changed bit changes the hash.
struct Hash {
  std::uint64_t value = 1469598103934665603ull;
  template <typename T> void add(const std::vector<T>& v) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(T); ++i)
      value = (value ^ bytes[i]) * 1099511628211ull;
  }
};

double threadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

} // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, &options)) {
    std::fprintf(
        stderr,
        "usage: swarm_hash FIELD.dng [--particles N] [--steps N] [--lifetime N] [--near V] [--speed V] [--swept] "
        "[--structs] [--isa scalar|sse4.1|avx2|avx512|neon]\n");
    return 1;
  }
  Diagnostic diag;
  if (setInstructionSet(options.isa, &diag) != Status::kOk) { // this machine lacks the set
    std::fprintf(stderr, "swarm_hash: %s\n", diag.message);
    return 3;
  }
  File file;
  if (File::open(options.field, &file, &diag) != Status::kOk) {
    std::fprintf(stderr, "swarm_hash: %s\n", diag.message);
    return 1;
  }
  const View& view = file.view();
  const float h = view.grid().voxel_size;
  Body body;
  if (Body::create(&view, materialFor(h, options.swept), &body, &diag) != Status::kOk) {
    std::fprintf(stderr, "swarm_hash: %s\n", diag.message);
    return 1;
  }
  const Swarm born = spawn(view, options.particles, options.near, options.speed);
  Swarm swarm = born;
  Hash hash;
  double seconds = 0.0;
  for (int step = 0; step < options.steps; ++step) {
    if (options.lifetime > 0) respawn(born, step, std::size_t(options.lifetime), &swarm);
    for (float& v : swarm.vz)
      v -= 0.02f * h / kDt;
    std::vector<ParticleStruct> structs;
    if (options.structs) structs = toStructs(swarm);
    const ParticleSpan span = options.structs ? structSpan(&structs, swarm.body.data()) : swarm.span();
    const double start = threadSeconds();
    if (stepParticles(span, kDt, &body, 1, &diag) != Status::kOk) {
      std::fprintf(stderr, "swarm_hash: step %d: %s\n", step, diag.message);
      return 2;
    }
    seconds += threadSeconds() - start;
    if (options.structs) fromStructs(structs, &swarm);
    for (const auto* v : {&swarm.px, &swarm.py, &swarm.pz, &swarm.vx, &swarm.vy, &swarm.vz})
      hash.add(*v);
    hash.add(swarm.body);
  }
  std::printf("%016llx %.1f ns per particle-step (%s)\n", static_cast<unsigned long long>(hash.value),
              1e9 * seconds / (double(options.steps) * double(options.particles)),
              instructionSetName(activeInstructionSet()));
  return dng::tools::finishStandardOutput("swarm_hash", 0);
}
