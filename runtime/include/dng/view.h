// dng::View: a validated, read-only window onto the bytes of a .dng file, and the field queries.
//
// A View does not own memory. Create it with View::open() over bytes that stay alive and unchanged
// for as long as the View is used (dng::File owns a mapped file and hands out its View). Opening
// validates the whole structure once (docs/FORMAT.md §6): for a bricked file in time proportional
// to its top table (every tile entry is checked), for a dense file to its voxel count (every voxel is
// checked for finiteness). After that every query is const, thread-safe, allocation-free and defined for every input.
#pragma once

#include "dng/format/dense_field.h"
#include "dng/format/layout.h"
#include "dng/format/limits.h"
#include "dng/format/vec3.h"
#include "dng/status.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace dng {

/// What a query found at a point.
enum class SampleStatus : std::uint32_t {
  kNoField = 0,    ///< outside the grid, or a NaN/infinite coordinate: distance = +inf, normal = 0
  kFarOutside = 1, ///< distance >= band: distance is that value (band on far tiles), normal = 0
  kFarInside = 2,  ///< distance <= -band: as above, negative
  kInBand = 3,     ///< |distance| < band: signed distance and unit normal
};

enum class Interpolation : std::uint32_t {
  /// The containing voxel, its distance refined by its own plane (paper §3.1); the normal is the
  /// voxel's shading normal (SHAD section) where the file has one, else its plane's.
  kNearest = 0,
  /// Trilinear blend of the eight surrounding voxel centres (shading normals where the file has them),
  /// normal renormalized.
  kTrilinear = 1,
  /// The closest to the true distance and normal (docs/RUNTIME.md, "Accurate queries"): the eight
  /// surrounding voxels' distances, lifted back from the conservative lowering when the file has a LIFT
  /// section, each corrected by half its plane's slope towards p (the distance's own gradient from a
  /// GRAD section when the stored normals are blurred), blended trilinearly; the normal is the
  /// normalized gradient of that blend. Second-order accurate where the surface is smooth. Not a bound:
  /// the step never uses it. About 3x the cost of kTrilinear.
  kAccurate = 2,
};

/// Result of one query. 20 bytes, trivially copyable.
struct Sample {
  float distance = 0.0f;
  Vec3f normal;
  SampleStatus status = SampleStatus::kNoField;
};

/// The GRID section as decoded: the placement the writer was given (format::GridGeometry: origin, voxel
/// size, dims, band, the same type and helpers) plus what the encoding added. The writer's input stays
/// encoding-free because the encoding and its brick options are chosen per encode (BrickOptions).
struct GridInfo : format::GridGeometry {
  format::Encoding encoding = format::Encoding::kDense;
  std::uint32_t brick_size = 0; ///< 0 for dense
  std::uint32_t brick_dims[3] = {};
  float tolerance_distance = 0.0f;   ///< bricked: voxels
  float tolerance_normal_deg = 0.0f; ///< bricked: degrees
  std::uint32_t flags = 0;           ///< format::kGridFlag* bits (1.1 files; 0 in 1.0 files)
};

/// Tile counts of a bricked file (all zero for dense), counted once at open: the encoder's type.
using TileCounts = format::TileCounts;

class View {
public:
  View() = default; ///< An empty view: valid() is false and every sample is kNoField.

  /// Validates `size` bytes at `data` and, on success, points `*out_view` at them. `data` must be
  /// 8-byte aligned (mmap and operator new are). Safe on any untrusted bytes: on failure returns the
  /// status, leaves `*out_view` empty and, if `out_diag` is not null, fills it. Never throws.
  static Status open(const void* data, std::size_t size, View* out_view, Diagnostic* out_diag = nullptr);

  bool valid() const { return data_ != nullptr; }

  /// Field at `p` (grid-local frame). Defined for every input, including NaN and infinities.
  Sample sample(Vec3f p, Interpolation mode = Interpolation::kNearest) const;

  /// What stepParticles' walk can prove at `p`: the voxel's plane, or its second bound where the file
  /// has one (PLN2: a second plane, or a pair of planes) and it reads higher, with the normal of the
  /// plane that gives the value (not the shading normal). In a file
  /// with conservative planes its distance, capped at guaranteedReach(), is at most the true distance
  /// wherever it is >= 0 (docs/FORMAT.md §5.1, §5.5), and a particle the walk is to move must be at a
  /// point where it reads at least a hundredth of a voxel (docs/RUNTIME.md, "Limits"): a spawner can
  /// ask here. Status as sample()'s. Defined for every input.
  Sample lowerBound(Vec3f p) const;

  /// Samples `count` points: point n is three floats at byte offset n * point_stride_bytes from
  /// `points` (stride >= 12; 12 for packed xyz). Writes out_samples[0..count). No allocation.
  void sampleBatch(const float* points, std::size_t point_stride_bytes, std::size_t count, Sample* out_samples,
                   Interpolation mode = Interpolation::kNearest) const;

  /// Recomputes every section's hash and compares with the table: the full check, O(file size).
  /// Separate from open() on purpose; nothing in a file can switch it off.
  Status verifyHashes(Diagnostic* out_diag = nullptr) const;

  /// Distance from the surface (local units) within which nearest queries are guaranteed to answer
  /// kInBand with a normal: band - sqrt(3)/2 * voxel_size, because a point belongs to its voxel and
  /// the voxel counts as far when its centre is. A particle system's design speed is this reach / dt.
  float guaranteedReach() const { return format::guaranteedReach(grid_.band, grid_.voxel_size); }

  const GridInfo& grid() const { return grid_; }
  /// True when the file promises that every plane bounds the true distance from below over its cell
  /// (format::kGridFlagConservativePlanes): what makes stepParticles' walk leak-free.
  bool conservativePlanes() const { return (grid_.flags & format::kGridFlagConservativePlanes) != 0; }
  /// True when the file carries a LIFT section (format 1.2): kAccurate queries then read the distances
  /// from before the conservative lowering; without it they read the stored values.
  bool hasLift() const { return lift_ != nullptr; }
  /// True when the file carries a GRAD section (format 1.2): the distance's own gradient beside blurred
  /// normals, which kAccurate queries use in place of the stored normals.
  bool hasGradient() const { return gradient_ != nullptr; }
  /// True when the file carries a SHAD section (format 1.3): the planes are the distance's own and
  /// the normals of the bake's mode (blurred, potential) sit beside them. kNearest and kTrilinear
  /// queries, and stepParticles' responses, read these; the step's walk trusts the planes.
  bool hasShading() const { return shading_ != nullptr; }
  /// True when the file carries a PLN2 section (format 1.3): second conservative planes beside edges,
  /// which stepParticles' walk reads where a voxel's own plane cannot prove a particle's way clear.
  /// Queries never read them.
  bool hasSecondPlanes() const { return second_slots_ != nullptr; }
  /// How many voxels have a second bound (0 without a PLN2 section).
  std::uint32_t secondPlaneCount() const { return second_count_; }
  const TileCounts& tileCounts() const { return tiles_; }
  std::uint16_t versionMajor() const { return version_major_; }
  std::uint16_t versionMinor() const { return version_minor_; }
  std::size_t sizeBytes() const { return size_; }
  const std::uint8_t* data() const { return data_; }
  /// The META section's UTF-8 JSON, or empty when the file has none. Not NUL-terminated.
  std::string_view metadata() const { return metadata_; }

private:
  friend class ViewBuilder;    // validation lives in view_open.cpp
  friend struct ViewInternals; // the SIMD batch kernels read the decoded layout (view_internals.h)
  struct VoxelValue {
    float distance;
    Vec3f normal;  ///< the plane's
    Vec3f shading; ///< SHAD's where the file has one (plane tiles: the plane's), else the plane's
  };
  // Query helpers, defined (and inlined) in view_sample.cpp, specialised per encoding.
  // nearest answers with the plane's normal, what the step's walk reads (ViewInternals::planeSample),
  // and writes the shading normal (zero unless in band), which sample() answers with, unless
  // `out_shading` is null: the walk's samples then skip SHAD's load and decode.
  template <format::Encoding kEncoding> Sample nearest(Vec3f p, Vec3f* out_shading) const;
  template <format::Encoding kEncoding> Sample nearestShaded(Vec3f p) const;
  Sample planeSample(Vec3f p, Vec3f* out_shading) const; // out_shading may be null
  Sample secondBound(Vec3f p, const Sample& first, bool* out_pair, float* out_other_distance,
                     Vec3f* out_other_normal) const;
  std::uint64_t secondPlaneRecord(std::size_t tile, std::uint32_t local) const;
  template <format::Encoding kEncoding> Sample trilinear(Vec3f p) const;
  template <format::Encoding kEncoding> Sample accurate(Vec3f p) const;
  // `with_shading` false leaves VoxelValue::shading the plane's normal.
  template <format::Encoding kEncoding>
  VoxelValue voxelValue(std::uint32_t i, std::uint32_t j, std::uint32_t k, bool with_shading = true) const;
  VoxelValue brickedValue(std::uint64_t entry, std::uint32_t i, std::uint32_t j, std::uint32_t k,
                          bool with_shading = true) const;
  struct AccurateValue {
    float distance;
    Vec3f normal;
    bool in_band; ///< of the stored value, before any lift
  };
  template <format::Encoding kEncoding>
  AccurateValue accurateValue(std::uint32_t i, std::uint32_t j, std::uint32_t k) const;
  bool toVoxelUnits(Vec3f p, float out_u[3]) const;
  Sample finish(float distance, Vec3f normal) const;

  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  GridInfo grid_;
  TileCounts tiles_;
  std::uint16_t version_major_ = 0;
  std::uint16_t version_minor_ = 0;
  std::string_view metadata_;
  // Derived at open for the query path.
  float inv_voxel_size_ = 0.0f;
  float dims_f_[3] = {};
  float range_step_ = 0.0f; // format::rangeStep(band), for brick distance ranges
  std::uint32_t brick_log2_ = 0;
  const format::DenseVoxel* dense_ = nullptr;
  const std::uint64_t* top_ = nullptr;
  const std::uint32_t* pool_ = nullptr;
  const std::int16_t* lift_ = nullptr;            // LIFT: per voxel (dense) or per tile (bricked)
  const std::int16_t* lift_pool_ = nullptr;       // bricked: per pool word, after the tiles' lifts
  float lift_step_ = 0.0f;                        // format::liftStep(band)
  const std::uint16_t* gradient_ = nullptr;       // GRAD: per voxel (dense) or per pool word (bricked)
  const std::uint16_t* shading_ = nullptr;        // SHAD: the same
  const std::uint32_t* second_slots_ = nullptr;   // PLN2 (bricked): per tile, its block or none
  const std::uint64_t* second_masks_ = nullptr;   // PLN2: per block, which voxels have a plane
  const std::uint32_t* second_first_ = nullptr;   // PLN2: per mask word, the index of its first plane
  const std::uint64_t* second_records_ = nullptr; // PLN2: the second bounds
  std::uint32_t second_mask_words_ = 0;           // per block: format::secondPlaneMaskWords
  std::uint32_t second_count_ = 0;                // planes in all
  float second_step_ = 0.0f;                      // format::secondPlaneStep(band)
  float second_raise_step_ = 0.0f;                // format::secondPlaneRaiseStep(band)
};

} // namespace dng
