// Sign by angle-weighted pseudonormals (J. A. Baerentzen & H. Aanaes, "Signed Distance Computation
// Using the Angle Weighted Pseudonormal", IEEE TVCG 11(3), 2005): for a closed manifold mesh, the
// point p is inside exactly when (p - c) . N < 0, where c is its closest surface point and N the
// pseudonormal of the feature c lies on: the face normal inside a face, the sum of the two face
// normals on an edge, the angle-weighted sum of the incident face normals at a vertex.
#include "stages.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace dng {
namespace baker {

namespace {

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b) { return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b); }

float cornerAngle(Vec3f at, Vec3f a, Vec3f b) { return float(angleDegrees(a - at, b - at) * 0.017453292519943295); }

} // namespace

struct PseudonormalSign::Impl {
  const TriangleSoup* soup = nullptr;
  std::vector<Vec3f> face;
  std::vector<Vec3f> vertex;
  std::map<std::uint64_t, Vec3f> edge;
};

PseudonormalSign::PseudonormalSign() : impl_(std::make_unique<Impl>()) {}
PseudonormalSign::~PseudonormalSign() = default;

BakeStatus PseudonormalSign::build(const TriangleSoup& soup, const MeshReport& report) {
  if (!report.wellFormedSolid())
    return BakeStatus::failure(BakeError::kInvalidInput,
                               "--sign pseudonormal needs a closed manifold mesh with outward faces; this one has " +
                                   std::to_string(report.boundary_edges) + " boundary, " +
                                   std::to_string(report.non_manifold_edges) + " non-manifold and " +
                                   std::to_string(report.misoriented_edges) + " misoriented edges and signed volume " +
                                   std::to_string(report.signed_volume) + ": use --sign winding");
  impl_ = std::make_unique<Impl>();
  impl_->soup = &soup;
  impl_->face.resize(soup.triangles.size());
  impl_->vertex.assign(soup.vertices.size(), Vec3f{});
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const auto& tri = soup.triangles[t];
    const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
    const Vec3f n = normalizeOrZero(cross(b - a, c - a));
    impl_->face[t] = n;
    impl_->vertex[tri[0]] = impl_->vertex[tri[0]] + n * cornerAngle(a, b, c);
    impl_->vertex[tri[1]] = impl_->vertex[tri[1]] + n * cornerAngle(b, c, a);
    impl_->vertex[tri[2]] = impl_->vertex[tri[2]] + n * cornerAngle(c, a, b);
    for (int e = 0; e < 3; ++e) {
      Vec3f& sum = impl_->edge[edgeKey(tri[e], tri[(e + 1) % 3])];
      sum = sum + n;
    }
  }
  return BakeStatus::success();
}

bool PseudonormalSign::inside(Vec3f p, Vec3f closest, std::uint32_t triangle) const {
  const TriangleSoup& soup = *impl_->soup;
  const auto& tri = soup.triangles[triangle];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  // Barycentric coordinates of the closest point: which feature it lies on.
  const Vec3f n = cross(b - a, c - a);
  const float area = dot(n, n);
  const float w[3] = {dot(cross(c - b, closest - b), n) / area, dot(cross(a - c, closest - c), n) / area,
                      dot(cross(b - a, closest - a), n) / area};
  constexpr float kOnFeature = 1e-4f;
  int at_vertex = -1, on_edge_opposite = -1;
  for (int v = 0; v < 3; ++v) {
    if (w[v] > 1.0f - kOnFeature) at_vertex = v;
    if (w[v] < kOnFeature) on_edge_opposite = v;
  }
  const Vec3f pseudo = at_vertex >= 0 ? impl_->vertex[tri[at_vertex]]
                       : on_edge_opposite >= 0
                           ? impl_->edge.at(edgeKey(tri[(on_edge_opposite + 1) % 3], tri[(on_edge_opposite + 2) % 3]))
                           : impl_->face[triangle];
  return dot(p - closest, pseudo) < 0.0f;
}

} // namespace baker
} // namespace dng
