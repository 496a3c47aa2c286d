// Closest points on a triangle soup with Embree's BVH (rtcPointQuery): Embree walks the hierarchy
// and calls us per candidate triangle; we compute the exact closest point and shrink the query
// radius so the walk prunes everything farther away.
#include "stages.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace dng {
namespace baker {

namespace {

// Doubles for the closest point on thin triangles: the Voronoi tests subtract products of nearly equal
// size, which in floats go wrong on slivers (one a millionth as wide as it is long read 0.044 from a
// point its edge lay 0.015 from: tests/closest_point_test). Floats do elsewhere, and cost less.
struct Vec3d {
  double x, y, z;
  explicit Vec3d(Vec3f v) : x(v.x), y(v.y), z(v.z) {}
  Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  Vec3d operator+(Vec3d o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3d operator-(Vec3d o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
};
double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3f toFloat(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }

// Closest point on triangle abc to p, by Voronoi regions of the vertices, edges and face
// (C. Ericson, Real-Time Collision Detection, 2005, §5.1.5), in Vec3f or Vec3d.
template <class V> V closestOnTriangle(V p, V a, V b, V c) {
  using S = decltype(dot(a, b));
  const S zero = 0;
  const V ab = b - a, ac = c - a, ap = p - a;
  const S d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= zero && d2 <= zero) return a;
  const V bp = p - b;
  const S d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= zero && d4 <= d3) return b;
  const S vc = d1 * d4 - d3 * d2;
  if (vc <= zero && d1 >= zero && d3 <= zero) return a + ab * (d1 / (d1 - d3));
  const V cp = p - c;
  const S d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= zero && d5 <= d6) return c;
  const S vb = d5 * d2 - d1 * d6;
  if (vb <= zero && d2 >= zero && d6 <= zero) return a + ac * (d2 / (d2 - d6));
  const S va = d3 * d6 - d5 * d4;
  if (va <= zero && (d4 - d3) >= zero && (d5 - d6) >= zero) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const S denom = S(1) / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// What a point query reads of one Embree primitive, packed in primitive order: the soup's triangle, its
// corners, and two cheap lower bounds on the distance to it. Most candidates a walk reaches lie farther
// than the radius, and the bounds send them away without the exact test: a ball around corner a that
// holds the triangle, and the triangle's plane.
struct Primitive {
  Vec3f a, b, c;
  Vec3f normal;       // unit, as computed in floats
  float normal_error; // bounds the angle (radians) between `normal` and the true one: large for slivers
  float extent;       // the farthest corner from a
  std::uint32_t triangle;
};

// Triangle t's primitive, or false when it has no area or a corner that is not finite (the index leaves
// those out: they bound nothing).
bool makePrimitive(const TriangleSoup& soup, std::uint32_t t, Primitive* out) {
  const auto& tri = soup.triangles[t];
  const Vec3f a = soup.vertices[tri[0]], b = soup.vertices[tri[1]], c = soup.vertices[tri[2]];
  const Vec3f twice_area = cross(b - a, c - a);
  if (!(length(twice_area) > 0.0f && std::isfinite(dot(a + b + c, a + b + c)))) return false;
  const float extent = std::max(length(b - a), length(c - a));
  // Each component of the cross product is off by a few float steps of |ab| |ac| <= extent^2, so its
  // direction by that over its length; four times that covers the normalization too.
  const float error = 16.0f * std::numeric_limits<float>::epsilon() * extent * extent / length(twice_area);
  *out = {a, b, c, normalizeOrZero(twice_area), std::isfinite(error) ? error : 2.0f, extent, t};
  return true;
}

// A triangle whose normal floats may get this wrong (radians) is thin enough for doubles: under about 2%
// as wide as it is long (16 float epsilons over 1e-4).
constexpr float kThinNormalError = 1e-4f;

float largestMagnitude(Vec3f v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// Whether the triangle surely lies at least `radius` from p, as the exact test would compute it: the
// bounds must clear the radius by more than the rounding of either computation, which grows with the
// coordinates' size, and the plane's by what its normal may be off over the way from a to p.
bool surelyBeyond(const Primitive& t, Vec3f p, float radius) {
  const Vec3f ap = p - t.a;
  const float from_a = length(ap);
  const float beyond = radius + 1e-5f * (largestMagnitude(p) + largestMagnitude(t.a) + t.extent);
  return from_a - t.extent > beyond || std::fabs(dot(t.normal, ap)) - t.normal_error * from_a > beyond;
}

// The primitives of a scene, in Embree's order.
using SceneTriangles = std::vector<Primitive>;

// The triangle of the primitive a point query reached, and its point closest to the query's.
struct Reached {
  std::uint32_t triangle;
  Vec3f closest;
  float distance;
};

// Nothing (triangle of ~0u) when the primitive surely lies beyond the query's radius.
Reached reached(const RTCPointQueryFunctionArguments* args, const SceneTriangles& scene) {
  const Primitive& t = scene[args->primID];
  const Vec3f p{args->query->x, args->query->y, args->query->z};
  if (surelyBeyond(t, p, args->query->radius)) return {~0u, p, std::numeric_limits<float>::infinity()};
  if (t.normal_error < kThinNormalError) {
    const Vec3f q = closestOnTriangle(p, t.a, t.b, t.c);
    return {t.triangle, q, length(p - q)};
  }
  const Vec3d q = closestOnTriangle(Vec3d(p), Vec3d(t.a), Vec3d(t.b), Vec3d(t.c));
  const Vec3d pq = Vec3d(p) - q;
  return {t.triangle, toFloat(q), float(std::sqrt(dot(pq, pq)))};
}

struct QueryState {
  const SceneTriangles* scene;
  ClosestPointIndex::Hit hit;
};

bool visitTriangle(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<QueryState*>(args->userPtr);
  const Reached r = reached(args, *state->scene);
  if (!(r.distance < args->query->radius)) return false;
  args->query->radius = r.distance; // prune the rest of the walk
  state->hit = {true, r.distance, r.closest, r.triangle};
  return true;
}

struct NearState {
  const SceneTriangles* scene;
  bool (*wanted)(void* user, std::uint32_t triangle); // null: every triangle
  void (*visit)(void* user, std::uint32_t triangle);
  void* user;
};

// Every triangle whose bounds the walk reaches, kept when the caller wants it and its closest point is
// within the radius.
bool visitNear(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<NearState*>(args->userPtr);
  if (state->wanted != nullptr && !state->wanted(state->user, (*state->scene)[args->primID].triangle)) return false;
  const Reached r = reached(args, *state->scene);
  if (r.distance < args->query->radius) state->visit(state->user, r.triangle);
  return false; // the radius stays: every triangle within it is wanted
}

// Embree's walk of `scene` for the ball of `radius` around p, calling `visit` with `state`.
void pointQuery(RTCScene scene, Vec3f p, float radius, RTCPointQueryFunction visit, void* state) {
  RTCPointQuery query;
  query.x = p.x, query.y = p.y, query.z = p.z;
  query.time = 0.0f;
  query.radius = radius;
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene, &query, &context, visit, state);
}

} // namespace

struct ClosestPointIndex::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  SceneTriangles primitives; // in Embree's order
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

ClosestPointIndex::ClosestPointIndex() : impl_(std::make_unique<Impl>()) {}
ClosestPointIndex::~ClosestPointIndex() = default;

BakeStatus ClosestPointIndex::build(const TriangleSoup& soup) {
  impl_ = std::make_unique<Impl>();
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) return BakeStatus::failure(BakeError::kInternal, "Embree could not create a device");
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  Primitive primitive{};
  for (std::uint32_t t = 0; t < soup.triangles.size(); ++t)
    if (makePrimitive(soup, t, &primitive)) impl_->primitives.push_back(primitive);
  // Embree reads vertices with 16-byte loads: its own buffers carry the padding it needs.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), soup.vertices.size()));
  auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), impl_->primitives.size()));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    return BakeStatus::failure(BakeError::kInternal, "Embree could not allocate the mesh buffers");
  }
  std::memcpy(vertices, soup.vertices.data(), soup.vertices.size() * sizeof(Vec3f));
  for (std::size_t i = 0; i < impl_->primitives.size(); ++i)
    std::memcpy(indices + 3 * i, soup.triangles[impl_->primitives[i].triangle].data(), 3 * sizeof(std::uint32_t));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE)
    return BakeStatus::failure(BakeError::kInternal, "Embree failed to build the scene");
  return BakeStatus::success();
}

ClosestPointIndex::Hit ClosestPointIndex::query(Vec3f p, float radius) const {
  QueryState state{&impl_->primitives, {}};
  pointQuery(impl_->scene, p, radius, visitTriangle, &state);
  return state.hit;
}

void ClosestPointIndex::forEachNear(Vec3f p, float radius, bool (*wanted)(void* user, std::uint32_t triangle),
                                    void (*visit)(void* user, std::uint32_t triangle), void* user) const {
  NearState state{&impl_->primitives, wanted, visit, user};
  pointQuery(impl_->scene, p, radius, visitNear, &state);
}

} // namespace baker
} // namespace dng
