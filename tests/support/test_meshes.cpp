#include "test_meshes.h"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace dng {
namespace testing {

namespace {

constexpr float kPi = 3.14159265358979f;

void quad(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  m.triangles.push_back({a, b, c});
  m.triangles.push_back({a, c, d});
}

float segmentDistance(Vec3f p, Vec3f a, Vec3f b) {
  const Vec3f ab = b - a;
  const float t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0f, 1.0f);
  return length(p - (a + ab * t));
}

} // namespace

// Projection onto the plane when it falls inside (barycentric signs), else the nearest edge.
float triangleDistance(Vec3f p, Vec3f a, Vec3f b, Vec3f c) {
  const Vec3f n = normalizeOrZero(cross(b - a, c - a));
  const Vec3f q = p - n * dot(p - a, n);
  const bool inside =
      dot(cross(b - a, q - a), n) >= 0.0f && dot(cross(c - b, q - b), n) >= 0.0f && dot(cross(a - c, q - c), n) >= 0.0f;
  if (inside && dot(n, n) > 0.0f) return std::fabs(dot(p - a, n));
  return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

Mesh boxMesh(Vec3f c, Vec3f h) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(c + Vec3f{i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z});
  quad(m, 0, 2, 3, 1); // -z
  quad(m, 4, 5, 7, 6); // +z
  quad(m, 0, 1, 5, 4); // -y
  quad(m, 2, 6, 7, 3); // +y
  quad(m, 0, 4, 6, 2); // -x
  quad(m, 1, 3, 7, 5); // +x
  return m;
}

Mesh lBlockMesh(Vec3f origin, float size, float depth) {
  // The outline counter-clockwise from above; the reflex corner (1, 1) fans the caps.
  const float outline[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  Mesh m;
  for (int level = 0; level < 2; ++level)
    for (const auto& xy : outline)
      m.vertices.push_back(origin + Vec3f{xy[0] * size, xy[1] * size, float(level) * depth * size});
  for (std::uint32_t e = 0; e < 6; ++e) // sides, outwards
    quad(m, e, (e + 1) % 6, 6 + (e + 1) % 6, 6 + e);
  const std::uint32_t fan[4][2] = {{4, 5}, {5, 0}, {0, 1}, {1, 2}};
  for (const auto& f : fan) {
    m.triangles.push_back({3, f[1], f[0]});         // bottom, facing -z
    m.triangles.push_back({9, 6 + f[0], 6 + f[1]}); // top, facing +z
  }
  return m;
}

Mesh sphereMesh(Vec3f c, float r, int slices, int stacks) {
  Mesh m;
  m.vertices.push_back(c + Vec3f{0, 0, r});
  for (int s = 1; s < stacks; ++s) {
    const float theta = kPi * float(s) / float(stacks);
    for (int k = 0; k < slices; ++k) {
      const float phi = 2.0f * kPi * float(k) / float(slices);
      m.vertices.push_back(
          c + Vec3f{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)} * r);
    }
  }
  m.vertices.push_back(c + Vec3f{0, 0, -r});
  const auto ring = [&](int s, int k) { return std::uint32_t(1 + (s - 1) * slices + (k % slices)); };
  const auto bottom = std::uint32_t(m.vertices.size() - 1);
  for (int k = 0; k < slices; ++k) {
    m.triangles.push_back({0, ring(1, k), ring(1, k + 1)});
    for (int s = 1; s + 1 < stacks; ++s)
      quad(m, ring(s, k), ring(s + 1, k), ring(s + 1, k + 1), ring(s, k + 1));
    m.triangles.push_back({bottom, ring(stacks - 1, k + 1), ring(stacks - 1, k)});
  }
  return m;
}

Mesh cylinderMesh(Vec3f c, float r, float hh, int segments) {
  Mesh m;
  for (int k = 0; k < segments; ++k) {
    const float phi = 2.0f * kPi * float(k) / float(segments);
    m.vertices.push_back(c + Vec3f{r * std::cos(phi), r * std::sin(phi), -hh});
    m.vertices.push_back(c + Vec3f{r * std::cos(phi), r * std::sin(phi), hh});
  }
  const auto bottom = std::uint32_t(m.vertices.size());
  m.vertices.push_back(c + Vec3f{0, 0, -hh});
  m.vertices.push_back(c + Vec3f{0, 0, hh});
  for (int k = 0; k < segments; ++k) {
    const auto a = std::uint32_t(2 * k), b = std::uint32_t(2 * ((k + 1) % segments));
    quad(m, a, b, b + 1, a + 1);
    m.triangles.push_back({bottom, b, a});
    m.triangles.push_back({bottom + 1, a + 1, b + 1});
  }
  return m;
}

Mesh torusMesh(Vec3f c, float major, float minor, int nu, int nv) {
  Mesh m;
  for (int u = 0; u < nu; ++u) {
    const float a = 2.0f * kPi * float(u) / float(nu);
    for (int v = 0; v < nv; ++v) {
      const float b = 2.0f * kPi * float(v) / float(nv);
      const float rr = major + minor * std::cos(b);
      m.vertices.push_back(c + Vec3f{rr * std::cos(a), rr * std::sin(a), minor * std::sin(b)});
    }
  }
  const auto at = [&](int u, int v) { return std::uint32_t((u % nu) * nv + (v % nv)); };
  for (int u = 0; u < nu; ++u)
    for (int v = 0; v < nv; ++v)
      quad(m, at(u, v), at(u + 1, v), at(u + 1, v + 1), at(u, v + 1));
  return m;
}

Mesh sheetMesh(Vec3f c, float h) {
  Mesh m;
  m.vertices = {c + Vec3f{-h, -h, 0}, c + Vec3f{h, -h, 0}, c + Vec3f{h, h, 0}, c + Vec3f{-h, h, 0}};
  quad(m, 0, 1, 2, 3);
  return m;
}

Mesh toSoup(const Mesh& mesh) {
  Mesh soup;
  for (const auto& t : mesh.triangles) {
    const auto base = std::uint32_t(soup.vertices.size());
    for (std::uint32_t v : t)
      soup.vertices.push_back(mesh.vertices[v]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  return soup;
}

Mesh withoutFace(const Mesh& box, int axis) {
  Mesh out = box;
  out.triangles.clear();
  for (const auto& t : box.triangles) {
    const Vec3f centroid = (box.vertices[t[0]] + box.vertices[t[1]] + box.vertices[t[2]]) * (1.0f / 3.0f);
    const float values[3] = {centroid.x, centroid.y, centroid.z};
    float top = -1e30f;
    for (const auto& v : box.vertices)
      top = std::max(top, component(v, axis));
    if (std::fabs(values[axis] - top) > 1e-5f) out.triangles.push_back(t);
  }
  return out;
}

void writeObj(const Mesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  for (const Vec3f& v : mesh.vertices)
    out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
  for (const auto& t : mesh.triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

float bruteDistance(const Mesh& mesh, Vec3f p) {
  float best = 1e30f;
  for (const auto& t : mesh.triangles)
    best = std::min(best, triangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  return best;
}

double bruteWinding(const Mesh& mesh, Vec3f p) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3f a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p, c = mesh.vertices[t[2]] - p;
    const double la = length(a), lb = length(b), lc = length(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * 3.14159265358979323846);
}

} // namespace testing
} // namespace dng
