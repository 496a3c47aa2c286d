// The README demo: particles rain on a baked mesh (the Stanford bunny), bounce, slide with drag and
// flow off it: every response of the paper at once (restitution §3.4, drag §3.5, surface flow §3.6).
//
//   dngbake bunny00.off -o bunny.dng --resolution 128
//   dng_demo MESH.dng [OUTPUT_FOLDER] [UP_AXIS: x, y or z; default z] [POSITIONS] [--particles N]
//            [--no-pictures]
//
// Writes OUTPUT_FOLDER/demo_side.png and demo_top.png and prints one JSON line of statistics; exits 2
// when a file cannot be read or written. Whether particles ended inside is not the field's to say: a
// baked field reads a little below the true distance on purpose (its planes are lower bounds, so the
// step can prove moves clear), and a particle resting beside a crease can read below zero while it is
// outside. The line reports that count as "field_below_zero", for information. With POSITIONS, the demo
// writes where every particle ended, "x y z" per line in the mesh's frame, so that a judge holding the
// mesh itself can count them: `bash setup.sh demo` runs dng_count_inside (tests/reference/) on them,
// and fails when the triangles say any particle is inside.
// Units: the mesh's own; gravity is scaled to its height.
#include "sample_io.h"
#include "sample_particles.h"

#include "dng/file.h"
#include "dng/forces.h"
#include "dng/particles.h"

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using dng::Vec3f;

constexpr float kDt = 1.0f / 60.0f;
constexpr int kSteps = 240, kEmitSteps = 120; // rain for two seconds, watch for four

using dng::samples::Particles;
using dng::samples::uniform;

// A raindrop: in a thin slab near the top of the grid (up axis `up`), away from its sides, at rest. The
// bunny's ears reach into the slab, and an emitter should not start particles inside what they collide
// with: drops within a voxel of the surface (or below it) are drawn again.
Vec3f raindrop(const dng::View& field, int up, std::mt19937& rng) {
  const dng::GridInfo& g = field.grid();
  const float lo[3] = {g.origin.x, g.origin.y, g.origin.z};
  float hi[3];
  for (int a = 0; a < 3; ++a)
    hi[a] = lo[a] + float(g.dims[a]) * g.voxel_size;
  const float height = float(g.dims[up]) * g.voxel_size;
  for (;;) {
    float c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = uniform(rng, lo[a] + 0.2f * (hi[a] - lo[a]), hi[a] - 0.2f * (hi[a] - lo[a]));
    c[up] = uniform(rng, hi[up] - 0.08f * height, hi[up] - 0.01f * height);
    const Vec3f p{c[0], c[1], c[2]};
    const dng::Sample s = field.sample(p);
    if (s.status != dng::SampleStatus::kInBand || s.distance >= g.voxel_size) return p;
  }
}

bool writePositions(const char* path, const Particles& particles) {
  std::FILE* out = std::fopen(path, "w");
  if (out == nullptr) return false;
  for (std::size_t n = 0; n < particles.px.size(); ++n)
    std::fprintf(out, "%.9g %.9g %.9g\n", double(particles.px[n]), double(particles.py[n]), double(particles.pz[n]));
  return std::fclose(out) == 0;
}

} // namespace

int main(int argc, char** argv) {
  const dng::samples::CommandLine command_line =
      dng::samples::parseCommandLine(argc, argv, 1, 4, "MESH.dng [OUTPUT_FOLDER] [x|y|z] [POSITIONS]");
  const std::string path = command_line.get(0, "");
  dng::File file;
  dng::Diagnostic diag;
  if (dng::File::open(path.c_str(), &file, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "%s: %s: %s\n", argv[0], path.c_str(), diag.message);
    return 2;
  }
  const std::string folder = dng::samples::outputFolder(command_line.get(1, "out"));
  const std::string axis = command_line.get(2, "z");
  const int up = axis[0] >= 'x' && axis[0] <= 'z' ? axis[0] - 'x' : 2; // bunny00.off is y-up
  const dng::View& field = file.view();
  const dng::GridInfo& g = field.grid();

  // One material with every response: a moderate bounce, drag within a voxel of the surface, and
  // surface flow that steers particles along it. Swept: falling particles may outrun the band, so every
  // step is walked with the longer sample budget (docs/RUNTIME.md).
  dng::Material material;
  material.restitution = 0.45f;
  material.collision_distance = 0.3f * g.voxel_size;
  material.drag = 1.0f;
  material.contact_distance = g.voxel_size;
  material.flow_in = 3.0f;
  material.flow_out = 1.0f;
  material.flow_distance = 2.0f * g.voxel_size;
  material.swept = true;
  dng::Body mesh;
  dng::samples::require(dng::Body::create(&field, material, &mesh, &diag), diag);
  const std::vector<dng::Body> bodies = {mesh};

  // The mesh is about one unit tall: scale gravity to it, so drops take a moment to land.
  const Vec3f size = Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  Vec3f gravity;
  dng::component(gravity, up) = -9.81f * dng::component(size, up) / 2.0f;
  const int per_step = std::max(1, (command_line.particles > 0 ? command_line.particles : 24000) / kEmitSteps);

  std::mt19937 rng(1);
  Particles particles;
  dng::samples::Trails trails(command_line.pictures ? folder + "/demo" : "", g.origin, g.origin + size, bodies,
                              {1.0f, 0.55f, 0.15f}, up);
  dng::samples::StepTally tally;
  for (int step = 0; step < kSteps; ++step) {
    for (int i = 0; step < kEmitSteps && i < per_step; ++i)
      particles.add(raindrop(field, up, rng), {0, 0, 0});
    const dng::ParticleSpan span = particles.span();
    dng::samples::require(dng::applyGravity(span, gravity, kDt, &diag), diag);
    tally.step(span, kDt, bodies.data(), bodies.size());
    trails.record(step, particles.px, particles.py, particles.pz);
  }
  const bool pictures_written = trails.write();

  // Where the field reads below zero: information only (see the top of this file).
  const std::size_t count = particles.px.size();
  std::size_t below_zero = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const dng::Sample s = field.sample(particles.position(n));
    below_zero += s.status != dng::SampleStatus::kNoField && s.distance < 0.0f ? 1 : 0;
  }
  std::printf("{\"sample\":\"demo\",\"particles\":%zu,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"field_below_zero\":%zu}\n",
              count, kSteps, tally.seconds, tally.particleStepsPerSecond(), (unsigned long long)tally.contacts,
              below_zero);
  if (command_line.positional.size() > 3 && !writePositions(command_line.positional[3].c_str(), particles)) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], command_line.positional[3].c_str());
    return 2;
  }
  return dng::samples::exitCode(0, pictures_written);
}
