// Internal: the decoded layout of a validated View, for the SIMD batch kernels, which decode voxels
// lane by lane exactly as View's own scalar queries do (view_sample.cpp).
#pragma once

#include "dng/view.h"

namespace dng {

struct ViewInternals {
  static float invVoxelSize(const View& v) { return v.inv_voxel_size_; }
  static const float* dimsF(const View& v) { return v.dims_f_; }
  static float rangeStep(const View& v) { return v.range_step_; }
  static std::uint32_t brickLog2(const View& v) { return v.brick_log2_; }
  static const format::DenseVoxel* dense(const View& v) { return v.dense_; }
  static const std::uint64_t* top(const View& v) { return v.top_; }
  static const std::uint32_t* pool(const View& v) { return v.pool_; }
  static const std::int16_t* lift(const View& v) { return v.lift_; }
  static const std::int16_t* liftPool(const View& v) { return v.lift_pool_; }
  static float liftStep(const View& v) { return v.lift_step_; }
  static const std::uint16_t* gradient(const View& v) { return v.gradient_; }
  static const std::uint16_t* shading(const View& v) { return v.shading_; }
  /// View::sample(p) (nearest) with the plane's normal in place of a shading one: the step's walk
  /// reads the planes the bake made conservative (docs/FORMAT.md §5.4). `out_shading`, when not null,
  /// gets the normal sample(p) would give: what the responses read; null (the walk) skips SHAD.
  static Sample planeSample(const View& v, Vec3f p, Vec3f* out_shading = nullptr) {
    return v.planeSample(p, out_shading);
  }
  /// The walk's second look at p (docs/FORMAT.md §5.5): `first` (planeSample(p)'s answer, in band)
  /// unless p's voxel has a second bound (PLN2) that reads higher at p. A plane alone: that plane's
  /// sample, its distance refined at p as the first's is, its normal and the status its distance gives.
  /// A pair: the smaller of the first plane raised and the second plane, with the smaller one's
  /// normal, and in *out_other the other plane (its distance at p and normal), which stays above it.
  struct OtherPlane {
    bool present = false;
    float distance = 0.0f;
    Vec3f normal;
  };
  static Sample secondBound(const View& v, Vec3f p, const Sample& first, OtherPlane* out_other) {
    *out_other = OtherPlane{};
    return v.secondBound(p, first, &out_other->present, &out_other->distance, &out_other->normal);
  }
  static bool hasSecondPlanesFast(const View& v) { return v.second_slots_ != nullptr; }
};

} // namespace dng
