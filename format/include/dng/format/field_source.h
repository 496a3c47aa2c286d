// Where the encoders read voxels from. A dense array is one source; the baker's sparse OpenVDB band
// is another, which never holds every voxel of a large grid at once. Encoders ask for one box of
// voxels at a time (a brick, or a slab of rows), so neither side has to know the other's layout.
#pragma once

#include "dng/format/dense_field.h"

#include <cstdint>
#include <vector>

namespace dng {
namespace format {

/// Voxels [lo, hi) on every axis, inside the grid.
struct VoxelBox {
  std::uint32_t lo[3] = {0, 0, 0};
  std::uint32_t hi[3] = {0, 0, 0}; ///< exclusive
  std::size_t count() const { return std::size_t(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]); }
};

/// What a source knows about a box without reading it.
enum class FarHint {
  kUnknown,    ///< read the voxels to find out
  kFarOutside, ///< every voxel is at distance >= band
  kFarInside,  ///< every voxel is at distance <= -band
};

/// A DN field the encoders can read box by box. Implementations must return the same values for the
/// same box every time (the output is a pure function of them). Reads must be safe from several
/// threads at once only when the encoder is given EncodeHooks::parallel_for (writer.h).
class FieldSource {
public:
  virtual ~FieldSource() = default;
  virtual const GridGeometry& grid() const = 0;
  /// Writes box.count() distances and normals, x fastest, then y, then z. Normals of far voxels
  /// may be zero.
  virtual void read(const VoxelBox& box, float* distance, Vec3f* normal) const = 0;
  /// True when readAccurate() has values: the encoders then write a LIFT section (docs/FORMAT.md §5.2).
  virtual bool hasAccurate() const { return false; }
  /// Writes box.count() distances as they were before the producer lowered them into the values read()
  /// returns (conservative planes), x fastest. Called only when hasAccurate(); same threading as read().
  virtual void readAccurate(const VoxelBox& box, float* distance) const {
    (void)box;
    (void)distance;
  }
  /// True when readGradient() has values: the encoders then write a GRAD section (docs/FORMAT.md §5.3).
  virtual bool hasGradient() const { return false; }
  /// Writes box.count() unit normals of the distance itself (zero where unknown), for sources whose
  /// read() normals are not its gradient (blurred). Called only when hasGradient(); threading as read().
  virtual void readGradient(const VoxelBox& box, Vec3f* gradient) const {
    (void)box;
    (void)gradient;
  }
  /// True when readShading() has values: the encoders then write a SHAD section (docs/FORMAT.md §5.4).
  virtual bool hasShading() const { return false; }
  /// Writes box.count() unit normals of the field's mode (zero where unknown), for sources whose read()
  /// normals are the distance's gradient but whose users want others (blurred). Called only when
  /// hasShading(); threading as read().
  virtual void readShading(const VoxelBox& box, Vec3f* shading) const {
    (void)box;
    (void)shading;
  }
  /// True when readSecondPlanes() has values: the bricked encoder then writes a PLN2 section
  /// (docs/FORMAT.md §5.5).
  virtual bool hasSecondPlanes() const { return false; }
  /// Writes box.count() second bounds, x fastest (docs/FORMAT.md §5.5): each voxel's second plane, its
  /// distance at the voxel centre and unit normal (distance -infinity where the voxel has none), and
  /// `raise`: not a number (or negative) where the plane alone bounds the true distance from below over
  /// the voxel's cell, as read()'s plane does; else the smaller of the two, read()'s plane raised by
  /// `raise` and the second plane, is the bound (a pair, beside a concave crease). Called only when
  /// hasSecondPlanes(); threading as read().
  virtual void readSecondPlanes(const VoxelBox& box, float* distance, Vec3f* normal, float* raise) const {
    (void)box;
    (void)distance;
    (void)normal;
    (void)raise;
  }
  /// A shortcut for empty space: kUnknown unless the source knows the whole box is far on one side.
  /// A source may always answer kUnknown; a wrong answer other than kUnknown is a bug.
  virtual FarHint farHint(const VoxelBox& box) const {
    (void)box;
    return FarHint::kUnknown;
  }
};

/// A DenseField seen as a source. The field must outlive the adapter. Reads are thread-safe.
class DenseSource final : public FieldSource {
public:
  explicit DenseSource(const DenseField& field) : field_(field) {}
  const GridGeometry& grid() const override { return field_.grid; }
  void read(const VoxelBox& box, float* distance, Vec3f* normal) const override {
    copyBox(field_.distance, box, distance);
    copyBox(field_.normal, box, normal);
  }
  bool hasAccurate() const override { return !field_.accurate.empty(); }
  void readAccurate(const VoxelBox& box, float* distance) const override { copyBox(field_.accurate, box, distance); }
  bool hasGradient() const override { return !field_.gradient.empty(); }
  void readGradient(const VoxelBox& box, Vec3f* gradient) const override { copyBox(field_.gradient, box, gradient); }
  bool hasShading() const override { return !field_.shading.empty(); }
  void readShading(const VoxelBox& box, Vec3f* shading) const override { copyBox(field_.shading, box, shading); }
  bool hasSecondPlanes() const override { return !field_.second_distance.empty(); }
  void readSecondPlanes(const VoxelBox& box, float* distance, Vec3f* normal, float* raise) const override {
    copyBox(field_.second_distance, box, distance);
    copyBox(field_.second_normal, box, normal);
    copyBox(field_.second_raise, box, raise);
  }

private:
  // The box's entries of one per-voxel array, x fastest.
  template <class T> void copyBox(const std::vector<T>& values, const VoxelBox& box, T* out) const {
    for (std::uint32_t k = box.lo[2]; k < box.hi[2]; ++k)
      for (std::uint32_t j = box.lo[1]; j < box.hi[1]; ++j)
        for (std::uint32_t i = box.lo[0]; i < box.hi[0]; ++i)
          *out++ = values[field_.grid.index(i, j, k)];
  }

  const DenseField& field_;
};

} // namespace format
} // namespace dng
