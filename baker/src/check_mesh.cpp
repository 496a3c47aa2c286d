// Mesh diagnostics (docs/DESIGN.md §5.3): what the user should know about their mesh before baking, and
// whether it can be baked at all.
#include "stages.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace dng {
namespace baker {

namespace {

// Zero area, relative to the triangle's own size so that tiny but valid triangles still count: a
// sliver thinner than float's precision over its longest edge has no normal to speak of.
bool degenerate(const TriangleSoup& soup, const std::array<std::uint32_t, 3>& t) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const Vec3f a = soup.vertices[t[0]], b = soup.vertices[t[1]], c = soup.vertices[t[2]];
  const float longest = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
  return !(length(cross(b - a, c - a)) > 1e-7f * longest);
}

// Each vertex's first twin: the lowest index with exactly the same coordinates. Files often repeat a
// vertex where its normals or texture coordinates change (a seam); such a mesh is open by its indices
// but has no hole.
std::vector<std::uint32_t> firstTwins(const TriangleSoup& soup) {
  struct Key {
    std::uint32_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (std::size_t(k.x) * 73856093u) ^ (std::size_t(k.y) * 19349663u) ^ (std::size_t(k.z) * 83492791u);
    }
  };
  const auto bits = [](float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return f == 0.0f ? 0u : u; // -0 and +0 are one position
  };
  std::unordered_map<Key, std::uint32_t, Hash> first;
  first.reserve(soup.vertices.size());
  std::vector<std::uint32_t> twin(soup.vertices.size());
  for (std::uint32_t v = 0; v < soup.vertices.size(); ++v) {
    const Vec3f p = soup.vertices[v];
    twin[v] = first.emplace(Key{bits(p.x), bits(p.y), bits(p.z)}, v).first->second;
  }
  return twin;
}

struct EdgeCounts {
  std::uint64_t once = 0, three_or_more = 0, same_direction = 0;
};

// Counts edges, with vertex v named name(v) (its index, or its first twin's), used once (boundary),
// three or more times (non-manifold), and twice in the same direction (the two faces disagree about
// which side is out).
template <class Name> EdgeCounts countEdges(const TriangleSoup& soup, Name&& name) {
  struct Edge {
    std::uint32_t lo, hi;
    bool forward; // runs lo -> hi in its triangle
    bool operator<(const Edge& o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
  };
  std::vector<Edge> edges;
  edges.reserve(soup.triangles.size() * 3);
  for (const auto& t : soup.triangles) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = name(t[e]), b = name(t[(e + 1) % 3]);
      if (a != b) edges.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  }
  std::sort(edges.begin(), edges.end());
  EdgeCounts counts;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi)
      ++j;
    counts.once += j - i == 1 ? 1 : 0;
    counts.three_or_more += j - i >= 3 ? 1 : 0;
    counts.same_direction += j - i == 2 && edges[i].forward == edges[i + 1].forward ? 1 : 0;
    i = j;
  }
  return counts;
}

// Divergence theorem: the tetrahedra each triangle forms with the origin, summed.
double signedVolume(const TriangleSoup& soup) {
  double volume = 0.0;
  for (const auto& t : soup.triangles) {
    const Vec3f a = soup.vertices[t[0]], b = soup.vertices[t[1]], c = soup.vertices[t[2]];
    volume += double(dot(a, cross(b, c))) / 6.0;
  }
  return volume;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t v) {
  while (parent[v] != v)
    v = parent[v] = parent[parent[v]]; // path halving
  return v;
}

std::uint64_t countComponents(const TriangleSoup& soup) {
  std::vector<std::uint32_t> parent(soup.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<bool> used(soup.vertices.size(), false);
  for (const auto& t : soup.triangles) {
    for (int e = 0; e < 3; ++e) {
      used[t[e]] = true;
      parent[findRoot(parent, t[e])] = findRoot(parent, t[(e + 1) % 3]);
    }
  }
  std::uint64_t roots = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v)
    roots += used[v] && findRoot(parent, v) == v ? 1 : 0;
  return roots;
}

} // namespace

MeshReport checkMesh(const TriangleSoup& soup) {
  MeshReport r;
  r.vertices = soup.vertices.size();
  r.triangles = soup.triangles.size();
  bool first = true;
  for (const Vec3f& v : soup.vertices) {
    if (!isFinite(v)) {
      ++r.non_finite_vertices;
      continue;
    }
    r.bounds_min =
        first ? v : Vec3f{std::min(r.bounds_min.x, v.x), std::min(r.bounds_min.y, v.y), std::min(r.bounds_min.z, v.z)};
    r.bounds_max =
        first ? v : Vec3f{std::max(r.bounds_max.x, v.x), std::max(r.bounds_max.y, v.y), std::max(r.bounds_max.z, v.z)};
    first = false;
  }
  for (const auto& t : soup.triangles)
    r.degenerate_triangles += degenerate(soup, t) ? 1 : 0;
  const EdgeCounts by_index = countEdges(soup, [](std::uint32_t v) { return v; });
  r.boundary_edges = by_index.once;
  r.non_manifold_edges = by_index.three_or_more;
  r.misoriented_edges = by_index.same_direction;
  if (r.boundary_edges > 0) {
    const std::vector<std::uint32_t> twin = firstTwins(soup);
    r.hole_edges = countEdges(soup, [&twin](std::uint32_t v) { return twin[v]; }).once;
  }
  r.components = countComponents(soup);
  if (r.non_finite_vertices == 0) r.signed_volume = signedVolume(soup);
  return r;
}

BakeStatus requireBakeable(const MeshReport& r) {
  if (r.triangles == 0) return BakeStatus::failure(BakeError::kInvalidInput, "the mesh has no faces");
  if (r.non_finite_vertices > 0)
    return BakeStatus::failure(BakeError::kInvalidInput,
                               std::to_string(r.non_finite_vertices) + " vertices have NaN or infinite coordinates");
  if (r.degenerate_triangles == r.triangles)
    return BakeStatus::failure(BakeError::kInvalidInput,
                               "all " + std::to_string(r.triangles) +
                                   " triangles are degenerate (a repeated vertex, or no area at float precision: "
                                   "thinner than 1e-7 of their longest edge)");
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
