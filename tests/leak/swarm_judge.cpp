#include "swarm_judge.h"

#include "dng/particles.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace dng {
namespace leak {

SwarmJudge::SwarmJudge(const Subject& subject, const Body& body, const testing::Swarm& swarm)
    : subject_(subject), judge_(subject.reference, subject.mesh.closed, subject.voxel), start_(swarm.size()),
      inside_(swarm.size(), 0), crossings_(swarm.size(), 0) {
  for (std::size_t n = 0; n < swarm.size(); ++n)
    start_[n] = body.toLocal(swarm.position(n));
}

void SwarmJudge::judgeStep(const Body& after, const testing::Swarm& swarm) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, swarm.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Tally& tally = tallies_.local();
                      CaseResult& t = tally.result;
                      for (std::size_t n = r.begin(); n != r.end(); ++n) {
                        const Vec3f end = after.toLocal(swarm.position(n));
                        const StepVerdict v = judge_.judge(start_[n], end, inside_[n] != 0, &tally.scratch);
                        inside_[n] = v.end_inside ? 1 : 0;
                        crossings_[n] += std::uint32_t(v.crossings);
                        start_[n] = end;
                        if (v.kind == CrossingKind::kNone) continue;
                        ++t.crossing_steps;
                        t.entered += v.kind == CrossingKind::kEntered ? 1 : 0;
                        t.left += v.kind == CrossingKind::kLeft ? 1 : 0;
                        t.through += v.kind == CrossingKind::kThrough ? 1 : 0;
                        t.within += v.kind == CrossingKind::kWithin ? 1 : 0;
                        t.visible_leaks += v.visible ? 1 : 0;
                        t.thin_passes += v.through_thin ? 1 : 0;
                        t.deepest = std::max(t.deepest, v.path_depth);
                        tally.depths.push_back(v.path_depth);
                      }
                    });
}

void SwarmJudge::addTo(CaseResult* out, std::vector<float>* depths) const {
  for (const Tally& tally : tallies_) {
    addCounts(tally.result, out);
    depths->insert(depths->end(), tally.depths.begin(), tally.depths.end());
  }
  for (std::size_t n = 0; n < start_.size(); ++n) {
    if (subject_.mesh.closed)
      out->inside_at_end += inside_[n] && judge_.depth(start_[n]) > kVisibleEndDepth;
    else
      out->other_side_at_end += crossings_[n] % 2;
  }
}

void setMedianDepth(std::vector<float>* depths, CaseResult* out) {
  if (depths->empty()) return;
  std::nth_element(depths->begin(), depths->begin() + depths->size() / 2, depths->end());
  out->median_depth = (*depths)[depths->size() / 2];
}

std::uint64_t countFast(const Subject& subject, const Body& body, float limit, const testing::Swarm& swarm) {
  std::uint64_t fast = 0;
  const GridInfo& g = subject.file.view().grid();
  const Vec3f hi = g.origin + Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    const Vec3f p = swarm.position(n), local = body.toLocal(p);
    const bool near = local.x > g.origin.x && local.y > g.origin.y && local.z > g.origin.z && local.x < hi.x &&
                      local.y < hi.y && local.z < hi.z;
    if (near && length(swarm.velocity(n) - body.surfaceVelocity(p)) > 1.001f * limit) ++fast;
  }
  return fast;
}

std::uint64_t stepInParallel(const Body* bodies, std::size_t count, float dt, testing::Swarm* swarm) {
  const ParticleSpan all = swarm->span();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, all.count, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    ParticleSpan part = all;
    part.position_x += r.begin(), part.position_y += r.begin(), part.position_z += r.begin();
    part.velocity_x += r.begin(), part.velocity_y += r.begin(), part.velocity_z += r.begin();
    part.out_contact += r.begin(), part.out_body += r.begin();
    part.count = r.size();
    (void)stepParticles(part, dt, bodies, count);
  });
  return std::uint64_t(std::count(swarm->contact.begin(), swarm->contact.end(), std::uint8_t(1)));
}

} // namespace leak
} // namespace dng
