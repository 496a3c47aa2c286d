#include "leak_case.h"

#include "case_setup.h"
#include "dng/forces.h"
#include "ray_caster.h"
#include "swarm_judge.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace dng {
namespace leak {

namespace {

// Steps every particle once with the case's stepper; the body goes from `before` to `after`.
std::uint64_t stepOnce(const Subject& subject, const CaseSpec& spec, const CaseSetup& setup, const Body& before,
                       const Body& after, testing::Swarm* swarm) {
  applyGravity(swarm->span(), setup.gravity, kDt);
  if (spec.stepper == Stepper::kRayCaster)
    return rayCastStep(subject.reference, subject.voxel, setup.material.restitution, kDt, before, after, swarm);
  return stepInParallel(&before, 1, kDt, swarm);
}

} // namespace

void addCounts(const CaseResult& from, CaseResult* to) {
  to->particle_steps += from.particle_steps, to->contacts += from.contacts, to->fast_steps += from.fast_steps;
  to->crossing_steps += from.crossing_steps, to->entered += from.entered, to->left += from.left;
  to->through += from.through, to->within += from.within, to->visible_leaks += from.visible_leaks;
  to->thin_passes += from.thin_passes, to->deepest = std::max(to->deepest, from.deepest);
  to->inside_at_end += from.inside_at_end, to->other_side_at_end += from.other_side_at_end;
}

CaseResult runCase(const Subject& subject, const CaseSpec& spec) {
  const auto t0 = std::chrono::steady_clock::now();
  const CaseSetup setup = makeSetup(subject, spec);
  Body before, after;
  (void)Body::create(&subject.file.view(), setup.material, &before);
  after = before;
  placeBody(setup, 0.0f, &before);
  testing::Swarm swarm = spawnParticles(subject, spec, setup, before);
  SwarmJudge judge(subject, before, swarm);
  CaseResult result;
  for (int k = 0; k < spec.steps; ++k) {
    placeBody(setup, float(k) * kDt, &before);
    placeBody(setup, float(k + 1) * kDt, &after);
    result.fast_steps += countFast(subject, before, setup.speed_limit, swarm);
    result.contacts += stepOnce(subject, spec, setup, before, after, &swarm);
    judge.judgeStep(after, swarm);
  }
  std::vector<float> depths;
  judge.addTo(&result, &depths);
  setMedianDepth(&depths, &result);
  result.particle_steps = std::uint64_t(swarm.size()) * std::uint64_t(spec.steps);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

} // namespace leak
} // namespace dng
