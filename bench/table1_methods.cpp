#include "table1_methods.h"

#include "dng/forces.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace dng {
namespace table1 {

namespace {

// The dngrid material of a case, lengths in voxels of the mesh's field (as particle_step_bench's
// sphere, whose voxel is 1).
Material materialFor(const Case& c, float voxel) {
  Material m;
  m.restitution = kRestitution;
  m.collision_distance = kCollisionVoxels * voxel;
  if (c.method != Method::kImpact) {
    m.drag = 2.0f, m.contact_distance = 1.0f * voxel;
    m.flow_in = 12.0f * voxel, m.flow_out = 3.0f * voxel, m.flow_distance = 2.0f * voxel;
  }
  m.swept = c.method == Method::kImpactDragFlowSwept;
  return m;
}

int packetWidth(Method m) {
  switch (m) {
  case Method::kEmbree4: return 4;
  case Method::kEmbree8: return 8;
  case Method::kEmbree16: return 16;
  default: return 1;
  }
}

// The field a dngrid case steps through.
const File& fieldOf(const MeshScene& scene, const Case& c) {
  return c.dense ? scene.dense : c.exact ? scene.exact : scene.bricked;
}

} // namespace

std::string caseId(const Case& c) {
  if (c.usesEmbree() && c.avx2) return "embree_rtcIntersect" + std::to_string(packetWidth(c.method)) + "_avx2";
  const std::string field = c.dense ? "dngrid_dense_" : c.exact ? "dngrid_bricked_exact_" : "dngrid_bricked_";
  if (c.avx2) return field + "flow_avx2";
  if (c.proven) return field + "flow_proven";
  switch (c.method) {
  case Method::kPlain: return "plain";
  case Method::kNoBody: return "dngrid_nobody";
  case Method::kImpact: return field + "impact";
  case Method::kImpactDragFlow: return field + "flow";
  case Method::kImpactDragFlowSwept: return field + "flow_swept";
  case Method::kEmbree1: return "embree_rtcIntersect1";
  case Method::kEmbree4: return "embree_rtcIntersect4";
  case Method::kEmbree8: return "embree_rtcIntersect8";
  case Method::kEmbree16: return "embree_rtcIntersect16";
  case Method::kLevelSetNearest: return "nanovdb_nearest";
  case Method::kLevelSetTrilinear: return "nanovdb_trilinear";
  }
  return "?";
}

std::string caseLabel(const Case& c) {
  if (c.usesEmbree() && c.avx2) return "Embree rtcIntersect" + std::to_string(packetWidth(c.method)) + ", AVX2 device";
  const std::string field = c.dense ? "dngrid dense, " : c.exact ? "dngrid bricked exact, " : "dngrid bricked, ";
  if (c.avx2) return field + "impact+drag+flow, AVX2 lanes";
  if (c.proven) return field + "impact+drag+flow, spawns the field proves";
  switch (c.method) {
  case Method::kPlain: return "no collision (plain loop)";
  case Method::kNoBody: return "dngrid stepParticles, no body";
  case Method::kImpact: return field + "impact";
  case Method::kImpactDragFlow: return field + "impact+drag+flow";
  case Method::kImpactDragFlowSwept: return field + "impact+drag+flow, swept";
  case Method::kEmbree1: return "Embree rtcIntersect1";
  case Method::kEmbree4: return "Embree rtcIntersect4";
  case Method::kEmbree8: return "Embree rtcIntersect8";
  case Method::kEmbree16: return "Embree rtcIntersect16";
  case Method::kLevelSetNearest: return "NanoVDB nearest + central differences";
  case Method::kLevelSetTrilinear: return "NanoVDB trilinear + gradient";
  }
  return "?";
}

Stepper stepperFor(const MeshScene& scene, const Case& c) {
  switch (c.method) {
  case Method::kPlain: return [](Swarm* s) { integrate(s, kDt); };
  case Method::kNoBody: // the best kernels, whichever a case stepped before this one set
    return [set = bestInstructionSet()](Swarm* s) {
      setInstructionSet(set);
      stepParticles(s->span(), kDt, nullptr, 0);
    };
  case Method::kImpact:
  case Method::kImpactDragFlow:
  case Method::kImpactDragFlowSwept: {
    Body body;
    const View* field = &fieldOf(scene, c).view();
    if (Body::create(field, materialFor(c, scene.voxel), &body) != Status::kOk) return nullptr;
    // The kernels are a process-wide choice: each step makes its own (an atomic store).
    const InstructionSet set = c.avx2 ? InstructionSet::kAvx2 : bestInstructionSet();
    return [body, set](Swarm* s) {
      setInstructionSet(set);
      stepParticles(s->span(), kDt, &body, 1);
    };
  }
  case Method::kEmbree1:
  case Method::kEmbree4:
  case Method::kEmbree8:
  case Method::kEmbree16: {
    const int width = packetWidth(c.method);
    const EmbreeCaster* caster = c.avx2 ? &scene.caster_avx2 : &scene.caster;
    return [caster, width](Swarm* s) { caster->step(width, kRestitution, kDt, s); };
  }
  case Method::kLevelSetNearest:
  case Method::kLevelSetTrilinear: {
    const LevelSetRead read = c.method == Method::kLevelSetNearest ? LevelSetRead::kNearest : LevelSetRead::kTrilinear;
    const float distance = kCollisionVoxels * scene.voxel;
    return [&scene, read, distance](Swarm* s) { stepLevelSet(scene.levelset, read, kRestitution, distance, kDt, s); };
  }
  }
  return nullptr;
}

std::size_t caseBytes(const MeshScene& scene, const Case& c) {
  if (c.usesField()) return fieldOf(scene, c).view().sizeBytes();
  if (c.usesEmbree()) return c.avx2 ? scene.caster_avx2.bytes() : scene.caster.bytes();
  switch (c.method) {
  case Method::kLevelSetNearest:
  case Method::kLevelSetTrilinear: return std::size_t(scene.levelset.size());
  default: return 0;
  }
}

Simulation::Simulation(const MeshScene& scene, const Case& c, std::size_t particles)
    : spawn(scene.spawn(particles, c.proven)), swarm(spawn), stepper(stepperFor(scene, c)),
      gravity(gravityFor(scene.voxel)) {}

void Simulation::prepare() {
  respawn(spawn, steps++, &swarm);
  applyGravity(swarm.span(), gravity, kDt);
}

void Simulation::warmUp() {
  for (std::size_t n = 0; n < kLifetime; ++n)
    step();
}

Judgement judgeCase(const MeshScene& scene, Simulation sim, std::uint64_t particle_steps) {
  const std::size_t particles = sim.swarm.size();
  Judgement out;
  std::vector<Vec3f> before(particles);
  while (out.segments < particle_steps) {
    sim.prepare(); // the segment judged is the method's own move, after the respawn
    for (std::size_t n = 0; n < particles; ++n)
      before[n] = sim.swarm.position(n);
    sim.stepper(&sim.swarm);
    tbb::combinable<std::uint64_t> crossed([] { return std::uint64_t(0); });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, particles), [&](const tbb::blocked_range<std::size_t>& r) {
      std::vector<reference::Crossing> hits;
      for (std::size_t n = r.begin(); n != r.end(); ++n) {
        scene.judge.crossings(before[n], sim.swarm.position(n), &hits);
        crossed.local() += hits.empty() ? 0 : 1;
      }
    });
    out.crossings += crossed.combine([](std::uint64_t a, std::uint64_t b) { return a + b; });
    out.segments += particles;
  }
  return out;
}

} // namespace table1
} // namespace dng
