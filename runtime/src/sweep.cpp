// Swept steps: sphere tracing a particle's step through a DN field, so particles faster than
// band / dt cannot tunnel through a wall. No peer engine does this (DESIGN.md §5): Godot and Unreal
// document tunnelling, Unity tests only the end point.
#include "sweep.h"

#include <cmath>

namespace dng {

namespace {

constexpr int kMaxSamples = 256;

// Clips the local segment q0 + t * dq, t in [0, 1], to the grid box; false when it misses.
bool clipToGrid(const GridInfo& g, Vec3f q0, Vec3f dq, float* io_t0, float* io_t1) {
  const float start[3] = {q0.x, q0.y, q0.z};
  const float dir[3] = {dq.x, dq.y, dq.z};
  const float lo[3] = {g.origin.x, g.origin.y, g.origin.z};
  for (int a = 0; a < 3; ++a) {
    const float hi = lo[a] + float(g.dims[a]) * g.voxel_size;
    if (dir[a] == 0.0f) {
      if (start[a] < lo[a] || start[a] >= hi) return false;
      continue;
    }
    float ta = (lo[a] - start[a]) / dir[a];
    float tb = (hi - start[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    *io_t0 = std::fmax(*io_t0, ta);
    *io_t1 = std::fmin(*io_t1, tb);
  }
  return *io_t0 <= *io_t1;
}

} // namespace

bool sweepSegment(const Body& body, Vec3f p, Vec3f delta, float* out_t, Contact* out_contact) {
  const View& field = *body.field();
  const GridInfo& g = field.grid();
  const Vec3f q0 = body.toLocal(p);
  const Vec3f dq = body.toLocal(p + delta) - q0;
  const float len = length(dq);
  float t = 0.0f, t_end = 1.0f;
  if (!(len > 0.0f) || !clipToGrid(g, q0, dq, &t, &t_end)) return false;

  const float reach = body.material().collision_distance / body.scale() + 0.05f * g.voxel_size;
  const float min_advance = 0.05f * g.voxel_size / len; // guarantees progress near grazing contacts
  // A far sample only proves the voxel centre is beyond the band; the point itself may be closer by
  // half a voxel diagonal (View::guaranteedReach), so far samples advance by that much less.
  const float far_slack = field.grid().band - field.guaranteedReach();
  for (int i = 0; i < kMaxSamples && t <= t_end; ++i) {
    const Sample s = field.sample(q0 + dq * t);
    if (s.status == SampleStatus::kNoField) { // rounding at a face of the grid: step on
      t += min_advance;
      continue;
    }
    const bool approaching = dot(dq, s.normal) < 0.0f;
    if (s.status == SampleStatus::kFarInside || (s.distance <= reach && approaching)) {
      *out_t = t;
      // Deep inside there is no normal: push straight back along the segment.
      const Vec3f local_normal = s.status == SampleStatus::kFarInside ? dq * (-1.0f / len) : s.normal;
      *out_contact = {s.distance * body.scale(), body.rotateToWorld(local_normal)};
      return true;
    }
    const float safe = s.status == SampleStatus::kInBand ? s.distance - reach : s.distance - far_slack - reach;
    t += std::fmax(safe / len, min_advance);
  }
  return false;
}

} // namespace dng
