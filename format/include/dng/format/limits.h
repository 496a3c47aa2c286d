// The format's numeric limits, in one place so that the writer and the reader can never disagree:
// the writer refuses to produce what the reader would refuse to open (docs/FORMAT.md §6, V12-V16).
#pragma once

#include <cstdint>

namespace dng {
namespace format {

/// Largest magnitude of any length or distance in a file. Far below FLT_MAX, so no sum or product a
/// query forms from validated values can overflow to infinity; voxel sizes must be at least its inverse.
inline constexpr float kMaxMagnitude = 1e18f;

/// Most voxels along one axis: positions are converted through float, which counts exactly to 2^24.
inline constexpr std::uint32_t kMaxAxisVoxels = 1u << 24;

/// Half the diagonal of a unit cube, sqrt(3)/2: how far a point can be from the centre of its voxel,
/// in voxels. A tile's half-diagonal is this times its edge.
inline constexpr float kHalfCubeDiagonal = 0.8660254f;

/// The guaranteed reach of a band `band` wide over voxels of `voxel_size` (docs/FORMAT.md §5.1): every
/// point of a far outside voxel's cell is at least this far from the surface, and no reader takes more
/// than this from a plane.
inline constexpr float guaranteedReach(float band, float voxel_size) { return band - kHalfCubeDiagonal * voxel_size; }

/// Dense normals are unit or zero; readers allow this much rounding slack in the squared length.
inline constexpr float kMaxNormalLengthSquared = 1.0001f;

} // namespace format
} // namespace dng
