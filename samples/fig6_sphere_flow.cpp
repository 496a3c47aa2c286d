// Fig. 6 of the paper (Ilmonen, Takala & Laitinen): a stream of particles flowing around a sphere with
// surface flow rho_in = 12, rho_out = 3 (§3.6): (a) the stream comes from the side, carried by a
// draught; (b) it falls on the sphere from above under gravity.
//
//   dng_fig6_sphere_flow [OUTPUT_FOLDER] [--particles N] [--no-pictures]
//
// The sphere is analytic, turned into a DN field in memory with the std-only writer. Per variant it
// writes OUTPUT_FOLDER/fig6X_NAME_side.png and _top.png and prints two JSON lines: the run's
// statistics, and what the figure is about: of the particles aimed at the sphere, the fraction that got
// past it, and how far from the stream's axis they passed. Exits 1 if a particle ends inside the sphere.
// Units: metres and seconds, 60 steps per second.
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
constexpr int kSteps = 150, kEmitSteps = 60; // emit for one second, watch for 2.5
constexpr float kSphereRadius = 1.0f;        // centred on the origin

// Exact signed distance to the sphere (negative inside) and the outward normal.
float sphereDistance(Vec3f p, Vec3f* normal) {
  const float len = dng::length(p);
  *normal = len > 0.0f ? p * (1.0f / len) : Vec3f{0, 0, 1};
  return len - kSphereRadius;
}

// The sphere's .dng file, in memory: a 5 cm grid with a 4-voxel band.
std::vector<std::uint8_t> encodeSphere() {
  return dng::samples::encodeAnalytic({-1.4f, -1.4f, -1.4f}, {1.4f, 1.4f, 1.4f}, 0.05f, 4, sphereDistance);
}

using dng::samples::Particles;
using dng::samples::uniform;

// A stream fired along `direction` from a disk of radius 0.7 m centred on `from`.
struct Stream {
  const char* name;
  Vec3f from, direction;
  float speed;
  bool gravity; // false: carried by the air moving with it instead
};
constexpr float kDiskRadius = 0.7f;
constexpr float kPast = 3.5f; // along the stream from `from`: beyond the sphere

// Runs one stream, prints its two JSON lines and returns its exit code (dng::samples::exitCode: 1 when
// a particle ended inside the sphere).
int run(const Stream& stream, const dng::View& field, const dng::samples::CommandLine& command_line,
        const std::string& folder) {
  dng::Material material; // no bounce: surface flow steers the particles around (§3.6)
  material.restitution = 0.0f;
  material.collision_distance = 0.02f;
  material.flow_in = 12.0f;
  material.flow_out = 3.0f;
  material.flow_distance = 0.2f;
  dng::Body sphere;
  dng::Diagnostic diag; // what a refused call says
  dng::samples::require(dng::Body::create(&field, material, &sphere, &diag), diag);
  const std::vector<dng::Body> bodies = {sphere};

  const Vec3f gravity = stream.gravity ? Vec3f{0, 0, -9.81f} : Vec3f{};
  const Vec3f wind = stream.direction * stream.speed;
  // The emitter disk's axes.
  const Vec3f u = std::fabs(stream.direction.z) > 0.9f ? Vec3f{1, 0, 0}
                                                       : dng::normalizeOrZero(dng::cross(stream.direction, {0, 0, 1}));
  const Vec3f w = dng::cross(stream.direction, u);
  const int per_step = std::max(1, (command_line.particles > 0 ? command_line.particles : 6000) / kEmitSteps);

  std::mt19937 rng(1);
  Particles particles;
  std::vector<float> start_offsets; // each particle's distance from the stream's axis when emitted
  dng::samples::Trails trails(command_line.pictures ? folder + "/" + stream.name : "", {-2.5f, -2.5f, -2.5f},
                              {2.5f, 2.5f, 2.5f}, bodies, {0.2f, 0.55f, 1.0f});
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    for (int i = 0; step < kEmitSteps && i < per_step; ++i) {
      const float r = kDiskRadius * std::sqrt(uniform(rng, 0, 1)), a = uniform(rng, 0, 2 * kPi);
      particles.add(stream.from + u * (r * std::cos(a)) + w * (r * std::sin(a)), stream.direction * stream.speed);
      start_offsets.push_back(r);
    }
    const dng::ParticleSpan span = particles.span();
    dng::samples::require(dng::applyGravity(span, gravity, kDt, &diag), diag);
    // Without gravity the stream is carried by the air moving with it (as smoke in a draught), so
    // particles slowed by the sphere pick up speed again downstream.
    if (!stream.gravity) dng::samples::require(dng::applyAirDrag(span, wind, 2.0f, kDt, &diag), diag);
    tally.step(span, kDt, bodies.data(), bodies.size());
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // Of the particles that started aimed at the sphere, who got past it, and how far from the axis?
  const dng::samples::StreamAxis axis{stream.from, stream.direction, kDiskRadius, kPast};
  return dng::samples::reportStream(stream.name, axis, particles, start_offsets, kSteps, tally, pictures_written,
                                    sphereDistance);
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line = dng::samples::parseCommandLine(argc, argv, 0, 1, "[OUTPUT_FOLDER]");
  const std::string folder = dng::samples::outputFolder(command_line.get(0, "out"));
  const std::vector<std::uint8_t> bytes = encodeSphere();
  dng::View field;
  dng::Diagnostic diag;
  if (dng::View::open(bytes.data(), bytes.size(), &field, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "%s: the sphere's field does not open: %s\n", argv[0], diag.message);
    return 2;
  }
  const Stream streams[] = {{"fig6a_from_side", {-2.5f, 0, 0}, {1, 0, 0}, 3.0f, false},
                            {"fig6b_from_above", {0, 0, 2.5f}, {0, 0, -1}, 2.0f, true}};
  int code = 0; // every stream runs; the first one's failure is the exit code
  for (const Stream& stream : streams) {
    const int stream_code = run(stream, field, command_line, folder);
    code = code != 0 ? code : stream_code;
  }
  return code;
}
