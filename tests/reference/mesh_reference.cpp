// Embree 3 queries for the reference (see mesh_reference.h). Written independently of the baker's
// closest-point and sign code, which it is there to check: the point-triangle distance here is the
// plane projection or the nearest edge, in double precision, and the inside test is ray parity.
#include "mesh_reference.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace dng {
namespace reference {

namespace {

struct Vec3d {
  double x, y, z;
};
Vec3d toD(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3f toF(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }
Vec3d sub(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d add(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d mul(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotD(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3d crossD(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

Vec3d closestOnSegment(Vec3d p, Vec3d a, Vec3d b) {
  const Vec3d ab = sub(b, a);
  const double len2 = dotD(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(dotD(sub(p, a), ab) / len2, 0.0, 1.0) : 0.0;
  return add(a, mul(ab, t));
}

// The projection onto the triangle's plane when it falls inside the triangle, else the nearest of
// the three edges' closest points.
Vec3d closestOnTriangle(Vec3d p, Vec3d a, Vec3d b, Vec3d c) {
  const Vec3d n = crossD(sub(b, a), sub(c, a));
  const double n2 = dotD(n, n);
  const Vec3d q = sub(p, mul(n, dotD(sub(p, a), n) / n2));
  if (dotD(crossD(sub(b, a), sub(q, a)), n) >= 0.0 && dotD(crossD(sub(c, b), sub(q, b)), n) >= 0.0 &&
      dotD(crossD(sub(a, c), sub(q, c)), n) >= 0.0)
    return q;
  Vec3d best = closestOnSegment(p, a, b);
  for (const Vec3d candidate : {closestOnSegment(p, b, c), closestOnSegment(p, c, a)}) {
    const Vec3d d0 = sub(best, p), d1 = sub(candidate, p);
    if (dotD(d1, d1) < dotD(d0, d0)) best = candidate;
  }
  return best;
}

// A hit is "near an edge" when a barycentric coordinate is this small: there a ray may report the
// crossing on both neighbours or on neither.
constexpr float kEdgeBarycentric = 1e-5f;

// Fixed directions with no special relation to the axes or to each other; the inside test uses the
// first three whose rays miss every edge.
constexpr float kDirections[7][3] = {{0.5377f, 0.8339f, 0.1247f},  {-0.2461f, 0.3124f, 0.9176f},
                                     {0.7718f, -0.4932f, 0.4013f}, {-0.6813f, -0.5167f, -0.5185f},
                                     {0.1359f, -0.9121f, 0.3867f}, {-0.8872f, 0.2316f, -0.3989f},
                                     {0.3301f, 0.4409f, -0.8345f}};

// The intersect context carries where the filter collects hits (Embree's documented way to pass
// per-query data to a context filter).
struct CollectContext {
  RTCIntersectContext base;
  std::vector<Crossing>* hits;
};

// Records every hit and rejects it, so traversal goes on to the next one along the ray.
void collectHit(const RTCFilterFunctionNArguments* args) {
  auto* context = reinterpret_cast<CollectContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    Crossing c;
    c.t = RTCRayN_tfar(args->ray, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    c.near_edge = std::min({u, v, 1.0f - u - v}) < kEdgeBarycentric;
    c.triangle = RTCHitN_primID(args->hit, args->N, i);
    context->hits->push_back(c);
    args->valid[i] = 0;
  }
}

} // namespace

struct MeshReference::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles; // the kept ones; Embree's primID indexes them
  std::vector<std::uint32_t> original;                 // primID -> index given to build()
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  // All hits along origin + t * direction for t in [0, tfar], unsorted, with t in ray units.
  void castAll(Vec3f origin, Vec3f direction, float tfar, std::vector<Crossing>* out) const {
    CollectContext context;
    rtcInitIntersectContext(&context.base);
    context.base.filter = collectHit;
    context.hits = out;
    RTCRayHit rayhit;
    std::memset(&rayhit, 0, sizeof rayhit);
    rayhit.ray.org_x = origin.x, rayhit.ray.org_y = origin.y, rayhit.ray.org_z = origin.z;
    rayhit.ray.dir_x = direction.x, rayhit.ray.dir_y = direction.y, rayhit.ray.dir_z = direction.z;
    rayhit.ray.tnear = 0.0f;
    rayhit.ray.tfar = tfar;
    rayhit.ray.mask = 0xFFFFFFFFu;
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context.base, &rayhit);
  }
};

MeshReference::MeshReference() : impl_(std::make_unique<Impl>()) {}
MeshReference::~MeshReference() = default;

bool MeshReference::build(const std::vector<Vec3f>& vertices,
                          const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.vertices = vertices;
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    if (std::max({tri[0], tri[1], tri[2]}) >= vertices.size()) continue;
    const Vec3f a = vertices[tri[0]], b = vertices[tri[1]], c = vertices[tri[2]];
    const float area2 = length(cross(b - a, c - a));
    if (!(area2 > 0.0f) || !std::isfinite(area2)) continue;
    m.triangles.push_back(tri);
    m.original.push_back(t);
  }
  if (m.triangles.empty()) return false;
  m.device = rtcNewDevice(nullptr);
  if (m.device == nullptr) return false;
  m.scene = rtcNewScene(m.device);
  // Robust traversal does not lose hits between neighbouring triangles; the context filter flag lets
  // collectHit see every hit.
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  RTCGeometry geometry = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), m.vertices.size()));
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(std::uint32_t), m.triangles.size()));
  if (vb == nullptr || ib == nullptr) {
    rtcReleaseGeometry(geometry);
    return false;
  }
  std::memcpy(vb, m.vertices.data(), m.vertices.size() * sizeof(Vec3f));
  std::memcpy(ib, m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(m.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(m.scene);
  return rtcGetDeviceError(m.device) == RTC_ERROR_NONE;
}

namespace {

struct ClosestState {
  const std::vector<Vec3f>* vertices;
  const std::vector<std::array<std::uint32_t, 3>>* triangles;
  Vec3d best_point{0, 0, 0};
  double best_distance = 0.0;
  std::uint32_t best_triangle = 0;
  bool found = false;
};

bool visitCandidate(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<ClosestState*>(args->userPtr);
  const auto& tri = (*state->triangles)[args->primID];
  const auto& v = *state->vertices;
  const Vec3d p{args->query->x, args->query->y, args->query->z};
  const Vec3d q = closestOnTriangle(p, toD(v[tri[0]]), toD(v[tri[1]]), toD(v[tri[2]]));
  const double d = std::sqrt(dotD(sub(p, q), sub(p, q)));
  if (state->found && d >= state->best_distance) return false;
  if (!(d <= double(args->query->radius))) return false;
  *state = {state->vertices, state->triangles, q, d, args->primID, true};
  args->query->radius = float(d); // the walk can skip everything farther
  return true;
}

} // namespace

Closest MeshReference::closest(Vec3f p, float radius) const {
  RTCPointQuery query;
  query.x = p.x, query.y = p.y, query.z = p.z;
  query.time = 0.0f;
  query.radius = radius;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  ClosestState state{&impl_->vertices, &impl_->triangles};
  rtcPointQuery(impl_->scene, &query, &context, visitCandidate, &state);
  Closest out;
  if (!state.found) return out;
  out.found = true;
  out.distance = float(state.best_distance);
  out.point = toF(state.best_point);
  out.triangle = impl_->original[state.best_triangle];
  return out;
}

bool MeshReference::inside(Vec3f p) const {
  std::vector<Crossing> hits;
  int votes = 0, inside_votes = 0, any_parity_inside = 0;
  for (const auto& d : kDirections) {
    hits.clear();
    impl_->castAll(p, {d[0], d[1], d[2]}, std::numeric_limits<float>::infinity(), &hits);
    const bool odd = hits.size() % 2 == 1;
    any_parity_inside += odd ? 1 : 0;
    if (std::any_of(hits.begin(), hits.end(), [](const Crossing& c) { return c.near_edge; })) continue;
    ++votes;
    inside_votes += odd ? 1 : 0;
    if (votes == 3) break;
  }
  // Almost never: most rays grazed an edge. Fall back to every ray's parity.
  if (votes < 3) return 2 * any_parity_inside > int(std::size(kDirections));
  return inside_votes >= 2;
}

void MeshReference::crossings(Vec3f a, Vec3f b, std::vector<Crossing>* out) const {
  out->clear();
  // The ray runs a + t (b - a), so Embree's t is already the segment parameter.
  impl_->castAll(a, b - a, 1.0f, out);
  for (Crossing& c : *out)
    c.triangle = impl_->original[c.triangle];
  std::sort(out->begin(), out->end(), [](const Crossing& x, const Crossing& y) { return x.t < y.t; });
}

Vec3f MeshReference::faceNormal(std::uint32_t triangle) const {
  const auto it = std::lower_bound(impl_->original.begin(), impl_->original.end(), triangle);
  if (it == impl_->original.end() || *it != triangle) return {};
  const auto& tri = impl_->triangles[std::size_t(it - impl_->original.begin())];
  const Vec3f a = impl_->vertices[tri[0]], b = impl_->vertices[tri[1]], c = impl_->vertices[tri[2]];
  return normalizeOrZero(cross(b - a, c - a));
}

} // namespace reference
} // namespace dng
