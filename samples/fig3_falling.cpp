// Fig. 3 of the paper (Ilmonen, Takala & Laitinen): particles falling on a table, in three materials:
//   (a) bouncy     restitution beta = 0.7 (§3.4)
//   (b) slippery   beta = 0
//   (c) high drag  beta = 0, drag delta = 2 /s within theta = 1 voxel of the surface (§3.5)
//
//   dng_fig3_falling [OUTPUT_FOLDER] [--particles N] [--no-pictures]
//
// The table is an analytic box turned into a DN field in memory with the std-only writer, so the sample
// needs no mesh. Per material it writes OUTPUT_FOLDER/fig3X_NAME_side.png and _top.png and prints two
// JSON lines: the run's statistics, and what the figure is about (how high particles bounce after
// their first contact; how many end at rest on the table). Exits 1 if a particle ends inside the box.
// Units: metres and seconds, 60 steps per second.
#include "analytic_field.h"
#include "sample_io.h"
#include "sample_particles.h"

#include "dng/forces.h"
#include "dng/particles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using dng::Vec3f;

constexpr float kDt = 1.0f / 60.0f;
constexpr int kSteps = 180;
const Vec3f kTableCentre{0, 0, -1}, kTableHalf{2, 2, 1}; // top face at z = 0, 4 m square

// Exact signed distance to the table (negative inside) and the outward normal at the nearest point.
float tableDistance(Vec3f p, Vec3f* normal) { return dng::samples::boxDistance(p, kTableCentre, kTableHalf, normal); }

// The table's .dng file, in memory: a 0.1 m grid with a 4-voxel band.
std::vector<std::uint8_t> encodeTable() {
  return dng::samples::encodeAnalytic({-3, -3, -2.6f}, {3, 3, 1.0f}, 0.1f, 4, tableDistance);
}

using dng::samples::Particles;
using dng::samples::uniform;

// One variant of the figure: drops the particles on the table, prints its two JSON lines and returns
// its exit code (dng::samples::exitCode: 1 when a particle ended inside the table).
int run(const char* name, float restitution, float drag, const dng::View& field,
        const dng::samples::CommandLine& command_line, const std::string& folder) {
  dng::Material material;
  material.restitution = restitution;
  material.collision_distance = 0.02f;
  material.drag = drag;
  material.contact_distance = 0.1f; // theta = 1 voxel, as in the paper's Fig. 3c
  dng::Body table;
  dng::Diagnostic diag; // what a refused call says
  dng::samples::require(dng::Body::create(&field, material, &table, &diag), diag);
  const std::vector<dng::Body> bodies = {table};

  // Every particle starts at once: a slab 2 m above the table, drifting sideways.
  const int count = command_line.particles > 0 ? command_line.particles : 2000;
  std::mt19937 rng(1);
  Particles particles;
  for (int i = 0; i < count; ++i) { // p and v apart: the draws in one call's arguments come in no set order
    const Vec3f p{uniform(rng, -1.5f, 1.5f), uniform(rng, -1.5f, 1.5f), uniform(rng, 2.0f, 2.5f)};
    const Vec3f v{uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f), 0.0f};
    particles.add(p, v);
  }

  dng::samples::Trails trails(command_line.pictures ? folder + "/" + name : "", {-3, -3, -2}, {3, 3, 2.6f}, bodies,
                              restitution > 0 ? dng::samples::Colour{1, 0.45f, 0.1f}
                                              : dng::samples::Colour{0.1f, 0.5f, 1});
  // Rebound: the highest point after the first contact (-1 before it); the table's top is z = 0.
  std::vector<float> rebound(std::size_t(count), -1.0f);
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    const dng::ParticleSpan span = particles.span();
    dng::samples::require(dng::applyGravity(span, {0.0f, 0.0f, -9.81f}, kDt, &diag), diag);
    tally.step(span, kDt, bodies.data(), bodies.size());
    for (std::size_t n = 0; n < particles.px.size(); ++n) {
      if (particles.contact[n])
        rebound[n] = std::max(rebound[n], 0.0f);
      else if (rebound[n] >= 0.0f)
        rebound[n] = std::max(rebound[n], particles.pz[n]);
    }
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  double rebound_sum = 0;
  std::size_t touched = 0, resting = 0, inside = 0;
  for (std::size_t n = 0; n < particles.px.size(); ++n) {
    if (rebound[n] >= 0.0f) rebound_sum += rebound[n], ++touched;
    const Vec3f p{particles.px[n], particles.py[n], particles.pz[n]},
        v{particles.vx[n], particles.vy[n], particles.vz[n]};
    const bool on_top = std::fabs(p.x) < 2 && std::fabs(p.y) < 2 && p.z > -0.05f && p.z < 0.3f;
    resting += on_top && dng::length(v) < 0.2f ? 1 : 0;
    Vec3f normal;
    inside += tableDistance(p, &normal) < 0.0f ? 1 : 0; // judged on the true box, not on the field
  }
  std::printf("{\"sample\":\"%s\",\"particles\":%d,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}\n",
              name, count, kSteps, tally.seconds, tally.particleStepsPerSecond(), (unsigned long long)tally.contacts,
              inside);
  const float mean_rebound = touched ? float(rebound_sum / double(touched)) : 0.0f;
  const float fraction_resting = float(resting) / float(count);
  std::printf("{\"sample\":\"%s\",\"mean_rebound_height\":%.3f,\"fraction_resting_on_top\":%.3f}\n", name,
              double(mean_rebound), double(fraction_resting));
  return dng::samples::exitCode(inside == 0 ? 0 : 1, pictures_written);
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line = dng::samples::parseCommandLine(argc, argv, 0, 1, "[OUTPUT_FOLDER]");
  const std::string folder = dng::samples::outputFolder(command_line.get(0, "out"));
  const std::vector<std::uint8_t> bytes = encodeTable();
  dng::View field;
  dng::Diagnostic diag;
  if (dng::View::open(bytes.data(), bytes.size(), &field, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "%s: the table's field does not open: %s\n", argv[0], diag.message);
    return 2;
  }
  const struct {
    const char* name;
    float restitution, drag;
  } variants[] = {{"fig3a_bouncy", 0.7f, 0.0f}, {"fig3b_slippery", 0.0f, 0.0f}, {"fig3c_drag", 0.0f, 2.0f}};
  int code = 0; // every variant runs; the first one's failure is the exit code
  for (const auto& v : variants) {
    const int variant_code = run(v.name, v.restitution, v.drag, field, command_line, folder);
    code = code != 0 ? code : variant_code;
  }
  return code;
}
