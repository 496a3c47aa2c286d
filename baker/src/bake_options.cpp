// checkBakeOptions: every option value is checked here, before bake() loads anything, so a bad value
// costs nothing and is reported as what it is (a usage error naming the option), never as a failure
// of the stage that would first have tripped over it.
#include "dng/baker/bake.h"
#include "stages.h"

#include <cmath>
#include <string>

namespace dng {
namespace baker {

namespace {

BakeStatus bad(const std::string& message) { return BakeStatus::failure(BakeError::kBadOption, message); }

BakeStatus checkGridOptions(const BakeOptions& o) {
  if (!(o.voxel_size >= 0.0f) || !std::isfinite(o.voxel_size)) return bad("--voxel-size must be a positive number");
  if (o.voxel_size > 0.0f && o.voxel_size < kMinVoxelSize)
    return bad("--voxel-size must be at least " + shortNumber(kMinVoxelSize) +
               " (OpenVDB's smallest voxel): bake in smaller units (--units, --scale)");
  if (o.voxel_size == 0.0f && (o.resolution < kMinResolution || o.resolution > kMaxBakeAxisVoxels))
    return bad("--resolution must be between " + std::to_string(kMinResolution) + " and " +
               std::to_string(kMaxBakeAxisVoxels));
  if ((o.max_speed > 0.0f) != (o.dt > 0.0f) || !std::isfinite(o.max_speed) || !std::isfinite(o.dt) ||
      !(o.max_speed >= 0.0f) || !(o.dt >= 0.0f))
    return bad("--max-speed and --dt go together, both positive");
  if (!(o.band_voxels >= 1.0f) || !(o.band_voxels <= float(kMaxBakeAxisVoxels)))
    return bad("--band must be between 1 and " + std::to_string(kMaxBakeAxisVoxels) + " voxels");
  return BakeStatus::success();
}

BakeStatus checkNormalOptions(const BakeOptions& o) {
  if (o.mode != NormalMode::kNormalBlur && o.mode != NormalMode::kPotential && o.mode != NormalMode::kExact)
    return bad("--mode must be normal-blur, potential or exact");
  if (o.mode == NormalMode::kExact) return BakeStatus::success(); // the blur options are unused
  if (o.blur_radius < 1 || o.blur_radius > kMaxBlurRadius)
    return bad("--blur-radius must be between 1 and " + std::to_string(kMaxBlurRadius) + " (the paper uses 2-4)");
  if (o.blur_rounds > kMaxBlurRounds)
    return bad("--blur-rounds must be between 0 and " + std::to_string(kMaxBlurRounds));
  return BakeStatus::success();
}

BakeStatus checkEncodingOptions(const BakeOptions& o) {
  if (o.sign != SignMode::kAuto && o.sign != SignMode::kWinding && o.sign != SignMode::kPseudonormal)
    return bad("--sign must be auto, winding or pseudonormal");
  if (o.encoding != format::Encoding::kDense && o.encoding != format::Encoding::kBricked)
    return bad("--encoding must be bricked or dense");
  const format::BrickOptions& b = o.brick;
  if (b.brick_size != 4 && b.brick_size != 8 && b.brick_size != 16) return bad("--brick-size must be 4, 8 or 16");
  if (!(b.tolerance_distance >= 0.0f) || !std::isfinite(b.tolerance_distance))
    return bad("--tolerance must be a finite number of voxels >= 0");
  if (!(b.tolerance_normal_deg >= 0.0f) || !(b.tolerance_normal_deg <= 180.0f))
    return bad("the normal tolerance must be between 0 and 180 degrees");
  return BakeStatus::success();
}

} // namespace

BakeStatus checkBakeOptions(const BakeOptions& options) {
  BakeStatus status = checkGridOptions(options);
  if (status.ok()) status = checkNormalOptions(options);
  if (status.ok()) status = checkEncodingOptions(options);
  return status;
}

} // namespace baker
} // namespace dng
