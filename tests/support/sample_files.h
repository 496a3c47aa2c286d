// Small, fully specified .dng files that several tests share, and byte-patching helpers.
#pragma once

#include "dng/format/layout.h"
#include "dng/format/writer.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace dng {
namespace testing {

/// 24^3 box field, brick size 4, band 2 voxels, with metadata. Holds every tile kind: far outside
/// (corners), far inside (core), plane (faces) and brick (edges).
std::vector<std::uint8_t> smallBrickedBox();
/// The same box with other META bytes (which need not be JSON, nor even UTF-8).
std::vector<std::uint8_t> smallBrickedBox(std::string_view metadata);
/// 6x5x4 dense tilted-plane field with metadata.
std::vector<std::uint8_t> smallDensePlane();
/// smallBrickedBox's field lowered in the band by 0.05 to 0.55 voxel, varying in space, as a
/// conservative-planes producer lowers it (inside it stops above -band), with the exact distances as
/// the accurate ones: encoded, it has a LIFT section.
format::DenseField loweredBoxField();
/// loweredBoxField() encoded as smallBrickedBox is, with metadata.
std::vector<std::uint8_t> smallBrickedBoxLifted();
/// Tilts every normal of `field` by up to about 25 degrees, varying smoothly in space, as a blur tilts
/// them, and keeps the untilted ones as the field's gradient: encoded, it has a GRAD section.
void blurNormalsKeepingTheGradient(format::DenseField* field);
/// loweredBoxField() with blurNormalsKeepingTheGradient, encoded as smallBrickedBox is, with metadata.
std::vector<std::uint8_t> smallBrickedBoxGraded();
/// `field`'s normals tilted as blurNormalsKeepingTheGradient tilts them, kept as its shading normals
/// (the normals stay): encoded, it has a SHAD section, as a 1.3 blurred bake has.
void addTiltedShading(format::DenseField* field);
/// loweredBoxField() with addTiltedShading, encoded as smallBrickedBox is, with metadata.
std::vector<std::uint8_t> smallBrickedBoxShaded();

/// Gives `field` (loweredBoxField or another lowered convex field) second bounds from each chosen band
/// voxel's plane before the lowering (its accurate distance and its normal), which bounds a convex
/// solid's distance everywhere: where (i + j + k) % 3 == 1 that plane alone; where it is 2 a pair, the
/// voxel's own plane raised back by its lowering and that plane a quarter of a voxel higher (so the
/// raised own plane is the smaller); none elsewhere, so blocks are sparse.
void addUnloweredSecondPlanes(format::DenseField* field);
/// loweredBoxField() with addUnloweredSecondPlanes, encoded as smallBrickedBox is, with metadata: a
/// PLN2 section.
std::vector<std::uint8_t> smallBrickedBoxSecondPlanes();

/// Byte offset of the table entry of the first section with `tag`, or 0 when absent.
std::size_t entryOffset(const std::vector<std::uint8_t>& bytes, std::uint32_t tag);
/// The table entry of the first section with `tag` (zeroed when absent).
format::SectionEntry entryOf(const std::vector<std::uint8_t>& bytes, std::uint32_t tag);

/// Overwrites the trivially copyable `value` at `offset`.
template <class T> void poke(std::vector<std::uint8_t>& bytes, std::size_t offset, const T& value) {
  std::memcpy(bytes.data() + offset, &value, sizeof value);
}
template <class T> T peek(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

/// Path of a golden file in the source tree.
std::string goldenPath(const char* name);
std::vector<std::uint8_t> readFileBytes(const std::string& path);
void writeFileBytes(const std::string& path, const std::vector<std::uint8_t>& bytes);

} // namespace testing
} // namespace dng
