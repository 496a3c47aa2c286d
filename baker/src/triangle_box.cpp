#include "triangle_box.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace baker {

bool triangleOverlapsBox(Vec3f a, Vec3f b, Vec3f c, Vec3f centre, float half) {
  const Vec3f v[3] = {a - centre, b - centre, c - centre};
  const Vec3f e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const Vec3f axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  auto separated = [&](Vec3f axis) {
    const float p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
    const float r = half * (std::fabs(axis.x) + std::fabs(axis.y) + std::fabs(axis.z));
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (const Vec3f& axis : axes) {
    if (separated(axis)) return false;
  }
  if (separated(cross(e[0], e[1]))) return false;
  for (const Vec3f& edge : e) {
    for (const Vec3f& axis : axes) {
      const Vec3f n = cross(edge, axis);
      if (dot(n, n) > 0.0f && separated(n)) return false;
    }
  }
  return true;
}

} // namespace baker
} // namespace dng
