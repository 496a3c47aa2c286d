// Internal to the writer: helpers both encoders share.
#pragma once

#include "dng/format/codec.h"
#include "dng/format/limits.h"
#include "dng/format/writer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace dng {
namespace format {

/// Empty when every voxel of a read box is finite and within kMaxMagnitude, else which one is not.
std::string checkVoxels(const VoxelBox& box, const float* distance, const Vec3f* normal);

/// Empty when every accurate distance of a read box (FieldSource::readAccurate) is finite and within
/// kMaxMagnitude, else which voxel is not.
std::string checkAccurate(const VoxelBox& box, const float* accurate);

/// `d` clamped to [-band, band]: what a reader makes of a far value.
inline float clampToBand(float d, float band) { return std::min(std::max(d, -band), band); }

/// The lift that takes a voxel's decoded distance to its accurate one, both clamped to the band (a
/// reader never lifts a far voxel), as the LIFT section's code (docs/FORMAT.md §5.2).
inline std::int16_t voxelLift(float accurate, float decoded, float band) {
  return liftCode(clampToBand(accurate, band) - clampToBand(decoded, band), band);
}

/// The error a lift leaves, in voxels: how far decoded + lift lands from the accurate distance.
inline float liftedError(float accurate, float decoded, std::int16_t lift, const GridGeometry& g) {
  const float lifted = clampToBand(decoded, g.band) + float(lift) * liftStep(g.band);
  return std::fabs(lifted - clampToBand(accurate, g.band)) / g.voxel_size;
}

/// Runs piece(i) for i in [0, count) through hooks.parallel_for (or in order), reporting progress
/// after each piece, one report at a time. False when the progress callback asked to stop; pieces not
/// yet started are then skipped.
bool runPieces(const EncodeHooks& hooks, std::size_t count, const std::function<void(std::size_t)>& piece);

/// GRID section for `g` with the encoding-independent fields filled and the bricked ones zero.
GridSection makeGridSection(const GridGeometry& g, Encoding encoding);

/// Adds the required GRID section and, when `metadata_json` is not empty, the optional META one.
void addCommonSections(ContainerBuilder& builder, const GridSection& grid, std::string_view metadata_json);

} // namespace format
} // namespace dng
