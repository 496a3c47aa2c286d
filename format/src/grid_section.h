// Internal to the writer: helpers both encoders share.
#pragma once

#include "dng/format/limits.h"
#include "dng/format/writer.h"

#include <string>
#include <string_view>

namespace dng {
namespace format {

/// Empty when every voxel of a read box is finite and within kMaxMagnitude, else which one is not.
std::string checkVoxels(const VoxelBox& box, const float* distance, const Vec3f* normal);

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
