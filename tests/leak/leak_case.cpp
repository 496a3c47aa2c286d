#include "leak_case.h"

#include "case_setup.h"
#include "dng/forces.h"
#include "dng/particles.h"
#include "path_judge.h"
#include "ray_caster.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace dng {
namespace leak {

namespace {

// Per-particle state the judge carries from step to step.
struct Track {
  std::vector<Vec3f> start; ///< body-frame position before the step
  std::vector<std::uint8_t> inside;
  std::vector<std::uint32_t> crossings; ///< total over the run (open meshes: its parity is the side)
};

struct Tally {
  CaseResult result;
  std::vector<float> depths;
  std::vector<reference::Crossing> scratch;
};

void count(const StepVerdict& v, Tally* t) {
  CaseResult& r = t->result;
  if (v.kind == CrossingKind::kNone) return;
  ++r.crossing_steps;
  r.entered += v.kind == CrossingKind::kEntered ? 1 : 0;
  r.left += v.kind == CrossingKind::kLeft ? 1 : 0;
  r.through += v.kind == CrossingKind::kThrough ? 1 : 0;
  r.within += v.kind == CrossingKind::kWithin ? 1 : 0;
  r.visible_leaks += v.visible ? 1 : 0;
  r.thin_passes += v.through_thin ? 1 : 0;
  r.deepest = std::max(r.deepest, v.path_depth);
  t->depths.push_back(v.path_depth);
}

// Steps every particle once with the case's stepper; the body goes from `before` to `after`.
std::uint64_t stepOnce(const Subject& subject, const CaseSpec& spec, const CaseSetup& setup, const Body& before,
                       const Body& after, testing::Swarm* swarm) {
  ParticleSpan all = swarm->span();
  applyGravity(all, setup.gravity, kDt);
  if (spec.stepper == Stepper::kRayCaster)
    return rayCastStep(subject.reference, subject.voxel, setup.material.restitution, kDt, before, after, swarm);
  // Particles are independent: split the span across TBB's threads.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, all.count, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    ParticleSpan part = all;
    part.position_x += r.begin(), part.position_y += r.begin(), part.position_z += r.begin();
    part.velocity_x += r.begin(), part.velocity_y += r.begin(), part.velocity_z += r.begin();
    part.out_contact += r.begin(), part.out_body += r.begin();
    part.count = r.size();
    (void)stepParticles(part, kDt, &before, 1);
  });
  return std::uint64_t(std::count(swarm->contact.begin(), swarm->contact.end(), std::uint8_t(1)));
}

// Counts steps begun near the body faster, relative to the surface, than the case means to test.
std::uint64_t countFast(const Subject& subject, const CaseSetup& setup, const Body& body, const testing::Swarm& swarm) {
  std::uint64_t fast = 0;
  const GridInfo& g = subject.file.view().grid();
  const Vec3f hi = g.origin + Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    const Vec3f p = swarm.position(n), local = body.toLocal(p);
    const bool near = local.x > g.origin.x && local.y > g.origin.y && local.z > g.origin.z && local.x < hi.x &&
                      local.y < hi.y && local.z < hi.z;
    if (near && length(swarm.velocity(n) - body.surfaceVelocity(p)) > 1.001f * setup.speed_limit) ++fast;
  }
  return fast;
}

void judgeStep(const PathJudge& judge, const Body& after, const testing::Swarm& swarm, Track* track,
               tbb::enumerable_thread_specific<Tally>* tallies) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, swarm.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Tally& tally = tallies->local();
                      for (std::size_t n = r.begin(); n != r.end(); ++n) {
                        const Vec3f end = after.toLocal(swarm.position(n));
                        const StepVerdict v = judge.judge(track->start[n], end, track->inside[n] != 0, &tally.scratch);
                        count(v, &tally);
                        track->inside[n] = v.end_inside ? 1 : 0;
                        track->crossings[n] += std::uint32_t(v.crossings);
                        track->start[n] = end;
                      }
                    });
}

} // namespace

CaseResult runCase(const Subject& subject, const CaseSpec& spec) {
  const auto t0 = std::chrono::steady_clock::now();
  const CaseSetup setup = makeSetup(subject, spec);
  Body before, after;
  (void)Body::create(&subject.file.view(), setup.material, &before);
  after = before;
  placeBody(setup, 0.0f, &before);
  testing::Swarm swarm = spawnParticles(subject, spec, setup, before);
  const PathJudge judge(subject.reference, subject.mesh.closed, subject.voxel);
  Track track{std::vector<Vec3f>(swarm.size()), std::vector<std::uint8_t>(swarm.size(), 0),
              std::vector<std::uint32_t>(swarm.size(), 0)};
  for (std::size_t n = 0; n < swarm.size(); ++n)
    track.start[n] = before.toLocal(swarm.position(n));

  tbb::enumerable_thread_specific<Tally> tallies;
  CaseResult result;
  for (int k = 0; k < spec.steps; ++k) {
    placeBody(setup, float(k) * kDt, &before);
    placeBody(setup, float(k + 1) * kDt, &after);
    result.fast_steps += countFast(subject, setup, before, swarm);
    result.contacts += stepOnce(subject, spec, setup, before, after, &swarm);
    judgeStep(judge, after, swarm, &track, &tallies);
  }
  std::vector<float> depths;
  for (Tally& t : tallies) {
    const CaseResult& r = t.result;
    result.crossing_steps += r.crossing_steps, result.entered += r.entered, result.left += r.left;
    result.through += r.through, result.within += r.within, result.visible_leaks += r.visible_leaks;
    result.thin_passes += r.thin_passes, result.deepest = std::max(result.deepest, r.deepest);
    depths.insert(depths.end(), t.depths.begin(), t.depths.end());
  }
  if (!depths.empty()) {
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    result.median_depth = depths[depths.size() / 2];
  }
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    if (subject.mesh.closed)
      result.inside_at_end += track.inside[n] && judge.depth(track.start[n]) > kVisibleEndDepth;
    else
      result.other_side_at_end += track.crossings[n] % 2;
  }
  result.particle_steps = std::uint64_t(swarm.size()) * std::uint64_t(spec.steps);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

} // namespace leak
} // namespace dng
