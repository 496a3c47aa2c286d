// Internal: the nearest query (view_sample.cpp) for a lane of points at once. Each step mirrors the
// scalar View::nearest operation for operation, so every lane gets the bit-identical sample: find the
// voxel, gather its value (dense float4, or brick-top entry then pool word), decode the octahedral
// normal, refine the distance with the voxel's plane (paper §3.1) and classify the result.
//
// Index arithmetic is 32-bit: callers use this only on views that batchIndexable() (step_batch.h)
// accepts, where every voxel, entry and pool word index fits.
#pragma once

#include "dng/format/codec.h"
#include "lanes.h"
#include "view_internals.h"

#include <cstddef>
#include <cstring>
#include <limits>

namespace dng {
namespace lanes {
namespace DNG_LANES_NS {

/// What View::sample returns, one lane per point; the status as four exclusive masks.
struct LaneSample {
  F distance;
  V3 normal;
  M in_band, far_outside, far_inside, no_field;
};

/// A voxel's stored value before the plane refinement (View::VoxelValue).
struct LaneVoxel {
  F distance;
  V3 normal;
};

// Octahedral decode (format::octDecode) with a per-lane code width.
DNG_LANE_INLINE V3 octDecodeLanes(I qu, I qv, F scale) {
  const F one = splat(1.0f);
  F x = toFloat(qu) * scale - one;
  F y = toFloat(qv) * scale - one;
  const F z = one - abs(x) - abs(y);
  const F t = maxOf(splat(0.0f) - z, splat(0.0f)); // -z > 0 ? -z : 0
  x = x - copysign(t, x);
  y = y - copysign(t, y);
  const F inv = one / sqrt(x * x + y * y + z * z);
  return {x * inv, y * inv, z * inv};
}

// 16-bit section entries (LIFT, GRAD, SHAD), widened; lanes where `m` is false give 0. Lane by lane: no set
// here gathers 16-bit words, and a 32-bit gather could read past the end of the file's last section.
template <class T> DNG_LANE_INLINE I gather16(const T* base, I index, M m) {
  alignas(kLaneAlign) std::int32_t at[kWidth], out[kWidth];
  std::memcpy(at, &index, sizeof at);
  const LaneBits on = bits(m);
  for (int n = 0; n < kWidth; ++n)
    out[n] = (on >> n) & 1u ? std::int32_t(base[at[n]]) : 0;
  I widened;
  std::memcpy(&widened, out, sizeof out);
  return widened;
}

// GRAD or SHAD words (format::gradientNormal), widened, decoded in the lanes of `m`; `fallback` in the
// others.
DNG_LANE_INLINE V3 wordNormalLanes(I word, M m, V3 fallback) {
  const I mask = splatI((1 << format::kGradientOctBits) - 1);
  const V3 n = octDecodeLanes(word & mask, shiftRight(word, format::kGradientOctBits) & mask,
                              splat(2.0f / float((1u << format::kGradientOctBits) - 1)));
  return {select(m, n.x, fallback.x), select(m, n.y, fallback.y), select(m, n.z, fallback.z)};
}

// A voxel's shading normal (View::VoxelValue::shading): SHAD's entry `index` in the lanes of `m`, where
// the file has the section; `normal` (the plane's) elsewhere. SHAD pads to whole 32-bit words
// (docs/FORMAT.md §5.4), so each lane loads the aligned pair that holds its entry, with one gather
// instruction where the set has one (a lane-by-lane gather16 cost 9 instructions per particle-step
// in the step, callgrind), and takes its half.
DNG_LANE_INLINE V3 shadingLanes(const View& view, I index, M m, V3 normal) {
  const std::uint16_t* shading = ViewInternals::shading(view);
  if (shading == nullptr || !any(m)) return normal;
  const I pair = gather(reinterpret_cast<const std::uint32_t*>(shading), shiftRight(index, 1), m);
  const I word = select((index & splatI(1)) == splatI(1), shiftRight(pair, 16), pair & splatI(0xFFFF));
  return wordNormalLanes(word, m, normal);
}

DNG_LANE_INLINE I denseIndex(const View& view, I i, I j, I k) {
  const GridInfo& g = view.grid();
  return (k * splatI(std::int32_t(g.dims[1])) + j) * splatI(std::int32_t(g.dims[0])) + i;
}

DNG_LANE_INLINE LaneVoxel denseVoxel(const View& view, I i, I j, I k, M m) {
  const GridInfo& g = view.grid();
  const I at = shiftLeft(denseIndex(view, i, j, k), 2); // four floats per voxel: distance, normal
  const float* base = reinterpret_cast<const float*>(ViewInternals::dense(view));
  LaneVoxel v;
  gatherPair(base, at, m, &v.distance, &v.normal.x);
  gatherPair(base, at + splatI(2), m, &v.normal.y, &v.normal.z);
  const F band = splat(g.band);
  const M far = ~(abs(v.distance) < band);
  v.distance = select(far, copysign(band, v.distance), v.distance);
  v.normal = select(far, splat(0.0f, 0.0f, 0.0f), v.normal);
  return v;
}

// format::rangeValue for lanes of 16-bit codes.
DNG_LANE_INLINE F rangeLanes(I q16, float band, float step) {
  const M top = q16 == splatI(std::int32_t(format::kRangeMax));
  return select(top, splat(band), splat(-band) + toFloat(q16) * splat(step));
}

/// A bricked voxel's value and where it came from: its tile's kind and index, and for bricks its pool
/// word's index (what the accurate query's LIFT and GRAD sections are indexed by).
struct BrickedVoxel {
  LaneVoxel value;
  M is_brick, is_plane;
  I tile, word;
};

DNG_LANE_INLINE BrickedVoxel brickedVoxelAt(const View& view, I i, I j, I k, M m) {
  const GridInfo& g = view.grid();
  const int s = int(ViewInternals::brickLog2(view));
  const I tile = (shiftRight(k, s) * splatI(std::int32_t(g.brick_dims[1])) + shiftRight(j, s)) *
                     splatI(std::int32_t(g.brick_dims[0])) +
                 shiftRight(i, s);
  I lo32, hi32;
  gather(ViewInternals::top(view), tile, m, &lo32, &hi32);
  const I kind = lo32 & splatI(3);
  const M is_brick = m & (kind == splatI(std::int32_t(format::TileKind::kBrick)));
  const M is_plane = kind == splatI(std::int32_t(format::TileKind::kPlane));
  const M is_far_inside = kind == splatI(std::int32_t(format::TileKind::kFarInside));

  // Far tiles: +-band and no normal. A lane of far tiles only (the common case away from the
  // surface) stops here.
  const float band = g.band;
  LaneVoxel v{select(is_far_inside, splat(-band), splat(band)), splat(0.0f, 0.0f, 0.0f)};
  if (!any(is_brick | is_plane)) return {v, is_brick, is_plane, tile, splatI(0)};

  // Bricks: the voxel's word in the pool.
  const I cell_mask = splatI((1 << s) - 1);
  const I local = shiftLeft(k & cell_mask, 2 * s) | shiftLeft(j & cell_mask, s) | (i & cell_mask);
  const I pool_index = shiftRight(lo32, 2) & splatI(std::int32_t(format::kMaxPoolBricks - 1));
  const I word_index = shiftLeft(pool_index, 3 * s) + local;
  const I word = gather(ViewInternals::pool(view), word_index, is_brick);
  const float step = ViewInternals::rangeStep(view);
  const F lo = rangeLanes(hi32 & splatI(0xFFFF), band, step);
  const F hi = rangeLanes(shiftRight(hi32, 16), band, step);
  const I code = shiftRight(word, 2 * format::kWordOctBits);
  const F brick_step = (hi - lo) * splat(1.0f / float(format::kWordDistanceMax));
  const F brick_distance =
      select(code == splatI(std::int32_t(format::kWordDistanceMax)), hi, lo + toFloat(code) * brick_step);
  const I word_mask = splatI((1 << format::kWordOctBits) - 1);
  const F word_scale = splat(2.0f / float((1u << format::kWordOctBits) - 1));

  // Planes: the tile's plane at the voxel centre, anchored at the tile centre. Lanes of bricks alone
  // take this path too: a branch to skip it, taken or not as bricks and plane tiles alternate along
  // the surface, mispredicted often enough to cost more than the work it saved (measured: bricked
  // nearest on coherent points 19.0 -> 15.7 ns per query, bench/field_query_bench.cpp).
  const float half = 0.5f * float(1 << s);
  const I base = splatI(~((1 << s) - 1));
  const F centre = splat(0.5f), tile_half = splat(half);
  const V3 from_centre{toFloat(i) + centre - (toFloat(i & base) + tile_half),
                       toFloat(j) + centre - (toFloat(j & base) + tile_half),
                       toFloat(k) + centre - (toFloat(k & base) + tile_half)};

  // One octahedral decode for both: 11-bit codes in words, 15-bit codes in plane entries.
  const I plane_mask = splatI((1 << format::kPlaneOctBits) - 1);
  const I qu = select(is_plane, shiftRight(lo32, 2) & plane_mask, word & word_mask);
  const I qv = select(is_plane, shiftRight(lo32, 2 + format::kPlaneOctBits) & plane_mask,
                      shiftRight(word, format::kWordOctBits) & word_mask);
  const F scale = select(is_plane, splat(2.0f / float((1u << format::kPlaneOctBits) - 1)), word_scale);
  const V3 n = octDecodeLanes(qu, qv, scale);
  const F plane_distance = asFloat(hi32) + splat(g.voxel_size) * dot(n, from_centre);
  v.distance = select(is_brick, brick_distance, select(is_plane, plane_distance, v.distance));
  v.normal = select(is_brick | is_plane, n, v.normal);
  return {v, is_brick, is_plane, tile, word_index};
}

/// p in voxel units (View::toVoxelUnits), and the lanes of `active` inside the grid (a NaN is not).
DNG_LANE_INLINE M toVoxelUnits(const View& view, V3 p, M active, V3* out_u) {
  const GridInfo& g = view.grid();
  const F inv = splat(ViewInternals::invVoxelSize(view));
  const float* dims = ViewInternals::dimsF(view);
  const V3 u{(p.x - splat(g.origin.x)) * inv, (p.y - splat(g.origin.y)) * inv, (p.z - splat(g.origin.z)) * inv};
  const F zero = splat(0.0f);
  *out_u = u;
  return active & (u.x >= zero) & (u.y >= zero) & (u.z >= zero) & (u.x < splat(dims[0])) & (u.y < splat(dims[1])) &
         (u.z < splat(dims[2]));
}

/// View::planeSample(p) for the lanes of `p`: the nearest query with the plane's normal, what the
/// step's walk reads. Lanes outside `active` give kNoField. With kShading, also the normal View::sample
/// answers with (VoxelValue::shading, zero unless in band) in *out_shading.
template <bool kDense, bool kShading = false>
DNG_LANE_INLINE LaneSample nearestLanes(const View& view, V3 p, M active, V3* out_shading = nullptr) {
  const GridInfo& g = view.grid();
  V3 u;
  const M inside = toVoxelUnits(view, p, active, &u);
  const F zero = splat(0.0f);
  // Outside lanes index voxel 0, which every view has, and their gathers are masked off anyway.
  const I i = truncate(select(inside, u.x, zero)), j = truncate(select(inside, u.y, zero)),
          k = truncate(select(inside, u.z, zero));
  LaneVoxel v;
  I word = splatI(0); // the voxel's SHAD entry, in the lanes of `worded`
  M worded = inside;
  if (kDense) {
    v = denseVoxel(view, i, j, k, inside);
    if (kShading) word = denseIndex(view, i, j, k);
  } else {
    const BrickedVoxel b = brickedVoxelAt(view, i, j, k, inside);
    v = b.value, word = b.word, worded = b.is_brick; // a plane tile's normal stands for its shading
  }

  const F band = splat(g.band), half = splat(0.5f);
  const M voxel_far = ~(abs(v.distance) < band);
  const V3 within{u.x - toFloat(i) - half, u.y - toFloat(j) - half, u.z - toFloat(k) - half};
  const F refined = v.distance + splat(g.voxel_size) * dot(v.normal, within);
  const F d = select(voxel_far, v.distance, refined);

  LaneSample out;
  out.no_field = ~inside;
  out.in_band = inside & (abs(d) < band);
  const M far = andNot(inside, out.in_band);
  out.far_outside = far & (d > zero);
  out.far_inside = andNot(far, out.far_outside);
  out.distance = select(inside, d, splat(std::numeric_limits<float>::infinity()));
  out.normal = select(out.in_band, v.normal, splat(0.0f, 0.0f, 0.0f));
  // SHAD has an entry for every brick word and dense voxel, in band or not: gathered for all of them,
  // the load waits for the tile entry only, not for the pool word, and the two overlap.
  if (kShading) *out_shading = select(out.in_band, shadingLanes(view, word, worded, v.normal), splat(0.0f, 0.0f, 0.0f));
  return out;
}

/// View::sample(p) (nearest) for the lanes of `p`: the plane's distance, the shading normal.
template <bool kDense> DNG_LANE_INLINE LaneSample nearestShadedLanes(const View& view, V3 p, M active) {
  V3 shading;
  LaneSample s = nearestLanes<kDense, true>(view, p, active, &shading);
  s.normal = shading;
  return s;
}

/// The eight voxel centres around the lanes' points (view_sample.cpp Stencil): per axis the lower and
/// upper index, clamped at the grid's faces, and the point's place between them.
struct LaneStencil {
  I lo[3], hi[3];
  F t[3];

  I index(int corner, int axis) const { return (corner >> axis) & 1 ? hi[axis] : lo[axis]; }
  F along(int corner, int axis) const { return (corner >> axis) & 1 ? t[axis] : splat(1.0f) - t[axis]; }
  F weight(int corner) const { return along(corner, 0) * along(corner, 1) * along(corner, 2); }
  /// d weight / d u: the weight with the axis' own factor replaced by its slope, +-1.
  V3 weightSlope(int corner) const {
    const F s[3] = {splat((corner & 1) ? 1.0f : -1.0f), splat((corner & 2) ? 1.0f : -1.0f),
                    splat((corner & 4) ? 1.0f : -1.0f)};
    return {s[0] * along(corner, 1) * along(corner, 2), along(corner, 0) * s[1] * along(corner, 2),
            along(corner, 0) * along(corner, 1) * s[2]};
  }
};

// Outside lanes take voxel 0's stencil, which every view has; their gathers are masked off.
DNG_LANE_INLINE LaneStencil stencilLanes(const View& view, V3 u, M inside) {
  const F zero = splat(0.0f), one = splat(1.0f), half = splat(0.5f);
  const float* dims = ViewInternals::dimsF(view);
  const F at[3] = {select(inside, u.x, zero), select(inside, u.y, zero), select(inside, u.z, zero)};
  LaneStencil s;
  for (int a = 0; a < 3; ++a) {
    const F c = maxOf(at[a] - half, zero); // centres sit at i + 0.5
    s.lo[a] = truncate(c);
    const F lo_f = toFloat(s.lo[a]);
    s.hi[a] = select(lo_f + one < splat(dims[a]), s.lo[a] + splatI(1), s.lo[a]);
    s.t[a] = minOf(c - lo_f, one);
  }
  return s;
}

// normalizeOrZero (vec3.h): a zero, infinite or NaN length gives no normal.
DNG_LANE_INLINE V3 normalizeOrZero(V3 v) {
  const F zero = splat(0.0f);
  const F len = sqrt(dot(v, v));
  const M unit = (len > zero) & (len < splat(std::numeric_limits<float>::infinity()));
  const F scale = splat(1.0f) / len;
  return {select(unit, v.x * scale, zero), select(unit, v.y * scale, zero), select(unit, v.z * scale, zero)};
}

// View::finish and the no-field answer: the status of a blended distance, the normal only in band.
DNG_LANE_INLINE LaneSample finishLanes(const View& view, M inside, F distance, V3 normal) {
  const F zero = splat(0.0f);
  LaneSample out;
  out.no_field = ~inside;
  out.in_band = inside & (abs(distance) < splat(view.grid().band));
  const M far = andNot(inside, out.in_band);
  out.far_outside = far & (distance > zero);
  out.far_inside = andNot(far, out.far_outside);
  out.distance = select(inside, distance, splat(std::numeric_limits<float>::infinity()));
  out.normal = select(out.in_band, normal, splat(0.0f, 0.0f, 0.0f));
  return out;
}

// A voxel's value with its shading normal (VoxelValue::shading) in place of the plane's.
template <bool kDense> DNG_LANE_INLINE LaneVoxel shadedVoxel(const View& view, I i, I j, I k, M m) {
  if (kDense) {
    LaneVoxel v = denseVoxel(view, i, j, k, m);
    v.normal = shadingLanes(view, denseIndex(view, i, j, k), m & (abs(v.distance) < splat(view.grid().band)), v.normal);
    return v;
  }
  BrickedVoxel b = brickedVoxelAt(view, i, j, k, m);
  b.value.normal = shadingLanes(view, b.word, b.is_brick, b.value.normal);
  return b.value;
}

/// View::sample(p, kTrilinear) for the lanes of `p`: the eight corners blended in the scalar order.
/// Lanes outside `active` give kNoField.
template <bool kDense> DNG_LANE_INLINE LaneSample trilinearLanes(const View& view, V3 p, M active) {
  V3 u;
  const M inside = toVoxelUnits(view, p, active, &u);
  const LaneStencil s = stencilLanes(view, u, inside);
  F distance = splat(0.0f);
  V3 normal = splat(0.0f, 0.0f, 0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const F w = s.weight(corner);
    const I i = s.index(corner, 0), j = s.index(corner, 1), k = s.index(corner, 2);
    const LaneVoxel v = shadedVoxel<kDense>(view, i, j, k, inside);
    distance = distance + w * v.distance;
    normal = normal + v.normal * w;
  }
  return finishLanes(view, inside, distance, normalizeOrZero(normal));
}

/// One corner of the accurate query (view_sample.cpp Corner): its lifted distance, its normal (GRAD's
/// gradient where the file has one), p - centre in voxel units, and whether it is in band.
struct LaneCorner {
  F distance;
  V3 normal, to_p;
  M in_band;
};

// View::accurateValue for the lanes: the voxel's value, and for in-band voxels the lift added and
// GRAD's normal in place of a brick word's (or a dense voxel's) stored one.
template <bool kDense> DNG_LANE_INLINE LaneCorner accurateCorner(const View& view, I i, I j, I k, M inside) {
  const GridInfo& g = view.grid();
  const std::int16_t* lift = ViewInternals::lift(view);
  const std::uint16_t* gradient = ViewInternals::gradient(view);
  const F lift_step = splat(ViewInternals::liftStep(view));
  LaneCorner c;
  I lift_code = splatI(0), gradient_at = splatI(0);
  M graded;
  if (kDense) {
    const LaneVoxel v = denseVoxel(view, i, j, k, inside);
    c.distance = v.distance, c.normal = v.normal;
    c.in_band = inside & (abs(v.distance) < splat(g.band));
    gradient_at = denseIndex(view, i, j, k);
    if (lift != nullptr) lift_code = gather16(lift, gradient_at, c.in_band);
    graded = c.in_band;
  } else {
    const BrickedVoxel b = brickedVoxelAt(view, i, j, k, inside);
    c.distance = b.value.distance, c.normal = b.value.normal;
    c.in_band = inside & (abs(b.value.distance) < splat(g.band));
    const M plane = c.in_band & b.is_plane, brick = andNot(c.in_band, b.is_plane); // far tiles are not in band
    if (lift != nullptr) {
      const I tile_lift = gather16(lift, b.tile, plane);
      const I word_lift = gather16(ViewInternals::liftPool(view), b.word, brick);
      lift_code = select(plane, tile_lift, word_lift);
    }
    gradient_at = b.word;
    graded = brick; // a plane tile's normal is its gradient already
  }
  if (lift != nullptr) c.distance = select(c.in_band, c.distance + toFloat(lift_code) * lift_step, c.distance);
  if (gradient != nullptr && any(graded))
    c.normal = wordNormalLanes(gather16(gradient, gradient_at, graded), graded, c.normal);
  return c;
}

// view_sample.cpp extendPastTheBand for the lanes: each corner beyond the band, in a lane whose
// stencil has in-band corners too, takes the mean of their planes at its centre (kept beyond the band)
// and their normalized mean normal. Sums run over the in-band corners in the scalar order.
DNG_LANE_INLINE void extendPastTheBand(LaneCorner corners[8], float band, float voxel) {
  const F zero = splat(0.0f);
  F in_band = zero;
  for (int c = 0; c < 8; ++c)
    in_band = select(corners[c].in_band, in_band + splat(1.0f), in_band);
  const M mixed = (in_band > zero) & (in_band < splat(8.0f));
  if (!any(mixed)) return;
  for (int far = 0; far < 8; ++far) {
    const M extend = andNot(mixed, corners[far].in_band);
    if (!any(extend)) continue;
    F planes = zero;
    V3 normals = splat(0.0f, 0.0f, 0.0f);
    for (int near = 0; near < 8; ++near) {
      const LaneCorner& c = corners[near];
      const F plane = c.distance + splat(voxel) * dot(c.normal, c.to_p - corners[far].to_p);
      planes = select(c.in_band, planes + plane, planes);
      const V3 sum = normals + c.normal;
      normals = {select(c.in_band, sum.x, normals.x), select(c.in_band, sum.y, normals.y),
                 select(c.in_band, sum.z, normals.z)};
    }
    const F mean = planes / in_band;
    const F kept = select(corners[far].distance > zero, maxOf(mean, splat(band)), minOf(mean, splat(-band)));
    const V3 n = normalizeOrZero(normals);
    LaneCorner& f = corners[far];
    f.distance = select(extend, kept, f.distance);
    f.normal = {select(extend, n.x, f.normal.x), select(extend, n.y, f.normal.y), select(extend, n.z, f.normal.z)};
  }
}

/// View::sample(p, kAccurate) for the lanes of `p`: each corner's lifted distance plus half its plane's
/// rise towards p, blended, and the blend's gradient as the normal. Lanes outside `active` give
/// kNoField.
template <bool kDense> DNG_LANE_INLINE LaneSample accurateLanes(const View& view, V3 p, M active) {
  const GridInfo& g = view.grid();
  V3 u;
  const M inside = toVoxelUnits(view, p, active, &u);
  const LaneStencil s = stencilLanes(view, u, inside);
  const F half = splat(0.5f);
  LaneCorner corners[8];
  for (int corner = 0; corner < 8; ++corner) {
    const I i = s.index(corner, 0), j = s.index(corner, 1), k = s.index(corner, 2);
    corners[corner] = accurateCorner<kDense>(view, i, j, k, inside);
    corners[corner].to_p = {u.x - toFloat(i) - half, u.y - toFloat(j) - half, u.z - toFloat(k) - half};
  }
  extendPastTheBand(corners, g.band, g.voxel_size);
  const F half_voxel = splat(0.5f * g.voxel_size);
  F distance = splat(0.0f);
  V3 slope = splat(0.0f, 0.0f, 0.0f); // d distance / d u; only its direction is used
  for (int corner = 0; corner < 8; ++corner) {
    const LaneCorner& c = corners[corner];
    const F value = c.distance + half_voxel * dot(c.normal, c.to_p);
    const F w = s.weight(corner);
    distance = distance + w * value;
    slope = slope + s.weightSlope(corner) * value + c.normal * (w * half_voxel);
  }
  return finishLanes(view, inside, distance, normalizeOrZero(slope));
}

// The lanes' points from strided xyz triples, starting at point n.
DNG_LANE_INLINE V3 loadPoints(const unsigned char* bytes, std::size_t stride, std::size_t n) {
  V3 p;
  if (stride == 3 * sizeof(float)) { // packed Vec3f
    loadTriples(reinterpret_cast<const float*>(bytes + n * stride), &p.x, &p.y, &p.z);
    return p;
  }
  alignas(kLaneAlign) float xyz[3][kWidth];
  for (int lane = 0; lane < kWidth; ++lane) {
    float q[3];
    std::memcpy(q, bytes + (n + std::size_t(lane)) * stride, sizeof q);
    xyz[0][lane] = q[0], xyz[1][lane] = q[1], xyz[2][lane] = q[2];
  }
  return {load(xyz[0]), load(xyz[1]), load(xyz[2])};
}

static_assert(sizeof(Sample) == 5 * sizeof(float) && offsetof(Sample, normal) == sizeof(float) &&
                  offsetof(Sample, status) == 4 * sizeof(float) && sizeof(SampleStatus) == sizeof(float),
              "storeSamples writes a Sample as five 32-bit words");

// Writes the lanes' samples to out[0..kWidth), as five-word records (no branch per lane for the status).
DNG_LANE_INLINE void storeSamples(const LaneSample& s, Sample* out) {
  const auto code = [](SampleStatus status) { return splatI(std::int32_t(status)); };
  const I status = select(s.in_band, code(SampleStatus::kInBand),
                          select(s.far_outside, code(SampleStatus::kFarOutside),
                                 select(s.far_inside, code(SampleStatus::kFarInside), code(SampleStatus::kNoField))));
  const F words[5] = {s.distance, s.normal.x, s.normal.y, s.normal.z, asFloat(status)};
  storeQuintuples(out, words);
}

template <bool kDense, Interpolation kMode> DNG_LANE_INLINE LaneSample sampleLanes(const View& view, V3 p) {
  return kMode == Interpolation::kAccurate    ? accurateLanes<kDense>(view, p, allTrue())
         : kMode == Interpolation::kTrilinear ? trilinearLanes<kDense>(view, p, allTrue())
                                              : nearestShadedLanes<kDense>(view, p, allTrue());
}

/// View::sampleBatch over strided points, lanes at a time; the tail goes through View::sample. Writes
/// out[0..count).
template <bool kDense, Interpolation kMode>
void sampleLanesBatch(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(points);
  std::size_t n = 0;
  if (kMode == Interpolation::kNearest) {
    // Two registers of points at a time, both loaded before either is sampled: a nearest query is a
    // short chain of dependent loads (tile entry, pool word) and a decode, and two independent chains
    // keep the core busier than one (bench/field_query_bench: about 20% less time per query, coherent
    // or random points; loading the second register after sampling the first gave nothing). The
    // trilinear and accurate queries already have eight corners to overlap, and gained nothing.
    for (; n + 2 * kWidth <= count; n += 2 * kWidth) {
      const V3 a = loadPoints(bytes, stride, n), b = loadPoints(bytes, stride, n + kWidth);
      const LaneSample first = nearestShadedLanes<kDense>(view, a, allTrue());
      const LaneSample second = nearestShadedLanes<kDense>(view, b, allTrue());
      storeSamples(first, out + n);
      storeSamples(second, out + n + kWidth);
    }
  }
  for (; n + kWidth <= count; n += kWidth)
    storeSamples(sampleLanes<kDense, kMode>(view, loadPoints(bytes, stride, n)), out + n);
  for (; n < count; ++n) {
    float p[3];
    std::memcpy(p, bytes + n * stride, sizeof p);
    out[n] = view.sample(Vec3f{p[0], p[1], p[2]}, kMode);
  }
}

/// The same for either encoding, one kernel table entry per interpolation (step_batch.h BatchKernels).
template <Interpolation kMode>
void sampleBatchLanes(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    sampleLanesBatch<true, kMode>(view, points, stride, count, out);
  else
    sampleLanesBatch<false, kMode>(view, points, stride, count, out);
}
inline void sampleNearestBatch(const View& view, const float* points, std::size_t stride, std::size_t count,
                               Sample* out) {
  sampleBatchLanes<Interpolation::kNearest>(view, points, stride, count, out);
}
inline void sampleTrilinearBatch(const View& view, const float* points, std::size_t stride, std::size_t count,
                                 Sample* out) {
  sampleBatchLanes<Interpolation::kTrilinear>(view, points, stride, count, out);
}
inline void sampleAccurateBatch(const View& view, const float* points, std::size_t stride, std::size_t count,
                                Sample* out) {
  sampleBatchLanes<Interpolation::kAccurate>(view, points, stride, count, out);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
