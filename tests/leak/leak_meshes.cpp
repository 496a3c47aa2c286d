#include "leak_meshes.h"

#include "stages.h"

#include <algorithm>
#include <cmath>

namespace dng {
namespace leak {

namespace {

void append(testing::Mesh& to, const testing::Mesh& from) {
  const auto base = std::uint32_t(to.vertices.size());
  to.vertices.insert(to.vertices.end(), from.vertices.begin(), from.vertices.end());
  for (const auto& t : from.triangles)
    to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// Rotates a mesh about the origin by `angle` radians about the unit `axis` (Rodrigues).
testing::Mesh rotated(testing::Mesh m, Vec3f axis, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  for (Vec3f& v : m.vertices)
    v = v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1.0f - c));
  return m;
}

testing::Mesh moved(testing::Mesh m, Vec3f offset) {
  for (Vec3f& v : m.vertices)
    v = v + offset;
  return m;
}

// A prism over a polygon in the xy plane (counter-clockwise), from z = -half to +half, with the caps
// triangulated by `cap` (indices into the polygon, counter-clockwise). Outward-facing when the polygon is.
testing::Mesh prism(const std::vector<std::array<float, 2>>& polygon,
                    const std::vector<std::array<std::uint32_t, 3>>& cap, float half) {
  testing::Mesh m;
  const auto n = std::uint32_t(polygon.size());
  for (const auto& p : polygon)
    m.vertices.push_back({p[0], p[1], -half});
  for (const auto& p : polygon)
    m.vertices.push_back({p[0], p[1], half});
  for (const auto& t : cap) {
    m.triangles.push_back({t[0], t[2], t[1]});             // bottom faces down
    m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n}); // top faces up
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({i, j, j + n});
    m.triangles.push_back({i, j + n, i + n});
  }
  return m;
}

testing::Mesh flipped(testing::Mesh m) {
  for (auto& t : m.triangles)
    std::swap(t[1], t[2]);
  return m;
}

} // namespace

void meshBounds(const LeakMesh& mesh, Vec3f* lo, Vec3f* hi) {
  *lo = {1e30f, 1e30f, 1e30f}, *hi = *lo * -1.0f;
  for (const Vec3f& v : mesh.mesh.vertices) {
    *lo = {std::min(lo->x, v.x), std::min(lo->y, v.y), std::min(lo->z, v.z)};
    *hi = {std::max(hi->x, v.x), std::max(hi->y, v.y), std::max(hi->z, v.z)};
  }
}

bool loadMeshFile(const std::string& path, const std::string& name, LeakMesh* out, std::string* out_error) {
  baker::TriangleSoup soup;
  const baker::BakeStatus status = baker::loadMesh(path, &soup);
  if (!status.ok()) {
    *out_error = path + ": " + status.message;
    return false;
  }
  const baker::MeshReport report = baker::checkMesh(soup);
  const Vec3f centre = (report.bounds_min + report.bounds_max) * 0.5f;
  out->name = name;
  out->closed = report.closed();
  out->mesh.vertices.clear();
  for (const Vec3f& v : soup.vertices)
    out->mesh.vertices.push_back(v - centre);
  out->mesh.triangles = soup.triangles;
  return true;
}

LeakMesh thinPlate() { return {"thin plate", testing::boxMesh({0, 0, 0}, {26.0f, 20.0f, 0.25f}), true}; }

LeakMesh concaveNotch() {
  // The L, with a vertex where the notch's wall meets the left side so the caps need no T-junction.
  const std::vector<std::array<float, 2>> l = {{-26, -26}, {26, -26}, {26, 0}, {0, 0}, {0, 26}, {-26, 26}, {-26, 0}};
  const std::vector<std::array<std::uint32_t, 3>> cap = {{0, 1, 2}, {0, 2, 3}, {0, 3, 6}, {6, 3, 4}, {6, 4, 5}};
  return {"concave notch", prism(l, cap, 16.0f), true};
}

LeakMesh rodsAndFins() {
  testing::Mesh m;
  const Vec3f tilt = normalizeOrZero({1.0f, 2.0f, 0.5f});
  append(m, moved(rotated(testing::boxMesh({0, 0, 0}, {0.3f, 0.3f, 22.0f}), tilt, 0.7f), {-14.0f, -12.0f, 0.0f}));
  append(m, moved(rotated(testing::boxMesh({0, 0, 0}, {22.0f, 0.3f, 0.3f}), {0, 0, 1}, 0.3f), {0.0f, 14.0f, 6.0f}));
  append(m, moved(rotated(testing::boxMesh({0, 0, 0}, {0.3f, 18.0f, 0.3f}), {1, 0, 0}, 0.5f), {14.0f, -6.0f, -8.0f}));
  append(m, moved(rotated(testing::boxMesh({0, 0, 0}, {0.2f, 9.0f, 9.0f}), tilt, 0.4f), {4.0f, -10.0f, 10.0f}));
  append(m, moved(rotated(testing::boxMesh({0, 0, 0}, {9.0f, 9.0f, 0.2f}), {0, 1, 0}, 0.35f), {-8.0f, 6.0f, -14.0f}));
  return {"rods and fins", m, true};
}

LeakMesh hollowBox() {
  testing::Mesh m = testing::boxMesh({0, 0, 0}, {26.0f, 20.0f, 16.0f});
  append(m, flipped(testing::boxMesh({0, 0, 0}, {25.0f, 19.0f, 15.0f}))); // the cavity faces inwards
  return {"hollow box", m, true};
}

LeakMesh closeFins() {
  testing::Mesh m;
  for (int i = -1; i <= 1; ++i)
    append(m, testing::boxMesh({0.0f, 0.0f, 3.5f * float(i)}, {26.0f, 20.0f, 0.75f}));
  return {"close fins", m, true};
}

} // namespace leak
} // namespace dng
