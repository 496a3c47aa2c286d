#include "table1_embree.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstring>

namespace dng {
namespace table1 {

namespace {

// How far in front of a hit face a stopped particle waits, in voxels: far above float rounding, far
// below anything a particle system would see (the leak harness's control stepper uses the same).
constexpr float kStandOffVoxels = 1e-3f;

// Embree's memory monitor: every allocation and free of the device, in bytes (negative for frees).
bool countBytes(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<long long>*>(user)->fetch_add(static_cast<long long>(bytes));
  return true;
}

// The packet types and calls of each width, so one template serves 4, 8 and 16.
template <int W> struct Packet;
template <> struct Packet<4> {
  using RayHit = RTCRayHit4;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect4(valid, s, c, r);
  }
};
template <> struct Packet<8> {
  using RayHit = RTCRayHit8;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(valid, s, c, r);
  }
};
template <> struct Packet<16> {
  using RayHit = RTCRayHit16;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(valid, s, c, r);
  }
};

// The response to one cast: stop in front of the hit face and reflect (impact rule, paper §3.4), or
// move the whole segment. `ng` is Embree's unnormalized geometric normal.
inline void resolve(std::size_t n, bool hit, float t, Vec3f ng, float standoff, float restitution, float dt, Swarm* s) {
  const Vec3f p = s->position(n), v = s->velocity(n), d = v * dt;
  Vec3f end = p + d;
  if (hit) {
    Vec3f normal = normalizeOrZero(ng);
    if (dot(normal, d) > 0.0f) normal = normal * -1.0f; // the side the particle came from
    end = p + d * t + normal * standoff;
    const float vn = dot(v, normal);
    if (vn < 0.0f) {
      const Vec3f w = v - normal * ((1.0f + restitution) * vn);
      s->vx[n] = w.x, s->vy[n] = w.y, s->vz[n] = w.z;
    }
  }
  s->px[n] = end.x, s->py[n] = end.y, s->pz[n] = end.z;
}

// A particle at rest has no segment to cast (Embree needs a non-zero direction).
inline bool moves(const Swarm& s, std::size_t n) { return s.vx[n] != 0.0f || s.vy[n] != 0.0f || s.vz[n] != 0.0f; }

} // namespace

struct EmbreeCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<long long> bytes{0};
  float standoff = 0.0f;
  bool built = false;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void step1(float restitution, float dt, Swarm* s) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t n = 0; n < s->size(); ++n) {
      if (!moves(*s, n)) continue;
      RTCRayHit rh;
      rh.ray.org_x = s->px[n], rh.ray.org_y = s->py[n], rh.ray.org_z = s->pz[n];
      rh.ray.dir_x = s->vx[n] * dt, rh.ray.dir_y = s->vy[n] * dt, rh.ray.dir_z = s->vz[n] * dt;
      rh.ray.tnear = 0.0f, rh.ray.tfar = 1.0f, rh.ray.time = 0.0f; // t in units of the step's move
      rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      resolve(n, rh.hit.geomID != RTC_INVALID_GEOMETRY_ID, rh.ray.tfar, {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z},
              standoff, restitution, dt, s);
    }
  }

  template <int W> void stepPackets(float restitution, float dt, Swarm* s) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    alignas(64) typename Packet<W>::RayHit rh;
    alignas(64) int valid[W];
    for (std::size_t base = 0; base < s->size(); base += W) {
      for (int i = 0; i < W; ++i) {
        const std::size_t n = base + std::size_t(i);
        valid[i] = n < s->size() && moves(*s, n) ? -1 : 0;
        if (valid[i] == 0) continue;
        rh.ray.org_x[i] = s->px[n], rh.ray.org_y[i] = s->py[n], rh.ray.org_z[i] = s->pz[n];
        rh.ray.dir_x[i] = s->vx[n] * dt, rh.ray.dir_y[i] = s->vy[n] * dt, rh.ray.dir_z[i] = s->vz[n] * dt;
        rh.ray.tnear[i] = 0.0f, rh.ray.tfar[i] = 1.0f, rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = 0xFFFFFFFFu, rh.ray.id[i] = 0, rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID, rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
      }
      Packet<W>::intersect(valid, scene, &context, &rh);
      for (int i = 0; i < W; ++i) {
        if (valid[i] == 0) continue;
        resolve(base + std::size_t(i), rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID, rh.ray.tfar[i],
                {rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]}, standoff, restitution, dt, s);
      }
    }
  }
};

EmbreeCaster::EmbreeCaster() : impl_(std::make_unique<Impl>()) {}
EmbreeCaster::~EmbreeCaster() = default;

bool EmbreeCaster::build(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                         float voxel, const char* device_config) {
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.standoff = kStandOffVoxels * voxel;
  m.device = rtcNewDevice(device_config);
  if (m.device == nullptr) return false;
  rtcSetDeviceMemoryMonitorFunction(m.device, countBytes, &m.bytes);
  m.scene = rtcNewScene(m.device);
  // A static mesh, as a game's level geometry is: the best BVH Embree builds, built once.
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), vertices.size()));
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(std::uint32_t), triangles.size()));
  if (vb == nullptr || ib == nullptr) {
    rtcReleaseGeometry(geometry);
    return false;
  }
  std::memcpy(vb, vertices.data(), vertices.size() * sizeof(Vec3f));
  std::memcpy(ib, triangles.data(), triangles.size() * sizeof(triangles[0]));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(m.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(m.scene);
  m.built = rtcGetDeviceError(m.device) == RTC_ERROR_NONE;
  return m.built;
}

bool EmbreeCaster::built() const { return impl_->built; }

std::size_t EmbreeCaster::bytes() const { return std::size_t(std::max(0LL, impl_->bytes.load())); }

void EmbreeCaster::step(int packet, float restitution, float dt, Swarm* swarm) const {
  switch (packet) {
  case 4: impl_->stepPackets<4>(restitution, dt, swarm); break;
  case 8: impl_->stepPackets<8>(restitution, dt, swarm); break;
  case 16: impl_->stepPackets<16>(restitution, dt, swarm); break;
  default: impl_->step1(restitution, dt, swarm); break;
  }
}

} // namespace table1
} // namespace dng
