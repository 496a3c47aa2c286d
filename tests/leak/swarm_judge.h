// A swarm judged against one body's original triangles, step after step: each particle's path in the
// body's own (mesh) frame, from where it was (through the body's pose before the step) to where it
// ended (through the pose after it). A single-body case has one; a scene has one per body.
#pragma once

#include "dng/body.h"
#include "leak_case.h"
#include "path_judge.h"
#include "swarm.h"

#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <vector>

namespace dng {
namespace leak {

class SwarmJudge {
public:
  /// `body` is the subject's body at its pose when the swarm starts. Both must outlive the judge.
  SwarmJudge(const Subject& subject, const Body& body, const testing::Swarm& swarm);

  /// Judges the step every particle has just taken; `after` is the body at its pose at the end of it.
  void judgeStep(const Body& after, const testing::Swarm& swarm);

  /// Adds this body's crossing counts and the particles it holds at the end (closed: deeper than
  /// kVisibleEndDepth; open: on the other side of the sheet) to *out, and every crossing path's depth
  /// to *depths.
  void addTo(CaseResult* out, std::vector<float>* depths) const;

private:
  struct Tally {
    CaseResult result;
    std::vector<float> depths;
    std::vector<reference::Crossing> scratch;
  };

  const Subject& subject_;
  PathJudge judge_;
  std::vector<Vec3f> start_; ///< body-frame position before the step
  std::vector<std::uint8_t> inside_;
  std::vector<std::uint32_t> crossings_; ///< over the run (open meshes: its parity is the side)
  tbb::enumerable_thread_specific<Tally> tallies_;
};

/// The median of `depths` (reordered) into out->median_depth; 0 when there are none.
void setMedianDepth(std::vector<float>* depths, CaseResult* out);

/// Steps begun in the body's grid box faster, relative to its surface, than `limit` (world units/s).
std::uint64_t countFast(const Subject& subject, const Body& body, float limit, const testing::Swarm& swarm);

/// stepParticles over the whole swarm through `bodies`, split across TBB's threads (particles are
/// independent); returns how many particles a body acted on.
std::uint64_t stepInParallel(const Body* bodies, std::size_t count, float dt, testing::Swarm* swarm);

} // namespace leak
} // namespace dng
