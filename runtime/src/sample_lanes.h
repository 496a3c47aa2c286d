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

DNG_LANE_INLINE LaneVoxel denseVoxel(const View& view, I i, I j, I k, M m) {
  const GridInfo& g = view.grid();
  const I voxel = (k * splatI(std::int32_t(g.dims[1])) + j) * splatI(std::int32_t(g.dims[0])) + i;
  const I at = shiftLeft(voxel, 2); // four floats per voxel: distance, normal
  const float* base = reinterpret_cast<const float*>(ViewInternals::dense(view));
  LaneVoxel v{gather(base, at, m),
              {gather(base, at + splatI(1), m), gather(base, at + splatI(2), m), gather(base, at + splatI(3), m)}};
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

DNG_LANE_INLINE LaneVoxel brickedVoxel(const View& view, I i, I j, I k, M m) {
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
  if (!any(is_brick | is_plane)) return v;

  // Bricks: the voxel's word in the pool.
  const I cell_mask = splatI((1 << s) - 1);
  const I local = shiftLeft(k & cell_mask, 2 * s) | shiftLeft(j & cell_mask, s) | (i & cell_mask);
  const I pool_index = shiftRight(lo32, 2) & splatI(std::int32_t(format::kMaxPoolBricks - 1));
  const I word = gather(ViewInternals::pool(view), shiftLeft(pool_index, 3 * s) + local, is_brick);
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
  return v;
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

/// View::sample(p) (nearest) for the lanes of `p`. Lanes outside `active` give kNoField.
template <bool kDense> DNG_LANE_INLINE LaneSample nearestLanes(const View& view, V3 p, M active) {
  const GridInfo& g = view.grid();
  V3 u;
  const M inside = toVoxelUnits(view, p, active, &u);
  const F zero = splat(0.0f);
  // Outside lanes index voxel 0, which every view has, and their gathers are masked off anyway.
  const I i = truncate(select(inside, u.x, zero)), j = truncate(select(inside, u.y, zero)),
          k = truncate(select(inside, u.z, zero));
  const LaneVoxel v = kDense ? denseVoxel(view, i, j, k, inside) : brickedVoxel(view, i, j, k, inside);

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
  return out;
}

/// View::sample(p, kTrilinear) for the lanes of `p`: the eight voxel centres around p, the stencil
/// clamped at the grid's faces (view_sample.cpp stencilAt), blended corner by corner in the scalar
/// order. Lanes outside `active` give kNoField.
template <bool kDense> DNG_LANE_INLINE LaneSample trilinearLanes(const View& view, V3 p, M active) {
  const GridInfo& g = view.grid();
  V3 u;
  const M inside = toVoxelUnits(view, p, active, &u);
  const F zero = splat(0.0f), one = splat(1.0f), half = splat(0.5f);
  const float* dims = ViewInternals::dimsF(view);
  // Outside lanes take voxel 0's stencil, which every view has; their gathers are masked off.
  const F at[3] = {select(inside, u.x, zero), select(inside, u.y, zero), select(inside, u.z, zero)};
  I lo[3], hi[3];
  F t[3];
  for (int a = 0; a < 3; ++a) {
    const F c = maxOf(at[a] - half, zero); // centres sit at i + 0.5
    lo[a] = truncate(c);
    const F lo_f = toFloat(lo[a]);
    hi[a] = select(lo_f + one < splat(dims[a]), lo[a] + splatI(1), lo[a]);
    t[a] = minOf(c - lo_f, one);
  }
  F distance = zero;
  V3 normal = splat(0.0f, 0.0f, 0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const bool up[3] = {(corner & 1) != 0, (corner & 2) != 0, (corner & 4) != 0};
    const F w = (up[0] ? t[0] : one - t[0]) * (up[1] ? t[1] : one - t[1]) * (up[2] ? t[2] : one - t[2]);
    const I i = up[0] ? hi[0] : lo[0], j = up[1] ? hi[1] : lo[1], k = up[2] ? hi[2] : lo[2];
    const LaneVoxel v = kDense ? denseVoxel(view, i, j, k, inside) : brickedVoxel(view, i, j, k, inside);
    distance = distance + w * v.distance;
    normal = normal + v.normal * w;
  }
  // normalizeOrZero: a zero, infinite or NaN length gives no normal.
  const F len = sqrt(dot(normal, normal));
  const M unit = (len > zero) & (len < splat(std::numeric_limits<float>::infinity()));
  const F scale = one / len;
  const V3 n{select(unit, normal.x * scale, zero), select(unit, normal.y * scale, zero),
             select(unit, normal.z * scale, zero)};

  LaneSample out;
  out.no_field = ~inside;
  out.in_band = inside & (abs(distance) < splat(g.band));
  const M far = andNot(inside, out.in_band);
  out.far_outside = far & (distance > zero);
  out.far_inside = andNot(far, out.far_outside);
  out.distance = select(inside, distance, splat(std::numeric_limits<float>::infinity()));
  out.normal = select(out.in_band, n, splat(0.0f, 0.0f, 0.0f));
  return out;
}

/// View::sampleBatch (nearest or trilinear) over strided points, lanes at a time; the tail goes
/// through View::sample. Writes out[0..count).
template <bool kDense, bool kTrilinear>
void sampleLanesBatch(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(points);
  std::size_t n = 0;
  for (; n + kWidth <= count; n += kWidth) {
    alignas(32) float xyz[3][kWidth];
    for (int lane = 0; lane < kWidth; ++lane) {
      float p[3];
      std::memcpy(p, bytes + (n + std::size_t(lane)) * stride, sizeof p);
      xyz[0][lane] = p[0], xyz[1][lane] = p[1], xyz[2][lane] = p[2];
    }
    const V3 p{load(xyz[0]), load(xyz[1]), load(xyz[2])};
    const LaneSample s =
        kTrilinear ? trilinearLanes<kDense>(view, p, allTrue()) : nearestLanes<kDense>(view, p, allTrue());
    alignas(32) float d[kWidth], nx[kWidth], ny[kWidth], nz[kWidth];
    store(d, s.distance), store(nx, s.normal.x), store(ny, s.normal.y), store(nz, s.normal.z);
    const unsigned in_band = bits(s.in_band), outside = bits(s.far_outside), inside = bits(s.far_inside);
    for (int lane = 0; lane < kWidth; ++lane) {
      const unsigned bit = 1u << lane;
      const SampleStatus status = (in_band & bit)   ? SampleStatus::kInBand
                                  : (outside & bit) ? SampleStatus::kFarOutside
                                  : (inside & bit)  ? SampleStatus::kFarInside
                                                    : SampleStatus::kNoField;
      out[n + std::size_t(lane)] = {d[lane], Vec3f{nx[lane], ny[lane], nz[lane]}, status};
    }
  }
  for (; n < count; ++n) {
    float p[3];
    std::memcpy(p, bytes + n * stride, sizeof p);
    out[n] = view.sample(Vec3f{p[0], p[1], p[2]}, kTrilinear ? Interpolation::kTrilinear : Interpolation::kNearest);
  }
}

/// The same for either encoding: the kernel table's entries (step_batch.h BatchKernels).
inline void sampleNearestBatch(const View& view, const float* points, std::size_t stride, std::size_t count,
                               Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    sampleLanesBatch<true, false>(view, points, stride, count, out);
  else
    sampleLanesBatch<false, false>(view, points, stride, count, out);
}
inline void sampleTrilinearBatch(const View& view, const float* points, std::size_t stride, std::size_t count,
                                 Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    sampleLanesBatch<true, true>(view, points, stride, count, out);
  else
    sampleLanesBatch<false, true>(view, points, stride, count, out);
}

} // namespace DNG_LANES_NS
} // namespace lanes
} // namespace dng
