// Triangle against axis-aligned cube, for the band's blocks (distance_field.cpp) and the surface
// voxels of the blurred modes (normal_modes.cpp).
#pragma once

#include "dng/format/vec3.h"

namespace dng {
namespace baker {

/// Whether triangle (a, b, c) touches the cube of centre `centre` and half edge `half`: the 13
/// separating axes of Akenine-Moeller, "Fast 3D Triangle-Box Overlap Testing", 2001. Touching counts.
bool triangleOverlapsBox(Vec3f a, Vec3f b, Vec3f c, Vec3f centre, float half);

} // namespace baker
} // namespace dng
