#include "path_judge.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace leak {

namespace {

// Samples per voxel of path length when looking for the deepest point: the distance is 1-Lipschitz,
// so the deepest point is found to within half a sample spacing (0.025 voxel).
constexpr float kSamplesPerVoxel = 20.0f;
constexpr int kMaxSamples = 400;

Vec3f lerp(Vec3f a, Vec3f b, float t) { return a + (b - a) * t; }

} // namespace

float PathJudge::depth(Vec3f p) const {
  if (!closed_ || !mesh_.inside(p)) return 0.0f;
  return mesh_.closest(p).distance / voxel_;
}

// The crossings split the path into pieces; a piece is inside when its midpoint is (asked afresh,
// not by counting crossings, which an edge hit reported twice would throw off).
float PathJudge::deepestInside(Vec3f a, Vec3f b, const std::vector<reference::Crossing>& hits) const {
  float deepest = 0.0f;
  const float length_voxels = length(b - a) / voxel_;
  float t0 = 0.0f;
  for (std::size_t i = 0; i <= hits.size(); ++i) {
    const float t1 = i < hits.size() ? hits[i].t : 1.0f;
    if (t1 - t0 > 1e-7f && mesh_.inside(lerp(a, b, 0.5f * (t0 + t1)))) {
      const int samples = std::clamp(int(std::ceil((t1 - t0) * length_voxels * kSamplesPerVoxel)), 2, kMaxSamples);
      for (int s = 0; s <= samples; ++s) {
        const Vec3f p = lerp(a, b, t0 + (t1 - t0) * float(s) / float(samples));
        deepest = std::max(deepest, mesh_.closest(p).distance / voxel_);
      }
    }
    t0 = t1;
  }
  return deepest;
}

StepVerdict PathJudge::judge(Vec3f a, Vec3f b, bool a_inside, std::vector<reference::Crossing>* scratch) const {
  StepVerdict v;
  mesh_.crossings(a, b, scratch);
  v.crossings = int(scratch->size());
  if (!closed_) {
    v.kind = v.crossings > 0 ? CrossingKind::kThrough : CrossingKind::kNone;
    v.through_thin = v.visible = v.crossings > 0; // a sheet is all thin part
    return v;
  }
  if (v.crossings == 0) {
    // No surface between a and b: b is where a was. A particle already inside stays as deep as it is.
    v.end_inside = a_inside;
    if (a_inside) v.end_depth = v.path_depth = depth(b);
    return v;
  }
  v.end_inside = mesh_.inside(b);
  v.end_depth = v.end_inside ? mesh_.closest(b).distance / voxel_ : 0.0f;
  v.path_depth = std::max(v.end_depth, deepestInside(a, b, *scratch));
  if (!a_inside)
    v.kind = v.end_inside ? CrossingKind::kEntered : CrossingKind::kThrough;
  else
    v.kind = v.end_inside ? CrossingKind::kWithin : CrossingKind::kLeft;
  if (v.kind == CrossingKind::kThrough) {
    const Vec3f in = mesh_.faceNormal(scratch->front().triangle), out = mesh_.faceNormal(scratch->back().triangle);
    v.through_thin = dot(in, out) < 0.0f;
  }
  // Only a step that gets in counts as a leak: leaving, or moving about after an earlier leak, is
  // the same leak again (it shows in the particles still inside at the end).
  const bool gets_in = v.kind == CrossingKind::kEntered || v.kind == CrossingKind::kThrough;
  v.visible = gets_in && (v.path_depth > kVisiblePathDepth || v.end_depth > kVisibleEndDepth || v.through_thin);
  return v;
}

} // namespace leak
} // namespace dng
