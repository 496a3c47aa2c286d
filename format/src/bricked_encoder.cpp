// The bricked encoding: Ilmonen, Takala & Laitinen's "compressed plane grid" (paper §3.2) as a
// two-level tree. Each brick of B^3 voxels becomes, in order of preference:
//   1. a far tile, when every voxel is beyond the band on the same side (nothing is lost);
//   2. a plane tile, when one plane d = d_c + n . (p - c) reproduces every voxel's distance and
//      normal within the tolerances (the paper: "turn the distance/normal information into a plane
//      equation");
//   3. a brick of 32-bit words in the pool (octahedral normal + brick-affine 10-bit distance).
// Bricks are read from the source one at a time into a small buffer, so a sparse source never has to
// expand into a dense grid. Each z layer of bricks is encoded on its own (in parallel when the caller
// brings threads) and the layers are joined in order, so the output depends only on the input.
#include "dng/format/codec.h"
#include "dng/format/writer.h"
#include "grid_section.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace format {
namespace {

constexpr float kDegrees = 57.29577951308232f;
// Relative float rounding between the encoder's and the reader's evaluation of the same plane.
constexpr float kRoundingSlack = 4e-7f;

// A section of one 16-bit normal per pool word (GRAD, docs/FORMAT.md §5.3; SHAD, §5.4), when the
// source has it: the brick's normals as read, and the words in the pool's order.
struct WordNormals {
  bool present = false;
  std::vector<Vec3f> brick;
  std::vector<std::uint16_t> pool;
};

// PLN2 (docs/FORMAT.md §5.5), when the source has second planes: the brick's as read; one slot per top
// entry; per block its voxel mask; the records, block by block in voxel order.
struct SecondPlanes {
  bool present = false;
  std::vector<float> distance;
  std::vector<Vec3f> normal;
  std::vector<float> raise;
  std::vector<float> stored_distance; // the brick's first planes as a reader decodes them (band voxels)
  std::vector<Vec3f> stored_normal;
  std::vector<std::uint64_t> by_voxel; // the brick's records by local index, 0 for none
  std::vector<std::uint32_t> slots;
  std::vector<std::uint64_t> masks;
  std::vector<std::uint64_t> words;
};

struct Encoder {
  const FieldSource& source;
  const GridGeometry& grid;
  std::uint32_t log2;
  std::uint32_t size;
  float tolerance_local; // distance tolerance in local units
  float min_cosine;      // cosine of the normal tolerance
  std::vector<std::uint64_t> top;
  std::vector<std::uint32_t> pool;
  EncodeStats stats;
  std::vector<float> distance; // the brick being encoded, x fastest
  std::vector<Vec3f> normal;
  std::vector<std::uint32_t> quantized; // writeBrick's scratch: octahedral normal bits per voxel
  std::vector<float> target;            // and the value each voxel's word may not exceed
  // LIFT (docs/FORMAT.md §5.2), when the source has accurate distances: the brick's accurate values,
  // and one lift per top entry and per pool word, in the orders of `top` and `pool`.
  bool lifted = false;
  std::vector<float> accurate;
  std::vector<std::int16_t> lift_top;
  std::vector<std::int16_t> lift_pool;
  WordNormals gradient; // GRAD: the distance's own gradient beside other normals
  WordNormals shading;  // SHAD: the mode's normals beside the gradient's planes
  SecondPlanes second;  // PLN2: second planes beside edges
  // A voxel whose input and decoded normals have a cosine above this cannot raise
  // stats.max_normal_error_deg (2: any voxel may). See measure().
  double no_news_cosine = 2.0;
};

// A brick's voxel range, clipped to the grid.
struct BrickBox {
  std::uint32_t lo[3];
  std::uint32_t hi[3]; // exclusive
};

// Calls visit(i, j, k, v) for every voxel of the brick, v indexing the brick buffer.
template <class Visit> void forEachVoxel(const BrickBox& box, Visit visit) {
  std::size_t v = 0;
  for (std::uint32_t k = box.lo[2]; k < box.hi[2]; ++k)
    for (std::uint32_t j = box.lo[1]; j < box.hi[1]; ++j)
      for (std::uint32_t i = box.lo[0]; i < box.hi[0]; ++i)
        visit(i, j, k, v++);
}

// How far a plane through a voxel centre with normal `stored` can rise above one with normal `input`
// anywhere in the voxel's cell: max over the cube of (stored - input) . x is the L1 norm times h/2.
float tiltAllowance(Vec3f stored, Vec3f input, float voxel_size) {
  const Vec3f d = stored - input;
  return (std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z)) * 0.5f * voxel_size;
}

bool inBand(const Encoder& e, std::size_t v) { return std::fabs(e.distance[v]) < e.grid.band; }

// Whether the cosine of angle `p` is above `bound` > 0, without the atan2.
bool cosineAbove(AngleParts p, double bound) {
  return p.cosine > 0.0 && p.cosine * p.cosine > bound * bound * (p.sine * p.sine + p.cosine * p.cosine);
}

// Records the error of a decoded (distance, normal) against the input voxel it stands for, and keeps
// the decoded plane for the voxel's second-plane pair (writeSecondPlanes).
void measure(Encoder& e, std::size_t v, float decoded_distance, Vec3f decoded_normal) {
  if (e.second.present) e.second.stored_distance[v] = decoded_distance, e.second.stored_normal[v] = decoded_normal;
  const float h = e.grid.voxel_size;
  e.stats.max_distance_error_voxels =
      std::max(e.stats.max_distance_error_voxels, std::fabs(decoded_distance - e.distance[v]) / h);
  // Most voxels' normal error is below the largest so far, and their cosine, without the angle's atan2
  // (a sixth of a 512^3 bake's encoding), says so with room to spare: the same maximum.
  const AngleParts parts = angleParts(e.normal[v], decoded_normal);
  if (cosineAbove(parts, e.no_news_cosine)) return;
  // A zero input normal (the producer gave none) compares as 0 degrees: nothing to compare.
  const auto angle = float(degreesOf(parts));
  if (!(angle > e.stats.max_normal_error_deg)) return;
  e.stats.max_normal_error_deg = angle;
  // Above cos(max) by far more than rounding: any angle whose cosine is above this is smaller.
  e.no_news_cosine = std::cos(double(angle) / 57.29577951308232) + 1e-9;
}

// Far tile when every voxel lies beyond the band on one side.
bool tryFarTile(Encoder& e, const BrickBox& box, std::uint64_t* out_entry) {
  const float band = e.grid.band;
  bool all_outside = true;
  bool all_inside = true;
  forEachVoxel(box, [&](std::uint32_t, std::uint32_t, std::uint32_t, std::size_t v) {
    all_outside = all_outside && e.distance[v] >= band;
    all_inside = all_inside && e.distance[v] <= -band;
  });
  if (!all_outside && !all_inside) return false;
  *out_entry = packFarEntry(all_outside ? TileKind::kFarOutside : TileKind::kFarInside);
  return true;
}

Vec3f tileCentre(const Encoder& e, const std::uint32_t brick[3]) {
  const GridGeometry& g = e.grid;
  const float half = 0.5f * float(e.size);
  return g.origin +
         Vec3f{float(brick[0] * e.size) + half, float(brick[1] * e.size) + half, float(brick[2] * e.size) + half} *
             g.voxel_size;
}

// Plane tile when the (quantized) mean normal and a least-squares offset reproduce every voxel.
bool tryPlaneTile(Encoder& e, const BrickBox& box, const std::uint32_t brick[3], std::uint64_t* out_entry) {
  const GridGeometry& g = e.grid;
  Vec3f normal_sum;
  forEachVoxel(box, [&](std::uint32_t, std::uint32_t, std::uint32_t, std::size_t v) {
    if (inBand(e, v)) normal_sum = normal_sum + normalizeOrZero(e.normal[v]);
  });
  if (dot(normal_sum, normal_sum) == 0.0f) return false;
  std::uint32_t qu = 0, qv = 0;
  octEncode(normalizeOrZero(normal_sum), kPlaneOctBits, &qu, &qv);
  const Vec3f n = octDecode(qu, qv, kPlaneOctBits);
  const Vec3f c = tileCentre(e, brick);

  double offset_sum = 0.0;
  std::size_t band_count = 0;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (!inBand(e, v)) return;
    offset_sum += double(e.distance[v]) - double(dot(n, g.voxelCentre(i, j, k) - c));
    ++band_count;
  });
  float d_c = float(offset_sum / double(band_count));
  // Conservative: the tile's plane may not rise above any voxel's own plane anywhere in that voxel's
  // cell (docs/FORMAT.md, "conservative planes"), so lower it by the worst excess, plus rounding.
  float excess = 0.0f;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (!inBand(e, v)) return;
    const float predicted = d_c + dot(n, g.voxelCentre(i, j, k) - c);
    const float allowed = e.distance[v] - tiltAllowance(n, normalizeOrZero(e.normal[v]), g.voxel_size);
    excess = std::max(excess, predicted - allowed);
  });
  d_c -= excess + kRoundingSlack * (std::fabs(d_c) + g.band);

  bool fits = true;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    const float predicted = d_c + dot(n, g.voxelCentre(i, j, k) - c);
    const float error = std::fabs(clampToBand(predicted, g.band) - clampToBand(e.distance[v], g.band));
    // A plane tile has no words to put shading normals in: its normal stands for them, within tolerance.
    const bool normal_ok =
        !inBand(e, v) || (dot(n, normalizeOrZero(e.normal[v])) >= e.min_cosine &&
                          (!e.shading.present || dot(n, normalizeOrZero(e.shading.brick[v])) >= e.min_cosine));
    fits = fits && error <= e.tolerance_local && normal_ok;
  });
  if (!fits) return false;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (inBand(e, v)) measure(e, v, d_c + dot(n, g.voxelCentre(i, j, k) - c), n);
  });
  *out_entry = packPlaneEntry(qu, qv, d_c);
  return true;
}

// Voxel v's lift over the value a reader decodes for it, and the error it leaves (band voxels).
std::int16_t lift(Encoder& e, std::size_t v, float decoded) {
  const std::int16_t code = voxelLift(e.accurate[v], decoded, e.grid.band);
  if (inBand(e, v))
    e.stats.max_lifted_error_voxels =
        std::max(e.stats.max_lifted_error_voxels, liftedError(e.accurate[v], decoded, code, e.grid));
  return code;
}

// A plane tile has one lift: the mean over its band voxels of what lifts each one from the plane.
std::int16_t planeLift(Encoder& e, const BrickBox& box, const std::uint32_t brick[3], std::uint64_t entry) {
  const GridGeometry& g = e.grid;
  const Vec3f n = entryPlaneNormal(entry), c = tileCentre(e, brick);
  const float d_c = entryPlaneDistance(entry);
  const auto plane = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return d_c + dot(n, g.voxelCentre(i, j, k) - c);
  };
  double sum = 0.0;
  std::size_t count = 0;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (!inBand(e, v)) return;
    sum += double(voxelLift(e.accurate[v], plane(i, j, k), g.band));
    ++count;
  });
  const auto code = std::int16_t(std::lround(sum / double(count)));
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (!inBand(e, v)) return;
    e.stats.max_lifted_error_voxels =
        std::max(e.stats.max_lifted_error_voxels, liftedError(e.accurate[v], plane(i, j, k), code, g));
  });
  return code;
}

// The value a voxel's word must not exceed: its distance lowered by the tilt its quantized normal
// adds over the cell (far voxels keep +-band, which decodes exactly).
float conservativeTarget(const Encoder& e, std::size_t v, Vec3f quantized_normal) {
  const float band = e.grid.band;
  if (!inBand(e, v)) return clampToBand(e.distance[v], band);
  const float allowance = tiltAllowance(quantized_normal, normalizeOrZero(e.normal[v]), e.grid.voxel_size);
  return clampToBand(e.distance[v] - allowance, band);
}

// The largest code whose decoded distance does not exceed `target`, for band voxels near or above
// zero; the nearest code for the others (far voxels, and values safely below zero, which only have to
// stay negative: a plane proves nothing where it reads below zero).
std::uint32_t distanceCode(float target, bool in_band, float lo, float hi, float step) {
  if (!in_band && target >= hi) return kWordDistanceMax;
  const bool round_down = in_band && target >= -2.0f * step;
  const float raw = step > 0.0f ? (target - lo) / step : 0.0f;
  auto code = std::uint32_t(std::clamp(round_down ? std::floor(raw) : std::round(raw), 0.0f, float(kWordDistanceMax)));
  while (round_down && code > 0 && wordDistance(packWord(0, 0, code), lo, hi, step) > target)
    --code;
  return code;
}

// Quantized brick: the range [lo, hi] is rounded outwards to 16 bits, then each voxel to 10 bits,
// downwards for band voxels so the decoded plane never rises above the input plane in the cell.
std::uint64_t writeBrick(Encoder& e, const BrickBox& box) {
  const float band = e.grid.band;
  std::vector<std::uint32_t>& normals = e.quantized;
  std::vector<float>& targets = e.target;
  float lo = band, hi = -band;
  forEachVoxel(box, [&](std::uint32_t, std::uint32_t, std::uint32_t, std::size_t v) {
    std::uint32_t qu = 0, qv = 0;
    octEncode(e.normal[v], kWordOctBits, &qu, &qv);
    normals[v] = packWord(qu, qv, 0);
    targets[v] = conservativeTarget(e, v, wordNormal(normals[v]));
    lo = std::min(lo, targets[v]);
    hi = std::max(hi, targets[v]);
  });
  const float to_q16 = float(kRangeMax) / (2.0f * band);
  const auto lo16 = std::uint32_t(std::clamp(std::floor((lo + band) * to_q16), 0.0f, float(kRangeMax)));
  const auto hi16 = std::uint32_t(std::clamp(std::ceil((hi + band) * to_q16), float(lo16), float(kRangeMax)));
  const float lo_value = rangeValue(lo16, band);
  const float hi_value = rangeValue(hi16, band);
  const float step = brickDistanceStep(lo_value, hi_value);

  const std::size_t base = e.pool.size();
  const std::uint32_t pool_index = std::uint32_t(base >> (3 * e.log2));
  e.pool.resize(base + (std::size_t(1) << (3 * e.log2)), 0u);
  if (e.lifted) e.lift_pool.resize(e.pool.size(), 0);
  for (WordNormals* words : {&e.gradient, &e.shading})
    if (words->present) words->pool.resize(e.pool.size(), 0);
  const std::uint32_t mask = e.size - 1;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    const std::uint32_t qd = distanceCode(targets[v], inBand(e, v), lo_value, hi_value, step);
    const std::uint32_t word = normals[v] | qd << (2 * kWordOctBits);
    const std::size_t local = ((k & mask) << (2 * e.log2)) | ((j & mask) << e.log2) | (i & mask);
    e.pool[base + local] = word;
    const float decoded = wordDistance(word, lo_value, hi_value, step);
    if (inBand(e, v)) measure(e, v, decoded, wordNormal(word));
    if (e.lifted) e.lift_pool[base + local] = lift(e, v, decoded);
    for (WordNormals* words : {&e.gradient, &e.shading})
      if (words->present) words->pool[base + local] = gradientWord(words->brick[v]);
  });
  return packBrickEntry(pool_index, lo16, hi16);
}

// A pair's raise counts from the voxel's first plane as read; the reader adds it to the stored plane,
// which may rise over the read one somewhere in the cell (a brick word rounds to the nearest code), so
// the raise gives up that rise, and a rounding slack, down to 0. Not a pair (negative or not a number):
// unchanged.
float storedRaise(const Encoder& e, std::size_t v) {
  const SecondPlanes& second = e.second;
  if (!(second.raise[v] >= 0.0f)) return second.raise[v];
  const float rise = second.stored_distance[v] - e.distance[v] +
                     tiltAllowance(second.stored_normal[v], normalizeOrZero(e.normal[v]), e.grid.voxel_size) +
                     kRoundingSlack * 4.0f * e.grid.band;
  return std::max(0.0f, second.raise[v] - std::max(0.0f, rise));
}

// The tile's block of second planes, when any of its band voxels has one: the block's index (counted
// from the layer's first), its mask and its planes in voxel order; kNoSecondPlanes otherwise.
std::uint32_t writeSecondPlanes(Encoder& e, const BrickBox& box, const VoxelBox& read) {
  SecondPlanes& second = e.second;
  e.source.readSecondPlanes(read, second.distance.data(), second.normal.data(), second.raise.data());
  std::vector<std::uint64_t>& by_voxel = second.by_voxel;
  std::fill(by_voxel.begin(), by_voxel.end(), 0u);
  const std::uint32_t mask = e.size - 1;
  bool any = false;
  forEachVoxel(box, [&](std::uint32_t i, std::uint32_t j, std::uint32_t k, std::size_t v) {
    if (!inBand(e, v) || !std::isfinite(second.distance[v])) return;
    const float raise = storedRaise(e, v);
    if (raise == 0.0f) return; // a pair the stored plane leaves nothing to raise
    const std::uint64_t word = secondPlaneRecord(
        secondPlaneWord(normalizeOrZero(second.normal[v]), second.distance[v], e.grid.band, e.grid.voxel_size), raise,
        e.grid.band);
    by_voxel[((k & mask) << (2 * e.log2)) | ((j & mask) << e.log2) | (i & mask)] = word;
    any = any || hasSecondPlane(word);
  });
  if (!any) return kNoSecondPlanes;
  const std::size_t first_mask = second.masks.size();
  second.masks.resize(first_mask + secondPlaneMaskWords(e.log2), 0u);
  for (std::size_t local = 0; local < by_voxel.size(); ++local) {
    if (!hasSecondPlane(by_voxel[local])) continue;
    second.masks[first_mask + local / 64] |= std::uint64_t(1) << (local % 64);
    second.words.push_back(by_voxel[local]);
  }
  ++e.stats.second_plane_blocks;
  return std::uint32_t(first_mask / secondPlaneMaskWords(e.log2));
}

// Encodes one brick (reading it unless the source hints it is far); false, with *error set, when a
// voxel is not finite.
bool encodeTile(Encoder& e, const std::uint32_t brick[3], std::string* error) {
  BrickBox box;
  VoxelBox read;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = read.lo[a] = brick[a] * e.size;
    box.hi[a] = read.hi[a] = std::min(box.lo[a] + e.size, e.grid.dims[a]);
  }
  std::uint64_t entry = 0;
  std::int16_t tile_lift = 0; // far tiles and bricks lift nothing at the tile level
  const FarHint hint = e.source.farHint(read);
  if (hint != FarHint::kUnknown) {
    entry = packFarEntry(hint == FarHint::kFarOutside ? TileKind::kFarOutside : TileKind::kFarInside);
  } else {
    e.source.read(read, e.distance.data(), e.normal.data());
    if (!(*error = checkVoxels(read, e.distance.data(), e.normal.data())).empty()) return false;
    if (e.lifted) e.source.readAccurate(read, e.accurate.data());
    if (e.lifted && !(*error = checkAccurate(read, e.accurate.data())).empty()) return false;
    if (e.gradient.present) e.source.readGradient(read, e.gradient.brick.data());
    if (e.shading.present) e.source.readShading(read, e.shading.brick.data());
    for (std::size_t v = 0; v < read.count(); ++v)
      e.stats.band_voxels += inBand(e, v) ? 1 : 0;
    if (!tryFarTile(e, box, &entry)) {
      if (tryPlaneTile(e, box, brick, &entry)) {
        ++e.stats.tiles.plane;
        tile_lift = e.lifted ? planeLift(e, box, brick, entry) : 0;
      } else {
        entry = writeBrick(e, box);
        ++e.stats.tiles.brick;
      }
    }
  }
  const TileKind kind = entryKind(entry);
  if (kind == TileKind::kFarOutside) ++e.stats.tiles.far_outside;
  if (kind == TileKind::kFarInside) ++e.stats.tiles.far_inside;
  e.top.push_back(entry);
  if (e.lifted) e.lift_top.push_back(tile_lift);
  if (e.second.present)
    e.second.slots.push_back(kind == TileKind::kPlane || kind == TileKind::kBrick ? writeSecondPlanes(e, box, read)
                                                                                  : kNoSecondPlanes);
  return true;
}

std::string checkOptions(const BrickOptions& o) {
  if (o.brick_size != 4 && o.brick_size != 8 && o.brick_size != 16) return "brick size must be 4, 8 or 16";
  if (!(o.tolerance_distance >= 0.0f) || !std::isfinite(o.tolerance_distance))
    return "distance tolerance must be finite and >= 0";
  if (!(o.tolerance_normal_deg >= 0.0f) || !(o.tolerance_normal_deg <= 180.0f))
    return "normal tolerance must be between 0 and 180 degrees";
  return {};
}

Encoder makeEncoder(const FieldSource& source, const BrickOptions& options, std::uint32_t log2) {
  const std::size_t brick_voxels = std::size_t(1) << (3 * log2);
  Encoder e{source,
            source.grid(),
            log2,
            options.brick_size,
            options.tolerance_distance * source.grid().voxel_size,
            std::cos(options.tolerance_normal_deg / kDegrees),
            {},
            {},
            {},
            std::vector<float>(brick_voxels),
            std::vector<Vec3f>(brick_voxels),
            std::vector<std::uint32_t>(brick_voxels),
            std::vector<float>(brick_voxels),
            source.hasAccurate(),
            {},
            {},
            {},
            {},
            {},
            {}};
  if (e.lifted) e.accurate.resize(brick_voxels);
  e.gradient.present = source.hasGradient();
  e.shading.present = source.hasShading();
  e.second.present = source.hasSecondPlanes();
  if (e.second.present) {
    e.second.distance.resize(brick_voxels), e.second.normal.resize(brick_voxels), e.second.raise.resize(brick_voxels);
    e.second.stored_distance.resize(brick_voxels), e.second.stored_normal.resize(brick_voxels);
    e.second.by_voxel.resize(brick_voxels);
  }
  for (WordNormals* words : {&e.gradient, &e.shading})
    if (words->present) words->brick.resize(brick_voxels);
  return e;
}

// What one z layer of bricks encoded to; pool indices in `top` count from the layer's first brick.
struct Layer {
  std::vector<std::uint64_t> top;
  std::vector<std::uint32_t> pool;
  std::vector<std::int16_t> lift_top, lift_pool;          // empty without accurate distances
  std::vector<std::uint16_t> gradient_pool, shading_pool; // empty without those sections
  std::vector<std::uint32_t> second_slots;                // block indices count from the layer's first
  std::vector<std::uint64_t> second_masks, second_words;
  EncodeStats stats;
  std::string error;
};

void addStats(const EncodeStats& layer, EncodeStats* total) {
  total->tiles.far_outside += layer.tiles.far_outside;
  total->tiles.far_inside += layer.tiles.far_inside;
  total->tiles.plane += layer.tiles.plane;
  total->tiles.brick += layer.tiles.brick;
  total->band_voxels += layer.band_voxels;
  total->max_distance_error_voxels = std::max(total->max_distance_error_voxels, layer.max_distance_error_voxels);
  total->max_normal_error_deg = std::max(total->max_normal_error_deg, layer.max_normal_error_deg);
  total->max_lifted_error_voxels = std::max(total->max_lifted_error_voxels, layer.max_lifted_error_voxels);
  total->second_plane_blocks += layer.second_plane_blocks;
}

// The PLN2 payload (docs/FORMAT.md §5.5): header, masks, records, each mask word's first record, slots
// (the 64-bit arrays first, so that every array is aligned to its type); empty when no tile has a
// second plane.
std::vector<std::uint8_t> packSecondPlanes(const std::vector<std::uint32_t>& slots,
                                           const std::vector<std::uint64_t>& masks,
                                           const std::vector<std::uint64_t>& words, std::size_t mask_words) {
  if (words.empty()) return {};
  std::vector<std::uint32_t> first(masks.size());
  std::uint32_t running = 0;
  for (std::size_t m = 0; m < masks.size(); ++m) {
    first[m] = running;
    running += bitCount(masks[m]);
  }
  const SecondPlanesHeader header{std::uint32_t(masks.size() / mask_words), std::uint32_t(words.size())};
  std::vector<std::uint8_t> out;
  const auto append = [&out](const void* data, std::size_t bytes) {
    const auto* b = static_cast<const std::uint8_t*>(data);
    out.insert(out.end(), b, b + bytes);
  };
  append(&header, sizeof header);
  append(masks.data(), masks.size() * sizeof(std::uint64_t));
  append(words.data(), words.size() * sizeof(std::uint64_t));
  append(first.data(), first.size() * sizeof(std::uint32_t));
  append(slots.data(), slots.size() * sizeof(std::uint32_t));
  return out;
}

// Concatenates the layers in z order, moving each layer's pool indices past the bricks before it.
EncodeResult joinLayers(const GridSection& grid, std::vector<Layer> layers, std::string_view metadata_json) {
  EncodeResult result;
  std::vector<std::uint64_t> top;
  std::vector<std::uint32_t> pool;
  std::vector<std::int16_t> lift_top, lift_pool;
  std::vector<std::uint16_t> gradient_pool, shading_pool;
  std::vector<std::uint32_t> second_slots;
  std::vector<std::uint64_t> second_masks, second_words;
  const std::size_t mask_words = secondPlaneMaskWords(grid.brick_log2);
  for (Layer& layer : layers) {
    addStats(layer.stats, &result.stats);
    if (result.stats.tiles.brick >= kMaxPoolBricks) {
      result.fail(EncodeError::kTooLarge, "too many bricks for one file (the pool index has 30 bits)");
      return result;
    }
    const auto first_brick = std::uint32_t(pool.size() >> (3 * grid.brick_log2));
    for (std::uint64_t entry : layer.top)
      top.push_back(entryKind(entry) != TileKind::kBrick
                        ? entry
                        : packBrickEntry(entryPoolIndex(entry) + first_brick, entryLo16(entry), entryHi16(entry)));
    pool.insert(pool.end(), layer.pool.begin(), layer.pool.end());
    lift_top.insert(lift_top.end(), layer.lift_top.begin(), layer.lift_top.end());
    lift_pool.insert(lift_pool.end(), layer.lift_pool.begin(), layer.lift_pool.end());
    gradient_pool.insert(gradient_pool.end(), layer.gradient_pool.begin(), layer.gradient_pool.end());
    shading_pool.insert(shading_pool.end(), layer.shading_pool.begin(), layer.shading_pool.end());
    const auto first_block = std::uint32_t(second_masks.size() / mask_words);
    for (std::uint32_t slot : layer.second_slots)
      second_slots.push_back(slot == kNoSecondPlanes ? slot : slot + first_block);
    second_masks.insert(second_masks.end(), layer.second_masks.begin(), layer.second_masks.end());
    second_words.insert(second_words.end(), layer.second_words.begin(), layer.second_words.end());
    layer = Layer{}; // give the memory back as we go
  }
  ContainerBuilder builder;
  addCommonSections(builder, grid, metadata_json);
  builder.addSection(kTagBrickTop, kSectionRequired, top.data(), top.size() * sizeof(std::uint64_t));
  builder.addSection(kTagBrickPool, kSectionRequired, pool.data(), pool.size() * sizeof(std::uint32_t));
  // LIFT: the tiles' lifts, then the pool's, one array.
  lift_top.insert(lift_top.end(), lift_pool.begin(), lift_pool.end());
  if (!lift_top.empty()) builder.addSection(kTagLift, 0, lift_top.data(), lift_top.size() * sizeof(std::int16_t));
  if (!gradient_pool.empty())
    builder.addSection(kTagGradient, 0, gradient_pool.data(), gradient_pool.size() * sizeof(std::uint16_t));
  if (!shading_pool.empty())
    builder.addSection(kTagShading, 0, shading_pool.data(), shading_pool.size() * sizeof(std::uint16_t));
  const std::vector<std::uint8_t> second_planes =
      packSecondPlanes(second_slots, second_masks, second_words, mask_words);
  if (!second_planes.empty()) builder.addSection(kTagSecondPlanes, 0, second_planes.data(), second_planes.size());
  result.stats.second_planes = second_words.size();
  result.stats.payload_bytes = top.size() * sizeof(std::uint64_t) + pool.size() * sizeof(std::uint32_t) +
                               lift_top.size() * sizeof(std::int16_t) +
                               (gradient_pool.size() + shading_pool.size()) * sizeof(std::uint16_t) +
                               second_planes.size();
  result.bytes = builder.finish();
  return result;
}

} // namespace

EncodeResult encodeBricked(const FieldSource& source, const BrickOptions& options, std::string_view metadata_json,
                           const EncodeHooks& hooks) {
  EncodeResult result;
  const GridGeometry& g = source.grid();
  result.fail(EncodeError::kInvalidGeometry, checkGeometry(g));
  result.fail(EncodeError::kInvalidOptions, checkOptions(options));
  if (!result.ok()) return result;

  const std::uint32_t log2 = options.brick_size == 4 ? 2 : options.brick_size == 8 ? 3 : 4;
  GridSection grid = makeGridSection(g, Encoding::kBricked);
  grid.brick_log2 = log2;
  for (int a = 0; a < 3; ++a)
    grid.brick_dims[a] = (g.dims[a] + options.brick_size - 1) >> log2;
  grid.tolerance_distance = options.tolerance_distance;
  grid.tolerance_normal_deg = options.tolerance_normal_deg;

  // One piece per z layer of bricks, each with its own pool (indices from 0), joined in order below.
  std::vector<Layer> layers(grid.brick_dims[2]);
  const bool finished = runPieces(hooks, layers.size(), [&](std::size_t z) {
    Encoder e = makeEncoder(source, options, log2);
    std::uint32_t brick[3] = {0, 0, std::uint32_t(z)};
    for (brick[1] = 0; brick[1] < grid.brick_dims[1]; ++brick[1])
      for (brick[0] = 0; brick[0] < grid.brick_dims[0]; ++brick[0])
        if (!encodeTile(e, brick, &layers[z].error)) return;
    layers[z].top = std::move(e.top);
    layers[z].pool = std::move(e.pool);
    layers[z].lift_top = std::move(e.lift_top);
    layers[z].lift_pool = std::move(e.lift_pool);
    layers[z].gradient_pool = std::move(e.gradient.pool);
    layers[z].shading_pool = std::move(e.shading.pool);
    layers[z].second_slots = std::move(e.second.slots);
    layers[z].second_masks = std::move(e.second.masks);
    layers[z].second_words = std::move(e.second.words);
    layers[z].stats = e.stats;
  });
  if (!finished) result.fail(EncodeError::kCancelled, "cancelled");
  for (const Layer& layer : layers)
    result.fail(EncodeError::kInvalidField, layer.error); // the first bad layer, whatever the threads
  if (!result.ok()) return result;
  return joinLayers(grid, std::move(layers), metadata_json);
}

EncodeResult encodeBricked(const DenseField& field, const BrickOptions& options, std::string_view metadata_json) {
  EncodeResult result;
  result.fail(EncodeError::kInvalidField, checkField(field));
  return result.ok() ? encodeBricked(DenseSource(field), options, metadata_json) : result;
}

} // namespace format
} // namespace dng
