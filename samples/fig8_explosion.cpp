// Fig. 8 of the paper (Ilmonen, Takala & Laitinen): an explosion among buildings. A radial blast,
// gravity and air drag (§3.7) throw the gas about; collision avoidance and surface flow (§3.6) carry it
// around the buildings' corners. Six buildings share one field, placed by their transforms; the ground
// is a second field.
//
//   dng_fig8_explosion [OUTPUT_FOLDER] [--particles N] [--no-pictures]
//
// The ground and the building are analytic boxes, turned into DN fields in memory with the std-only
// writer. Writes OUTPUT_FOLDER/fig8_explosion_side.png and _top.png and prints two JSON lines: the run's
// statistics, and the fraction of the gas that ended farther out than the buildings. Exits 1 if a
// particle ends inside the ground or a building. Units: metres and seconds, 60 steps per second.
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
constexpr float kPi = 3.14159265f;
constexpr int kSteps = 150;
const Vec3f kGroundCentre{0, 0, -0.25f}, kGroundHalf{6, 6, 0.25f};     // 12 m square, top at z = 0
const Vec3f kBuildingCentre{0, 0, 1.0f}, kBuildingHalf{0.6f, 0.6f, 1}; // in its own frame: standing on z = 0

// A box's .dng file, in memory: a grid of `voxel` cells over [lo, hi].
std::vector<std::uint8_t> encodeBox(Vec3f centre, Vec3f half, Vec3f lo, Vec3f hi, float voxel, float band_voxels) {
  return dng::samples::encodeAnalytic(lo, hi, voxel, band_voxels, [&](Vec3f p, Vec3f* normal) {
    return dng::samples::boxDistance(p, centre, half, normal);
  });
}

using dng::samples::Particles;
using dng::samples::uniform;

bool openField(const std::vector<std::uint8_t>& bytes, const char* what, dng::View* out) {
  dng::Diagnostic diag;
  if (dng::View::open(bytes.data(), bytes.size(), out, &diag) == dng::Status::kOk) return true;
  std::fprintf(stderr, "the %s's field does not open: %s\n", what, diag.message);
  return false;
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line = dng::samples::parseCommandLine(argc, argv, 0, 1, "[OUTPUT_FOLDER]");
  const std::string folder = dng::samples::outputFolder(command_line.get(0, "out"));
  // The ground on a 10 cm grid; the building finer, on 5 cm, for its corners.
  const std::vector<std::uint8_t> ground_bytes =
      encodeBox(kGroundCentre, kGroundHalf, {-6.4f, -6.4f, -0.9f}, {6.4f, 6.4f, 0.6f}, 0.1f, 4);
  const std::vector<std::uint8_t> building_bytes =
      encodeBox(kBuildingCentre, kBuildingHalf, {-1.0f, -1.0f, -0.4f}, {1.0f, 1.0f, 2.4f}, 0.05f, 5);
  dng::View ground_field, building_field;
  if (!openField(ground_bytes, "ground", &ground_field) || !openField(building_bytes, "building", &building_field))
    return 2;

  // One material for everything: a little bounce, and surface flow that carries the gas around the
  // corners. Swept: the blast throws particles far faster than the fields' reach per step, so every
  // step is walked with the longer sample budget (docs/RUNTIME.md).
  dng::Material material;
  material.restitution = 0.2f;
  material.collision_distance = 0.02f;
  material.flow_in = 8.0f;
  material.flow_out = 2.0f;
  material.flow_distance = 0.15f;
  material.swept = true;
  std::vector<dng::Body> bodies(1);
  dng::Diagnostic diag; // what a refused call says
  dng::samples::require(dng::Body::create(&ground_field, material, &bodies[0], &diag), diag);
  // Six buildings on a ring of radius 2.4 m: one field, six bodies, each moved by its transform.
  std::vector<Vec3f> sites;
  for (int i = 0; i < 6; ++i) {
    const float a = 2 * kPi * float(i) / 6.0f + 0.3f;
    sites.push_back({2.4f * std::cos(a), 2.4f * std::sin(a), 0.0f});
    const float transform[12] = {1, 0, 0, sites.back().x, 0, 1, 0, sites.back().y, 0, 0, 1, sites.back().z};
    dng::Body building;
    dng::samples::require(dng::Body::create(&building_field, material, &building, &diag), diag);
    dng::samples::require(building.setTransform(transform, &diag), diag);
    bodies.push_back(building);
  }

  // The gas starts at once in a small block over the centre, flying outwards and up.
  const int count = command_line.particles > 0 ? command_line.particles : 6000;
  std::mt19937 rng(1);
  Particles particles;
  for (int i = 0; i < count; ++i) { // p and v apart: the draws in one call's arguments come in no set order
    const Vec3f p{uniform(rng, -0.3f, 0.3f), uniform(rng, -0.3f, 0.3f), uniform(rng, 0.1f, 0.6f)};
    const Vec3f v{uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, 0, 3)};
    particles.add(p, v);
  }

  dng::samples::Trails trails(command_line.pictures ? folder + "/fig8_explosion" : "", {-5.5f, -5.5f, -0.5f},
                              {5.5f, 5.5f, 3.0f}, bodies, {1.0f, 0.4f, 0.1f});
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    const dng::ParticleSpan span = particles.span();
    dng::samples::require(dng::applyGravity(span, {0.0f, 0.0f, -9.81f}, kDt, &diag), diag);
    dng::samples::require(dng::applyAirDrag(span, {}, 1.5f, kDt, &diag), diag); // still air
    // The blast: a radial push from just above the ground for its first quarter second.
    if (float(step) * kDt < 0.25f)
      dng::samples::require(dng::applyExplosion(span, {0, 0, 0.3f}, 150.0f, 0.6f, kDt, &diag), diag);
    tally.step(span, kDt, bodies.data(), bodies.size());
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // Judged on the true boxes, not on the fields: inside the ground or any building? Beyond the ring?
  std::size_t inside = 0, beyond = 0;
  for (std::size_t n = 0; n < particles.px.size(); ++n) {
    const Vec3f p{particles.px[n], particles.py[n], particles.pz[n]};
    Vec3f normal;
    bool in = dng::samples::boxDistance(p, kGroundCentre, kGroundHalf, &normal) < 0.0f;
    for (const Vec3f& site : sites)
      in = in || dng::samples::boxDistance(p, site + kBuildingCentre, kBuildingHalf, &normal) < 0.0f;
    inside += in ? 1 : 0;
    beyond += std::hypot(p.x, p.y) > 3.1f ? 1 : 0;
  }
  std::printf("{\"sample\":\"fig8_explosion\",\"particles\":%d,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}\n",
              count, kSteps, tally.seconds, tally.particleStepsPerSecond(), (unsigned long long)tally.contacts, inside);
  const float fraction_beyond = float(beyond) / float(count);
  std::printf("{\"sample\":\"fig8_explosion\",\"fraction_beyond_buildings\":%.3f}\n", double(fraction_beyond));
  return dng::samples::exitCode(inside == 0 ? 0 : 1, pictures_written);
}
