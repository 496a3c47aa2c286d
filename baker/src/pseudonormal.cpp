// Sign by angle-weighted pseudonormals (J. A. Baerentzen & H. Aanaes, "Signed Distance Computation
// Using the Angle Weighted Pseudonormal", IEEE TVCG 11(3), 2005): for a closed manifold mesh, the
// point p is inside exactly when (p - c) . N < 0, where c is its closest surface point and N the
// pseudonormal of the feature c lies on: the face normal inside a face, the sum of the two face
// normals on an edge, the angle-weighted sum of the incident face normals at a vertex.
#include "stages.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>

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
  std::vector<Vec3f> edge; // 3 t + e: edge e of triangle t, from corner e to corner e + 1
};

PseudonormalSign::PseudonormalSign() : impl_(std::make_unique<Impl>()) {}
PseudonormalSign::~PseudonormalSign() = default;

namespace {

// Each edge's pseudonormal, the sum of the normals of the faces that share it (two in a closed manifold
// mesh), in triangle order, into every one of its slots: its half-edges sorted by edge, then by slot.
void sumEdgeNormals(const TriangleSoup& soup, const std::vector<Vec3f>& face, std::vector<Vec3f>* out) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> halves(3 * soup.triangles.size());
  tbb::parallel_for(std::size_t(0), soup.triangles.size(), [&](std::size_t t) {
    const auto& tri = soup.triangles[t];
    for (std::size_t e = 0; e < 3; ++e)
      halves[3 * t + e] = {edgeKey(tri[e], tri[(e + 1) % 3]), std::uint32_t(3 * t + e)};
  });
  tbb::parallel_sort(halves.begin(), halves.end());
  out->assign(halves.size(), Vec3f{});
  for (std::size_t first = 0; first < halves.size();) {
    std::size_t last = first;
    Vec3f sum;
    for (; last < halves.size() && halves[last].first == halves[first].first; ++last)
      sum = sum + face[halves[last].second / 3];
    for (std::size_t k = first; k < last; ++k)
      (*out)[halves[k].second] = sum;
    first = last;
  }
}

} // namespace

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
  const std::size_t count = soup.triangles.size();
  impl_->face.resize(count);
  // The faces' normals and corner angles in parallel; each vertex's sum then in triangle order, so its
  // bits do not depend on the threads.
  std::vector<std::array<float, 3>> angles(count);
  tbb::parallel_for(std::size_t(0), count, [&](std::size_t t) {
    const auto& tri = soup.triangles[t];
    const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
    impl_->face[t] = normalizeOrZero(cross(b - a, c - a));
    angles[t] = {cornerAngle(a, b, c), cornerAngle(b, c, a), cornerAngle(c, a, b)};
  });
  impl_->vertex.assign(soup.vertices.size(), Vec3f{});
  for (std::size_t t = 0; t < count; ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      Vec3f& sum = impl_->vertex[soup.triangles[t][k]];
      sum = sum + impl_->face[t] * angles[t][k];
    }
  sumEdgeNormals(soup, impl_->face, &impl_->edge);
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
                           ? impl_->edge[3 * std::size_t(triangle) + std::size_t((on_edge_opposite + 1) % 3)]
                           : impl_->face[triangle];
  return dot(p - closest, pseudo) < 0.0f;
}

} // namespace baker
} // namespace dng
