// Fig. 7 of the paper (Ilmonen, Takala & Laitinen): a stream coming from the right flows around a
// vertical shaft, carried by a draught, with three surface-flow settings (§3.6):
//   (a) rho_in / rho_out = 12 / 3
//   (b) 3 / 6, with a shorter flow distance
//   (c) 3 / -3: a negative rho_out attracts, pulling the stream in behind the shaft
//
//   dng_fig7_shaft_flow [OUTPUT_FOLDER] [--particles N] [--no-pictures]
//
// The shaft is an analytic cylinder, turned into a DN field in memory with the std-only writer. Per
// variant it writes OUTPUT_FOLDER/fig7X_NAME_side.png and _top.png and prints two JSON lines: the run's
// statistics, and what the figure is about: of the particles aimed at the shaft, the fraction that got
// past it, and how far from the stream's axis they were then. Exits 1 if a particle ends inside the
// shaft. Units: metres and seconds, 60 steps per second.
#include "analytic_field.h"
#include "sample_io.h"
#include "sample_particles.h"
#include "stream_report.h"

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
constexpr float kPi = 3.14159265f;
constexpr int kSteps = 150, kEmitSteps = 60;                  // emit for one second, watch for 2.5
constexpr float kShaftRadius = 0.4f, kShaftHalfHeight = 1.0f; // along z, centred on the origin

// Exact signed distance to the capped cylinder (negative inside) and the outward normal.
float shaftDistance(Vec3f p, Vec3f* normal) {
  const float radial = std::sqrt(p.x * p.x + p.y * p.y);
  const float side = radial - kShaftRadius, cap = std::fabs(p.z) - kShaftHalfHeight;
  const Vec3f radial_dir = radial > 0.0f ? Vec3f{p.x / radial, p.y / radial, 0.0f} : Vec3f{1, 0, 0};
  const Vec3f cap_dir{0, 0, p.z < 0 ? -1.0f : 1.0f};
  if (side > 0.0f && cap > 0.0f) { // beyond the rim: the distance to the circle
    const Vec3f d = radial_dir * side + cap_dir * cap;
    *normal = dng::normalizeOrZero(d);
    return dng::length(d);
  }
  *normal = side > cap ? radial_dir : cap_dir;
  return std::max(side, cap);
}

// The shaft's .dng file, in memory: a 4 cm grid with a 5-voxel band.
std::vector<std::uint8_t> encodeShaft() {
  return dng::samples::encodeAnalytic({-0.8f, -0.8f, -1.4f}, {0.8f, 0.8f, 1.4f}, 0.04f, 5, shaftDistance);
}

using dng::samples::Particles;
using dng::samples::uniform;

// The stream: fired along -x from a disk of radius 0.5 m centred 2 m to the right of the shaft.
const Vec3f kFrom{2.0f, 0, 0}, kDirection{-1, 0, 0};
constexpr float kSpeed = 2.5f, kDiskRadius = 0.5f;
constexpr float kPast = 2.8f; // along the stream from kFrom: beyond the shaft

struct Variant {
  const char* name;
  float rho_in, rho_out, flow_distance;
};

// Runs the stream against the shaft with one surface-flow setting, prints its two JSON lines and returns
// its exit code (dng::samples::exitCode: 1 when a particle ended inside the shaft).
int run(const Variant& variant, const dng::View& field, const dng::samples::CommandLine& command_line,
        const std::string& folder) {
  dng::Material material; // no bounce: surface flow steers the particles around (§3.6)
  material.restitution = 0.0f;
  material.collision_distance = 0.02f;
  material.flow_in = variant.rho_in;
  material.flow_out = variant.rho_out;
  material.flow_distance = variant.flow_distance;
  dng::Body shaft;
  dng::Diagnostic diag; // what a refused call says
  dng::samples::require(dng::Body::create(&field, material, &shaft, &diag), diag);
  const std::vector<dng::Body> bodies = {shaft};

  // The emitter disk's axes: the stream runs along x, so the disk spans y and z.
  const Vec3f u = dng::normalizeOrZero(dng::cross(kDirection, {0, 0, 1}));
  const Vec3f w = dng::cross(kDirection, u);
  const int per_step = std::max(1, (command_line.particles > 0 ? command_line.particles : 6000) / kEmitSteps);

  std::mt19937 rng(1);
  Particles particles;
  std::vector<float> start_offsets; // each particle's distance from the stream's axis when emitted
  dng::samples::Trails trails(command_line.pictures ? folder + "/" + variant.name : "", {-2.2f, -1.6f, -1.2f},
                              {2.2f, 1.6f, 1.2f}, bodies, {1.0f, 0.5f, 0.15f});
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    for (int i = 0; step < kEmitSteps && i < per_step; ++i) {
      const float r = kDiskRadius * std::sqrt(uniform(rng, 0, 1)), a = uniform(rng, 0, 2 * kPi);
      particles.add(kFrom + u * (r * std::cos(a)) + w * (r * std::sin(a)), kDirection * kSpeed);
      start_offsets.push_back(r);
    }
    const dng::ParticleSpan span = particles.span();
    // No gravity: the stream is carried by the air moving with it (as smoke in a draught), so particles
    // slowed by the shaft pick up speed again downstream.
    dng::samples::require(dng::applyAirDrag(span, kDirection * kSpeed, 2.0f, kDt, &diag), diag);
    tally.step(span, kDt, bodies.data(), bodies.size());
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // Of the particles that started aimed at the shaft, who got past it, and how far from the axis?
  const dng::samples::StreamAxis axis{kFrom, kDirection, kDiskRadius, kPast};
  return dng::samples::reportStream(variant.name, axis, particles, start_offsets, kSteps, tally, pictures_written,
                                    shaftDistance);
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line = dng::samples::parseCommandLine(argc, argv, 0, 1, "[OUTPUT_FOLDER]");
  const std::string folder = dng::samples::outputFolder(command_line.get(0, "out"));
  const std::vector<std::uint8_t> bytes = encodeShaft();
  dng::View field;
  dng::Diagnostic diag;
  if (dng::View::open(bytes.data(), bytes.size(), &field, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "%s: the shaft's field does not open: %s\n", argv[0], diag.message);
    return 2;
  }
  const Variant variants[] = {{"fig7a_12_3", 12, 3, 0.2f}, {"fig7b_3_6", 3, 6, 0.1f}, {"fig7c_3_minus3", 3, -3, 0.2f}};
  int code = 0; // every variant runs; the first one's failure is the exit code
  for (const Variant& variant : variants) {
    const int variant_code = run(variant, field, command_line, folder);
    code = code != 0 ? code : variant_code;
  }
  return code;
}
