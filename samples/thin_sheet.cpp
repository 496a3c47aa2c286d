// A thin open sheet, such as Debian's blade.off, has no inside: only a field baked in potential mode
// (paper §3.1, method 2) has normals that push particles away on both sides. This sample fires
// particles at the sheet from both sides, from inside its band, and counts those that got through.
//
//   dngbake blade.off -o blade.dng --mode potential
//   dng_thin_sheet blade.dng [OUTPUT_FOLDER] [--particles N] [--no-pictures]
//
// Writes OUTPUT_FOLDER/thin_sheet_side.png and _top.png and prints two JSON lines: the run's statistics,
// and how many particles crossed. Exits 1 if one crossed (2 when the file cannot be read). A sheet has
// no inside, so `inside` (where the field reads below zero, as every sample counts it) is reported but
// not judged: beside a sheet thinner than a voxel the conservative planes may read below zero in front
// of it (blade.off at resolution 128: 1 of 4,000 particles, stopped about 0.03 voxel in front of its
// triangles where the field reads -0.66 voxel). A normal-blur bake (method 1) stops them too: its
// normals point one way ("works towards one direction"), but its planes are the distance's own (format
// 1.3). A field whose planes all face one way lets them through (tests/samples_test.cpp). Units: the
// sheet's own; 60 steps per second.
#include "sample_io.h"
#include "sample_particles.h"

#include "dng/file.h"
#include "dng/particles.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using dng::Vec3f;

constexpr float kDt = 1.0f / 60.0f;
constexpr int kSteps = 60;

using dng::samples::Particles;
using dng::samples::uniform;

// Where a particle starts, and the surface plane it faces there: its closest point on the sheet and the
// normal towards the particle. It has crossed if it gets behind that plane near where it started.
struct Start {
  Vec3f position, closest, normal;
};

// The direction away from the sheet at q: the gradient of the trilinear distance. It does not read the
// stored normals, so a one-sided field is put to the test from both sides.
Vec3f away(const dng::View& field, Vec3f q) {
  const float e = 0.5f * field.grid().voxel_size;
  auto d = [&](Vec3f x) { return field.sample(x, dng::Interpolation::kTrilinear).distance; };
  return dng::normalizeOrZero({d(q + Vec3f{e, 0, 0}) - d(q - Vec3f{e, 0, 0}),
                               d(q + Vec3f{0, e, 0}) - d(q - Vec3f{0, e, 0}),
                               d(q + Vec3f{0, 0, e}) - d(q - Vec3f{0, 0, e})});
}

// Whether q (at distance d, direction n from the sheet) lies over the sheet's interior: there the
// distance stays the same three voxels along the sheet. Near a rim it grows; particles may go around
// the edge there, and the potential method's normals turn sideways (a limitation of method 2 this
// sample leaves out rather than hides: docs/SAMPLES.md).
bool overInterior(const dng::View& field, Vec3f q, Vec3f n, float d) {
  const float voxel = field.grid().voxel_size;
  const Vec3f t1 = dng::normalizeOrZero(dng::cross(n, std::fabs(n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
  const Vec3f t2 = dng::cross(n, t1);
  for (Vec3f t : {t1, t1 * -1.0f, t2, t2 * -1.0f}) {
    const dng::Sample s = field.sample(q + t * (3.0f * voxel), dng::Interpolation::kTrilinear);
    if (s.status != dng::SampleStatus::kInBand || std::fabs(s.distance - d) > 0.1f * voxel) return false;
  }
  return true;
}

// A random start in the band on either side of the sheet, 0.4 to 0.9 of the field's guaranteed reach
// away from it, over its interior.
Start randomStart(const dng::View& field, Vec3f size, std::mt19937& rng) {
  const dng::GridInfo& g = field.grid();
  const float reach = field.guaranteedReach();
  for (;;) {
    const Vec3f q = g.origin + Vec3f{uniform(rng, 0, size.x), uniform(rng, 0, size.y), uniform(rng, 0, size.z)};
    const dng::Sample s = field.sample(q, dng::Interpolation::kTrilinear);
    if (s.status != dng::SampleStatus::kInBand || s.distance < 0.4f * reach || s.distance > 0.9f * reach) continue;
    const Vec3f n = away(field, q);
    if (dng::dot(n, n) == 0.0f || !overInterior(field, q, n, s.distance)) continue;
    return {q, q - n * s.distance, n};
  }
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line =
      dng::samples::parseCommandLine(argc, argv, 1, 2, "SHEET.dng [OUTPUT_FOLDER]");
  dng::File file;
  dng::Diagnostic diag;
  if (dng::File::open(command_line.get(0, "").c_str(), &file, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "%s: %s: %s\n", argv[0], command_line.get(0, "").c_str(), diag.message);
    return 2;
  }
  const std::string folder = dng::samples::outputFolder(command_line.get(1, "out"));
  const dng::View& field = file.view();
  const dng::GridInfo& g = field.grid();
  const Vec3f size = Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;

  dng::Material material;
  material.restitution = 0.3f;
  material.collision_distance = 0.2f * g.voxel_size;
  dng::Body sheet;
  dng::samples::require(dng::Body::create(&field, material, &sheet, &diag), diag);
  const std::vector<dng::Body> bodies = {sheet};

  // Every particle starts at once, flying at the sheet at 0.8 of the field's reach per step: fast, but
  // within what one step's walk can prove (docs/RUNTIME.md). No gravity.
  const int count = command_line.particles > 0 ? command_line.particles : 4000;
  const float speed = 0.8f * field.guaranteedReach() / kDt;
  std::mt19937 rng(1);
  Particles particles;
  std::vector<Start> starts;
  for (int i = 0; i < count; ++i) {
    starts.push_back(randomStart(field, size, rng));
    particles.add(starts.back().position, starts.back().normal * -speed);
  }

  dng::samples::Trails trails(command_line.pictures ? folder + "/thin_sheet" : "", g.origin, g.origin + size, bodies,
                              {0.3f, 0.8f, 0.3f});
  std::vector<std::uint8_t> crossed(std::size_t(count), 0);
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    tally.step(particles.span(), kDt, bodies.data(), bodies.size());
    // Checked every step near the start: a particle that got through keeps flying away.
    for (std::size_t n = 0; n < crossed.size(); ++n) {
      const Vec3f from_plane = particles.position(n) - starts[n].closest;
      if (dng::length(from_plane) < 2.0f * g.band && dng::dot(from_plane, starts[n].normal) < 0.0f) crossed[n] = 1;
    }
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // "Inside" as the field sees it: where it reads below zero (the same count as every other sample's);
  // reported only, as a sheet has no inside (see the top of this file).
  std::size_t inside = 0, crossed_count = 0;
  for (std::size_t n = 0; n < crossed.size(); ++n) {
    const dng::Sample s = field.sample(particles.position(n));
    inside += s.status != dng::SampleStatus::kNoField && s.distance < 0.0f ? 1 : 0;
    crossed_count += crossed[n];
  }
  std::printf("{\"sample\":\"thin_sheet\",\"particles\":%d,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}\n",
              count, kSteps, tally.seconds, tally.particleStepsPerSecond(), (unsigned long long)tally.contacts, inside);
  std::printf("{\"sample\":\"thin_sheet\",\"crossed\":%zu}\n", crossed_count);
  return dng::samples::exitCode(crossed_count == 0 ? 0 : 1, pictures_written);
}
