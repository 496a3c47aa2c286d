// Field queries on a validated View (paper §3.1 "retrieving the value of the DN field").
//
// Nearest: the voxel that contains p; its distance is refined with the voxel's own plane,
// d = d_v + n_v . (p - c_v), so the answer varies smoothly inside a voxel instead of in steps
// (docs/DESIGN.md §3). Trilinear: the eight voxel centres around p, blended. Accurate: the same eight,
// lifted and corrected by half their planes (below). All work in "voxel units"
// u = (p - origin) / voxel_size, where voxel (i, j, k) spans [i, i + 1) and its centre is i + 0.5.
// Open-time validation guarantees every index and value used here; the only check left is whether
// p lies inside the grid, written so a NaN coordinate fails it.
//
// Speed: the per-encoding helpers are force-inlined into loops specialised per encoding and mode, so
// a batch pays for the dispatch once, not per point, and no intermediate struct round-trips through
// memory (measured: inlining alone took dense nearest from 27 to 10 ns per query, bench/).
#include "dng/format/codec.h"
#include "dng/view.h"
#include "fast_math.h"
#include "step_batch.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace dng {

namespace fmt = format;

namespace {

Sample noField() { return {std::numeric_limits<float>::infinity(), Vec3f{}, SampleStatus::kNoField}; }

// Where voxel (i, j, k) of a bricked grid lives: its tile's index in the top table, and its offset
// within a brick of 2^log2 voxels per edge (docs/FORMAT.md §2.6).
DNG_FORCE_INLINE std::size_t tileOf(const GridInfo& g, std::uint32_t log2, std::uint32_t i, std::uint32_t j,
                                    std::uint32_t k) {
  return (std::size_t(k >> log2) * g.brick_dims[1] + (j >> log2)) * g.brick_dims[0] + (i >> log2);
}
DNG_FORCE_INLINE std::size_t offsetInBrick(std::uint32_t log2, std::uint32_t i, std::uint32_t j, std::uint32_t k) {
  const std::uint32_t mask = (1u << log2) - 1;
  return (std::size_t(k & mask) << (2 * log2)) | (std::size_t(j & mask) << log2) | (i & mask);
}
// The pool word of voxel (i, j, k) in the brick of top entry `entry` (a brick entry).
DNG_FORCE_INLINE std::size_t poolWordOf(std::uint64_t entry, std::uint32_t log2, std::uint32_t i, std::uint32_t j,
                                        std::uint32_t k) {
  return (std::size_t(fmt::entryPoolIndex(entry)) << (3 * log2)) + offsetInBrick(log2, i, j, k);
}

} // namespace

DNG_FORCE_INLINE Sample View::finish(float distance, Vec3f normal) const {
  if (std::fabs(distance) < grid_.band) return {distance, normal, SampleStatus::kInBand};
  return {distance, Vec3f{}, distance > 0.0f ? SampleStatus::kFarOutside : SampleStatus::kFarInside};
}

DNG_FORCE_INLINE bool View::toVoxelUnits(Vec3f p, float out_u[3]) const {
  out_u[0] = (p.x - grid_.origin.x) * inv_voxel_size_;
  out_u[1] = (p.y - grid_.origin.y) * inv_voxel_size_;
  out_u[2] = (p.z - grid_.origin.z) * inv_voxel_size_;
  // Written as "inside" so that NaN fails it.
  return out_u[0] >= 0.0f && out_u[1] >= 0.0f && out_u[2] >= 0.0f && out_u[0] < dims_f_[0] && out_u[1] < dims_f_[1] &&
         out_u[2] < dims_f_[2];
}

// Distance and normals at the centre of voxel (i, j, k), without refinement. Far voxels read as +-band
// with zero normals in both encodings. `with_shading` false skips SHAD: the decode is a call the
// compiler cannot drop when only the result goes unused, and the walk's samples never read it.
template <>
DNG_FORCE_INLINE View::VoxelValue View::voxelValue<fmt::Encoding::kDense>(std::uint32_t i, std::uint32_t j,
                                                                          std::uint32_t k, bool with_shading) const {
  const std::size_t at = (std::size_t(k) * grid_.dims[1] + j) * grid_.dims[0] + i;
  const fmt::DenseVoxel& v = dense_[at];
  if (!(std::fabs(v.distance) < grid_.band)) return {std::copysign(grid_.band, v.distance), Vec3f{}, Vec3f{}};
  const Vec3f n{v.normal[0], v.normal[1], v.normal[2]};
  return {v.distance, n, with_shading && shading_ != nullptr ? fmt::gradientNormal(shading_[at]) : n};
}

// The same for a bricked voxel whose tile's top entry the caller has read.
DNG_FORCE_INLINE View::VoxelValue View::brickedValue(std::uint64_t entry, std::uint32_t i, std::uint32_t j,
                                                     std::uint32_t k, bool with_shading) const {
  const std::uint32_t s = brick_log2_;
  const fmt::TileKind kind = fmt::entryKind(entry);
  if (kind == fmt::TileKind::kBrick) { // the common case near a curved surface
    const std::size_t at = poolWordOf(entry, s, i, j, k);
    const std::uint32_t word = pool_[at];
    const float lo = fmt::rangeValue(fmt::entryLo16(entry), grid_.band, range_step_);
    const float hi = fmt::rangeValue(fmt::entryHi16(entry), grid_.band, range_step_);
    const Vec3f n = fmt::wordNormal(word);
    return {fmt::wordDistance(word, lo, hi, fmt::brickDistanceStep(lo, hi)), n,
            with_shading && shading_ != nullptr ? fmt::gradientNormal(shading_[at]) : n};
  }
  if (kind == fmt::TileKind::kPlane) {
    // The plane is anchored at the tile centre, (tile * B + B/2) in voxel units.
    const float half = 0.5f * float(1u << s);
    const std::uint32_t base = ~((1u << s) - 1);
    const Vec3f from_centre{float(i) + 0.5f - (float(i & base) + half), float(j) + 0.5f - (float(j & base) + half),
                            float(k) + 0.5f - (float(k & base) + half)};
    const Vec3f n = fmt::entryPlaneNormal(entry); // stands for the tile's shading normals (§5.4)
    return {fmt::entryPlaneDistance(entry) + grid_.voxel_size * dot(n, from_centre), n, n};
  }
  return {kind == fmt::TileKind::kFarOutside ? grid_.band : -grid_.band, Vec3f{}, Vec3f{}};
}

template <>
DNG_FORCE_INLINE View::VoxelValue View::voxelValue<fmt::Encoding::kBricked>(std::uint32_t i, std::uint32_t j,
                                                                            std::uint32_t k, bool with_shading) const {
  return brickedValue(top_[tileOf(grid_, brick_log2_, i, j, k)], i, j, k, with_shading);
}

template <fmt::Encoding kEncoding> DNG_FORCE_INLINE Sample View::nearest(Vec3f p, Vec3f* out_shading) const {
  if (out_shading != nullptr) *out_shading = Vec3f{};
  float u[3];
  if (!toVoxelUnits(p, u)) return noField();
  const auto i = std::uint32_t(u[0]);
  const auto j = std::uint32_t(u[1]);
  const auto k = std::uint32_t(u[2]);
  const VoxelValue v = voxelValue<kEncoding>(i, j, k, out_shading != nullptr);
  if (!(std::fabs(v.distance) < grid_.band)) return finish(v.distance, Vec3f{});
  // Plane refinement; for plane tiles this is exactly the tile's plane evaluated at p.
  const Vec3f within{u[0] - float(i) - 0.5f, u[1] - float(j) - 0.5f, u[2] - float(k) - 0.5f};
  const Sample s = finish(v.distance + grid_.voxel_size * dot(v.normal, within), v.normal);
  if (out_shading != nullptr && s.status == SampleStatus::kInBand) *out_shading = v.shading;
  return s;
}

// What sample() answers: the plane's distance, the shading normal.
template <fmt::Encoding kEncoding> DNG_FORCE_INLINE Sample View::nearestShaded(Vec3f p) const {
  Vec3f shading;
  Sample s = nearest<kEncoding>(p, &shading);
  s.normal = shading;
  return s;
}

std::uint64_t View::secondPlaneRecord(std::size_t tile, std::uint32_t local) const {
  const std::uint32_t slot = second_slots_[tile];
  if (slot == fmt::kNoSecondPlanes) return 0;
  // The block's mask says which voxels have a record; the records before this one in its mask word, and
  // the word's first record, say where it is.
  const std::size_t m = std::size_t(slot) * second_mask_words_ + local / 64;
  const std::uint64_t below = (std::uint64_t(1) << (local % 64)) - 1;
  const std::uint64_t mask = second_masks_[m];
  if (!((mask >> (local % 64)) & 1u)) return 0;
  return second_records_[second_first_[m] + fmt::bitCount(mask & below)];
}

Sample View::secondBound(Vec3f p, const Sample& first, bool* out_pair, float* out_other_distance,
                         Vec3f* out_other_normal) const {
  *out_pair = false;
  if (second_slots_ == nullptr || first.status != SampleStatus::kInBand) return first;
  float u[3];
  if (!toVoxelUnits(p, u)) return first;
  const auto i = std::uint32_t(u[0]);
  const auto j = std::uint32_t(u[1]);
  const auto k = std::uint32_t(u[2]);
  const std::uint64_t record =
      secondPlaneRecord(tileOf(grid_, brick_log2_, i, j, k), std::uint32_t(offsetInBrick(brick_log2_, i, j, k)));
  if (!fmt::hasSecondPlane(record)) return first;
  // The same refinement as the first plane's (nearest), so the two compare on the same footing.
  const Vec3f n = fmt::secondPlaneNormal(record);
  const Vec3f within{u[0] - float(i) - 0.5f, u[1] - float(j) - 0.5f, u[2] - float(k) - 0.5f};
  const float d = fmt::secondPlaneDistance(record, grid_.band, second_step_) + grid_.voxel_size * dot(n, within);
  if (!fmt::isSecondPlanePair(record)) return d > first.distance ? finish(d, n) : first;
  // A pair: the smaller of the first plane raised and the second plane, answered with the smaller one's
  // normal; the other comes back beside it.
  const float raised = first.distance + fmt::secondPlaneRaise(record, second_raise_step_);
  const float bound = minOf(raised, d);
  if (!(bound > first.distance)) return first;
  const bool second_lower = d < raised;
  *out_pair = true;
  *out_other_distance = second_lower ? raised : d;
  *out_other_normal = second_lower ? first.normal : n;
  return finish(bound, second_lower ? n : first.normal);
}

Sample View::lowerBound(Vec3f p) const {
  Vec3f unused_normal;
  bool unused_pair;
  float unused_distance;
  return secondBound(p, planeSample(p, nullptr), &unused_pair, &unused_distance, &unused_normal);
}

Sample View::planeSample(Vec3f p, Vec3f* out_shading) const {
  if (!valid()) {
    if (out_shading != nullptr) *out_shading = Vec3f{};
    return noField();
  }
  return dense_ != nullptr ? nearest<fmt::Encoding::kDense>(p, out_shading)
                           : nearest<fmt::Encoding::kBricked>(p, out_shading);
}

namespace {

// The eight voxel centres around a point at voxel units u, and the point's place between them. The
// stencil is clamped to the grid, so edge voxels extrapolate flat.
struct Stencil {
  std::uint32_t lo[3], hi[3];
  float t[3];

  std::uint32_t index(int corner, int axis) const { return (corner >> axis) & 1 ? hi[axis] : lo[axis]; }
  float along(int corner, int axis) const { return (corner >> axis) & 1 ? t[axis] : 1.0f - t[axis]; }
  float weight(int corner) const { return along(corner, 0) * along(corner, 1) * along(corner, 2); }
  /// d weight / d u: the weight with the axis' own factor replaced by its slope, +-1.
  Vec3f weightSlope(int corner) const {
    const float s[3] = {(corner & 1) ? 1.0f : -1.0f, (corner & 2) ? 1.0f : -1.0f, (corner & 4) ? 1.0f : -1.0f};
    return {s[0] * along(corner, 1) * along(corner, 2), along(corner, 0) * s[1] * along(corner, 2),
            along(corner, 0) * along(corner, 1) * s[2]};
  }
};

DNG_FORCE_INLINE Stencil stencilAt(const float u[3], const std::uint32_t dims[3]) {
  Stencil s;
  for (int a = 0; a < 3; ++a) {
    // Centres sit at i + 0.5.
    const float c = maxOf(u[a] - 0.5f, 0.0f);
    s.lo[a] = std::uint32_t(c);
    s.hi[a] = s.lo[a] + 1 < dims[a] ? s.lo[a] + 1 : s.lo[a];
    s.t[a] = minOf(c - float(s.lo[a]), 1.0f);
  }
  return s;
}

} // namespace

template <fmt::Encoding kEncoding> Sample View::trilinear(Vec3f p) const {
  float u[3];
  if (!toVoxelUnits(p, u)) return noField();
  const Stencil s = stencilAt(u, grid_.dims);
  float distance = 0.0f;
  Vec3f normal;
  for (int corner = 0; corner < 8; ++corner) {
    const float w = s.weight(corner);
    const VoxelValue v = voxelValue<kEncoding>(s.index(corner, 0), s.index(corner, 1), s.index(corner, 2));
    distance += w * v.distance;
    normal = normal + v.shading * w;
  }
  return finish(distance, normalizeOrZero(normal));
}

// What the accurate query reads at voxel (i, j, k): voxelValue, and for a voxel whose stored value is
// in band its lift (LIFT, §5.2: per voxel, per plane tile or per pool word) added to the distance, and
// its gradient (GRAD, §5.3: per voxel or per pool word; a plane tile's normal is its gradient already)
// in place of the stored normal. Without the sections, voxelValue itself.
template <>
View::AccurateValue View::accurateValue<fmt::Encoding::kDense>(std::uint32_t i, std::uint32_t j,
                                                               std::uint32_t k) const {
  const VoxelValue v = voxelValue<fmt::Encoding::kDense>(i, j, k);
  AccurateValue out{v.distance, v.normal, std::fabs(v.distance) < grid_.band};
  if (!out.in_band) return out;
  const std::size_t at = (std::size_t(k) * grid_.dims[1] + j) * grid_.dims[0] + i;
  if (lift_ != nullptr) out.distance = v.distance + float(lift_[at]) * lift_step_;
  if (gradient_ != nullptr) out.normal = fmt::gradientNormal(gradient_[at]);
  return out;
}

template <>
View::AccurateValue View::accurateValue<fmt::Encoding::kBricked>(std::uint32_t i, std::uint32_t j,
                                                                 std::uint32_t k) const {
  const std::size_t tile = tileOf(grid_, brick_log2_, i, j, k);
  const std::uint64_t entry = top_[tile];
  const VoxelValue v = brickedValue(entry, i, j, k);
  AccurateValue out{v.distance, v.normal, std::fabs(v.distance) < grid_.band};
  if (!out.in_band) return out; // far tiles among them: they read as +-band
  if (fmt::entryKind(entry) == fmt::TileKind::kPlane) {
    if (lift_ != nullptr) out.distance = v.distance + float(lift_[tile]) * lift_step_;
    return out;
  }
  const std::size_t word = poolWordOf(entry, brick_log2_, i, j, k);
  if (lift_ != nullptr) out.distance = v.distance + float(lift_pool_[word]) * lift_step_;
  if (gradient_ != nullptr) out.normal = fmt::gradientNormal(gradient_[word]);
  return out;
}

namespace {

// One corner of the accurate query's stencil: its (lifted) distance and normal, and p - centre in
// voxel units.
struct Corner {
  float distance;
  Vec3f normal;
  Vec3f to_p;
  bool in_band;
};

// A corner beyond the band knows only that |D| >= band, and its zero normal would bend the blend's
// gradient: near the band's edge the stencil (up to sqrt(3) voxels across) reaches past it. Such a
// corner takes the mean of its in-band neighbours' planes at its centre, kept beyond the band, and
// their mean normal: what a smooth surface continues as.
void extendPastTheBand(Corner corners[8], float band, float voxel) {
  int in_band = 0;
  for (int c = 0; c < 8; ++c)
    in_band += corners[c].in_band ? 1 : 0;
  if (in_band == 0 || in_band == 8) return;
  for (int far = 0; far < 8; ++far) {
    if (corners[far].in_band) continue;
    float planes = 0.0f;
    Vec3f normals;
    for (int near = 0; near < 8; ++near) {
      const Corner& c = corners[near];
      if (!c.in_band) continue;
      planes += c.distance + voxel * dot(c.normal, c.to_p - corners[far].to_p);
      normals = normals + c.normal;
    }
    const float mean = planes / float(in_band);
    corners[far].distance = corners[far].distance > 0.0f ? maxOf(mean, band) : minOf(mean, -band);
    corners[far].normal = normalizeOrZero(normals);
  }
}

} // namespace

// Each corner's distance, lifted, plus half its plane's rise towards p, blended trilinearly. For a
// smooth distance D the plain blend of D errs by +1/2 sum w (p-c)^T H (p-c) and the blend of the full
// planes by minus the same, so the half-way blend cancels the second-order term (docs/RUNTIME.md).
// The normal is the gradient of that blend: consistent with the distance across creases and medial
// axes, where blending the corners' normals mixes the two sides (measured: bench/accuracy_bench.cpp).
template <fmt::Encoding kEncoding> Sample View::accurate(Vec3f p) const {
  float u[3];
  if (!toVoxelUnits(p, u)) return noField();
  const Stencil s = stencilAt(u, grid_.dims);
  Corner corners[8];
  for (int corner = 0; corner < 8; ++corner) {
    const std::uint32_t i = s.index(corner, 0), j = s.index(corner, 1), k = s.index(corner, 2);
    const AccurateValue v = accurateValue<kEncoding>(i, j, k);
    corners[corner] = {
        v.distance, v.normal, {u[0] - float(i) - 0.5f, u[1] - float(j) - 0.5f, u[2] - float(k) - 0.5f}, v.in_band};
  }
  extendPastTheBand(corners, grid_.band, grid_.voxel_size);
  const float half_voxel = 0.5f * grid_.voxel_size;
  float distance = 0.0f;
  Vec3f slope; // d distance / d u; only its direction is used
  for (int corner = 0; corner < 8; ++corner) {
    const Corner& c = corners[corner];
    const float value = c.distance + half_voxel * dot(c.normal, c.to_p);
    const float w = s.weight(corner);
    distance += w * value;
    slope = slope + s.weightSlope(corner) * value + c.normal * (w * half_voxel);
  }
  return finish(distance, normalizeOrZero(slope));
}

Sample View::sample(Vec3f p, Interpolation mode) const {
  if (!valid()) return noField();
  const bool dense = dense_ != nullptr;
  if (mode == Interpolation::kAccurate)
    return dense ? accurate<fmt::Encoding::kDense>(p) : accurate<fmt::Encoding::kBricked>(p);
  if (mode == Interpolation::kTrilinear)
    return dense ? trilinear<fmt::Encoding::kDense>(p) : trilinear<fmt::Encoding::kBricked>(p);
  return dense ? nearestShaded<fmt::Encoding::kDense>(p) : nearestShaded<fmt::Encoding::kBricked>(p);
}

namespace {

// Runs `query` over strided points. The query is a lambda so each instantiation inlines its own: the
// encoding and the interpolation are chosen once per batch, never per point.
template <class Query>
void forEachPoint(const float* points, std::size_t stride, std::size_t count, Sample* out, Query query) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(points);
  for (std::size_t n = 0; n < count; ++n) {
    float xyz[3];
    std::memcpy(xyz, bytes + n * stride, sizeof xyz);
    out[n] = query(Vec3f{xyz[0], xyz[1], xyz[2]});
  }
}

} // namespace

void View::sampleBatch(const float* points, std::size_t point_stride_bytes, std::size_t count, Sample* out_samples,
                       Interpolation mode) const {
  const std::size_t stride = point_stride_bytes;
  if (!valid()) {
    for (std::size_t n = 0; n < count; ++n)
      out_samples[n] = noField();
  } else if (const BatchKernels* kernels = activeBatchKernels(); kernels != nullptr && batchIndexable(*this)) {
    // SIMD lanes, bit for bit the same
    if (mode == Interpolation::kAccurate)
      kernels->sample_accurate(*this, points, stride, count, out_samples);
    else if (mode == Interpolation::kTrilinear)
      kernels->sample_trilinear(*this, points, stride, count, out_samples);
    else
      kernels->sample_nearest(*this, points, stride, count, out_samples);
  } else if (mode == Interpolation::kAccurate && dense_ != nullptr) {
    forEachPoint(points, stride, count, out_samples, [this](Vec3f p) { return accurate<fmt::Encoding::kDense>(p); });
  } else if (mode == Interpolation::kAccurate) {
    forEachPoint(points, stride, count, out_samples, [this](Vec3f p) { return accurate<fmt::Encoding::kBricked>(p); });
  } else if (mode == Interpolation::kTrilinear && dense_ != nullptr) {
    forEachPoint(points, stride, count, out_samples, [this](Vec3f p) { return trilinear<fmt::Encoding::kDense>(p); });
  } else if (mode == Interpolation::kTrilinear) {
    forEachPoint(points, stride, count, out_samples, [this](Vec3f p) { return trilinear<fmt::Encoding::kBricked>(p); });
  } else if (dense_ != nullptr) {
    forEachPoint(points, stride, count, out_samples,
                 [this](Vec3f p) { return nearestShaded<fmt::Encoding::kDense>(p); });
  } else {
    forEachPoint(points, stride, count, out_samples,
                 [this](Vec3f p) { return nearestShaded<fmt::Encoding::kBricked>(p); });
  }
}

} // namespace dng
