// libFuzzer target for stepParticles on whatever View::open accepts: every file that opens becomes a
// body (at rest; moving and turning; then three bodies, through a BodyIndex too), and a lattice of
// particles with fast and slow velocities is stepped a few times with the scalar code and with every
// SIMD set this CPU has.
//
// The runtime promises that a file it opened is safe to query: no crash, no sanitizer report, finite
// results, and the SIMD kernels give the scalar code's bits. The walk reads more of a file than the
// queries do (second planes, neighbour bounds, many cells per move), so it gets its own target.
// Hashes are resealed as in fuzz_open.cpp, so mutations reach the validation rules and the step.
#include "dng/body.h"
#include "dng/body_index.h"
#include "dng/format/writer.h"
#include "dng/instruction_set.h"
#include "dng/particles.h"
#include "dng/view.h"
#include "swarm.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace {

constexpr int kParticles = 96;
constexpr int kSteps = 3;

using Swarm = dng::testing::Swarm; // tests/support: structure-of-arrays particles and their span

// Whether the lattice's particles (finite ones, the first kParticles) stayed finite.
bool latticeFinite(const Swarm& s) {
  for (std::size_t n = 0; n < std::size_t(kParticles); ++n)
    if (!std::isfinite(s.px[n]) || !std::isfinite(s.py[n]) || !std::isfinite(s.pz[n]) || !std::isfinite(s.vx[n]) ||
        !std::isfinite(s.vy[n]) || !std::isfinite(s.vz[n]))
      return false;
  return true;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

bool sameResults(const Swarm& a, const Swarm& b) {
  return sameBits(a.px, b.px) && sameBits(a.py, b.py) && sameBits(a.pz, b.pz) && sameBits(a.vx, b.vx) &&
         sameBits(a.vy, b.vy) && sameBits(a.vz, b.vz) && a.contact == b.contact && a.body == b.body;
}

// A lattice over the grid and a little beyond, each particle moving 0.05 to about 4 voxels per step
// in a direction of its own: slow ones settle by the balls, fast ones walk cell by cell.
Swarm lattice(const dng::GridInfo& g, float dt) {
  Swarm s;
  for (int n = 0; n < kParticles; ++n) {
    const float t[3] = {float(n % 4) / 3.0f, float((n / 4) % 4) / 3.0f, float((n / 16) % 6) / 5.0f};
    const float span[3] = {float(g.dims[0]), float(g.dims[1]), float(g.dims[2])};
    const dng::Vec3f p{g.origin.x + (t[0] * 1.1f - 0.05f) * span[0] * g.voxel_size,
                       g.origin.y + (t[1] * 1.1f - 0.05f) * span[1] * g.voxel_size,
                       g.origin.z + (t[2] * 1.1f - 0.05f) * span[2] * g.voxel_size};
    const float speed = g.voxel_size / dt * (n % 3 == 0 ? 0.05f : n % 3 == 1 ? 0.7f : 4.0f);
    const float a = 2.399963f * float(n), z = 1.0f - 2.0f * (float(n) + 0.5f) / float(kParticles);
    const float r = std::sqrt(1.0f - z * z);
    s.add(p, {speed * r * std::cos(a), speed * r * std::sin(a), speed * z});
  }
  // And particles a buggy emitter would hand over: NaN and infinite numbers, a move that overflows.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float centre[3] = {g.origin.x + 0.5f * float(g.dims[0]) * g.voxel_size,
                           g.origin.y + 0.5f * float(g.dims[1]) * g.voxel_size,
                           g.origin.z + 0.5f * float(g.dims[2]) * g.voxel_size};
  const float hostile[][6] = {
      {nan, centre[1], centre[2], 0, 0, 0},         {centre[0], centre[1], centre[2], nan, 0, 0},
      {centre[0], centre[1], centre[2], inf, 0, 0}, {centre[0], centre[1], centre[2], 3e38f, 0, 0},
      {3e38f, centre[1], centre[2], -3e38f, 0, 0},  {-inf, centre[1], centre[2], inf, 0, 0}};
  for (const auto& h : hostile)
    s.add({h[0], h[1], h[2]}, {h[3], h[4], h[5]});
  return s;
}

// Steps `swarm` kSteps times with the instruction set in use, through the index when there is one;
// false when the step refused the call.
bool run(const std::vector<dng::Body>& bodies, const dng::BodyIndex* index, float dt, Swarm* swarm) {
  for (int step = 0; step < kSteps; ++step) {
    const dng::Status status =
        index != nullptr ? dng::stepParticles(swarm->span(), dt, bodies.data(), bodies.size(), *index, nullptr)
                         : dng::stepParticles(swarm->span(), dt, bodies.data(), bodies.size(), nullptr);
    if (status != dng::Status::kOk) return false;
  }
  return true;
}

// The scalar step, then every SIMD set this build and CPU have, from the same swarm, and with several
// bodies each set through a BodyIndex too: all finite, all the same bits.
void compare(const std::vector<dng::Body>& bodies, float dt) {
  const Swarm start = lattice(bodies[0].field()->grid(), dt);
  Swarm scalar = start;
  if (dng::setInstructionSet(dng::InstructionSet::kScalar) != dng::Status::kOk) std::abort();
  const bool scalar_ok = run(bodies, nullptr, dt, &scalar);
  if (scalar_ok && !latticeFinite(scalar)) std::abort();
  dng::BodyIndex index;
  if (scalar_ok && bodies.size() > 1 && index.rebuild(bodies.data(), bodies.size(), dt) != dng::Status::kOk)
    std::abort(); // the step took these bodies, so the index must
  for (dng::InstructionSet set : dng::kInstructionSets) {
    if (dng::setInstructionSet(set) != dng::Status::kOk) continue;
    if (set != dng::InstructionSet::kScalar) {
      Swarm wide = start;
      if (run(bodies, nullptr, dt, &wide) != scalar_ok) std::abort();
      if (scalar_ok && !sameResults(scalar, wide)) std::abort();
    }
    if (!scalar_ok || bodies.size() < 2) continue;
    Swarm indexed = start;
    if (!run(bodies, &index, dt, &indexed) || !sameResults(scalar, indexed)) std::abort();
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size); // operator new: 8-byte aligned, as open() needs
  dng::format::resealHashes(bytes);
  dng::View view;
  if (dng::View::open(bytes.data(), bytes.size(), &view) != dng::Status::kOk) return 0;
  const float dt = 1.0f / 60.0f;
  dng::Material material; // impact with drag and flow near the surface, as Table 1 steps
  const float h = view.grid().voxel_size;
  material.collision_distance = 0.1f * h, material.drag = 2.0f, material.contact_distance = h;
  material.flow_in = 5.0f * h, material.flow_out = -2.0f * h, material.flow_distance = h;
  dng::Body body;
  if (dng::Body::create(&view, material, &body) != dng::Status::kOk) return 0; // e.g. a band too thin to step
  compare({body}, dt);
  // Moving and turning, swept, with the spring response: the walk between two poses. Then beside the
  // resting body and a third, offset one that only drags: the several-body kernels and the index.
  dng::Body moving = body;
  material.response = dng::Response::kSpring, material.swept = true;
  if (moving.setMaterial(material) != dng::Status::kOk) std::abort();
  const float turn[4] = {0.96f, 0.1f, 0.2f, 0.15f};
  if (moving.setTransform({h, -2.0f * h, 0.5f * h}, turn, 1.5f) != dng::Status::kOk) return 0;
  moving.setVelocity({3.0f * h / dt, 0.0f, -h / dt}, {0.0f, 0.4f / dt, 0.1f / dt});
  compare({moving}, dt);
  dng::Body dragging = body;
  material.response = dng::Response::kNone, material.swept = false;
  if (dragging.setMaterial(material) != dng::Status::kOk) std::abort();
  const float still[4] = {1.0f, 0.0f, 0.0f, 0.0f};
  if (dragging.setTransform({-3.0f * h, 2.0f * h, 4.0f * h}, still, 1.0f) != dng::Status::kOk) return 0;
  compare({body, moving, dragging}, dt);
  return 0;
}
