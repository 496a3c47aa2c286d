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
#include "sample_io.h"

#include "dng/forces.h"
#include "dng/format/writer.h"
#include "dng/particles.h"

#include <algorithm>
#include <chrono>
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

// Exact signed distance to a solid axis-aligned box (negative inside) and the outward normal at the
// nearest point.
float boxDistance(Vec3f p, Vec3f centre, Vec3f half, Vec3f* normal) {
  const Vec3f r = p - centre;
  const Vec3f q{std::fabs(r.x) - half.x, std::fabs(r.y) - half.y, std::fabs(r.z) - half.z};
  const Vec3f sign{r.x < 0 ? -1.0f : 1.0f, r.y < 0 ? -1.0f : 1.0f, r.z < 0 ? -1.0f : 1.0f};
  const Vec3f outside{std::max(q.x, 0.0f) * sign.x, std::max(q.y, 0.0f) * sign.y, std::max(q.z, 0.0f) * sign.z};
  const float inner = std::max(q.x, std::max(q.y, q.z));
  if (inner > 0.0f) {
    *normal = dng::normalizeOrZero(outside);
    return dng::length(outside);
  }
  *normal = {}; // inside: the nearest face is the axis with the largest q
  if (q.x >= q.y && q.x >= q.z)
    normal->x = sign.x;
  else if (q.y >= q.z)
    normal->y = sign.y;
  else
    normal->z = sign.z;
  return inner;
}

// A box's .dng file, in memory: the exact distance and normal at every voxel centre of a grid over
// [lo, hi], bricked (paper §3.2) as dngbake would write it from a mesh.
std::vector<std::uint8_t> encodeBox(Vec3f centre, Vec3f half, Vec3f lo, Vec3f hi, float voxel, float band_voxels) {
  dng::format::GridGeometry grid;
  grid.origin = lo;
  grid.voxel_size = voxel;
  grid.dims[0] = std::uint32_t(std::ceil((hi.x - lo.x) / voxel));
  grid.dims[1] = std::uint32_t(std::ceil((hi.y - lo.y) / voxel));
  grid.dims[2] = std::uint32_t(std::ceil((hi.z - lo.z) / voxel));
  grid.band = band_voxels * voxel;
  dng::format::DenseField field;
  field.reset(grid);
  for (std::uint32_t k = 0; k < grid.dims[2]; ++k)
    for (std::uint32_t j = 0; j < grid.dims[1]; ++j)
      for (std::uint32_t i = 0; i < grid.dims[0]; ++i) {
        const std::size_t v = grid.index(i, j, k);
        field.distance[v] = boxDistance(grid.voxelCentre(i, j, k), centre, half, &field.normal[v]);
      }
  return dng::format::encodeBricked(field, {}, "{\"source\":\"analytic\"}").bytes;
}

// Particles as structure-of-arrays, the layout stepParticles reads fastest.
struct Particles {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::uint8_t> contact; // 1 when a body acted on the particle this step

  void add(Vec3f p, Vec3f v) {
    px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
    vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
    contact.push_back(0);
  }
  dng::ParticleSpan span() {
    dng::ParticleSpan s;
    s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
    s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
    s.count = px.size();
    s.out_contact = contact.data();
    return s;
  }
};

float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

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
  double step_seconds = 0.0;
  std::uint64_t particle_steps = 0; // the live particles, summed over the steps (emitters add as they go)
  std::uint64_t contacts = 0;
  for (int step = 0; step < kSteps; ++step) {
    const dng::ParticleSpan span = particles.span();
    dng::samples::require(dng::applyGravity(span, {0.0f, 0.0f, -9.81f}, kDt, &diag), diag);
    dng::samples::require(dng::applyAirDrag(span, {}, 1.5f, kDt, &diag), diag); // still air
    // The blast: a radial push from just above the ground for its first quarter second.
    if (float(step) * kDt < 0.25f)
      dng::samples::require(dng::applyExplosion(span, {0, 0, 0.3f}, 150.0f, 0.6f, kDt, &diag), diag);
    const auto start = std::chrono::steady_clock::now();
    dng::samples::require(dng::stepParticles(span, kDt, bodies.data(), bodies.size(), &diag), diag);
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    particle_steps += span.count;
    for (std::uint8_t c : particles.contact)
      contacts += c;
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // Judged on the true boxes, not on the fields: inside the ground or any building? Beyond the ring?
  std::size_t inside = 0, beyond = 0;
  for (std::size_t n = 0; n < particles.px.size(); ++n) {
    const Vec3f p{particles.px[n], particles.py[n], particles.pz[n]};
    Vec3f normal;
    bool in = boxDistance(p, kGroundCentre, kGroundHalf, &normal) < 0.0f;
    for (const Vec3f& site : sites)
      in = in || boxDistance(p, site + kBuildingCentre, kBuildingHalf, &normal) < 0.0f;
    inside += in ? 1 : 0;
    beyond += std::hypot(p.x, p.y) > 3.1f ? 1 : 0;
  }
  std::printf("{\"sample\":\"fig8_explosion\",\"particles\":%d,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}\n",
              count, kSteps, step_seconds, step_seconds > 0 ? double(particle_steps) / step_seconds : 0.0,
              (unsigned long long)contacts, inside);
  const float fraction_beyond = float(beyond) / float(count);
  std::printf("{\"sample\":\"fig8_explosion\",\"fraction_beyond_buildings\":%.3f}\n", double(fraction_beyond));
  return dng::samples::exitCode(inside == 0 ? 0 : 1, pictures_written);
}
