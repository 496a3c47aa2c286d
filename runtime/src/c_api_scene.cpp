// The C ABI's scenes (dng/dng.h): bodies by index, enable/disable and removal on top of dng::Body,
// stepping through dng::stepParticles with the scene's broadphase when it is fresh. Only
// dng_scene_create, dng_scene_add_body and dng_scene_prepare_step allocate.
#include "c_api_internal.h"

#include <algorithm>
#include <new>

namespace {

using dng::c_api::fail;
using dng::c_api::report;

dng::Material toMaterial(const dng_material& m) {
  dng::Material out;
  out.response = dng::Response(m.response);
  out.restitution = m.restitution;
  out.collision_distance = m.collision_distance;
  out.spring_stiffness = m.spring_stiffness;
  out.spring_distance = m.spring_distance;
  out.drag = m.drag;
  out.contact_distance = m.contact_distance;
  out.flow_in = m.flow_in;
  out.flow_out = m.flow_out;
  out.flow_distance = m.flow_distance;
  out.swept = m.swept != 0;
  return out;
}

dng::Body* bodyAt(dng_scene* scene, std::uint32_t index) {
  return scene != nullptr && index < scene->bodies.size() ? &scene->bodies[index] : nullptr;
}

// Packs the enabled bodies. Never allocates: dng_scene_add_body reserved room for every body.
void rebuildActive(dng_scene* scene) {
  scene->index_fresh = false;
  scene->active.clear();
  scene->active_body.clear();
  for (std::uint32_t i = 0; i < scene->bodies.size(); ++i) {
    scene->active_slot[i] = scene->enabled[i] ? std::int32_t(scene->active.size()) : -1;
    if (!scene->enabled[i]) continue;
    scene->active.push_back(scene->bodies[i]);
    scene->active_body.push_back(i);
  }
}

// After a change to bodies[index]: the packed copy follows.
void syncActive(dng_scene* scene, std::uint32_t index) {
  scene->index_fresh = false;
  const std::int32_t slot = scene->active_slot[index];
  if (slot >= 0) scene->active[std::size_t(slot)] = scene->bodies[index];
}

// Room for one more body in every array, so that later rebuilds cannot allocate. The room doubles when
// it runs out: reserving one more each time copied every body on every add (40,000 adds took 49 s).
void reserveOneMore(dng_scene* scene) {
  const std::size_t n = scene->bodies.size() + 1, room = std::max(n, 2 * scene->bodies.size());
  const auto grow = [&](auto& array) {
    if (array.capacity() < n) array.reserve(room);
  };
  grow(scene->bodies);
  grow(scene->enabled);
  grow(scene->active_slot);
  grow(scene->active);
  grow(scene->active_body);
}

} // namespace

extern "C" {

dng_status dng_scene_create(dng_scene** out_scene) {
  if (out_scene == nullptr) return DNG_INVALID_ARGUMENT;
  *out_scene = new (std::nothrow) dng_scene;
  return *out_scene != nullptr ? DNG_OK : DNG_OUT_OF_MEMORY;
}

void dng_scene_destroy(dng_scene* scene) { delete scene; }

dng_status dng_scene_add_body(dng_scene* scene, const dng_field* field, const dng_material* material,
                              uint32_t* out_index, char* out_message, size_t capacity) {
  if (scene == nullptr || field == nullptr || material == nullptr || out_index == nullptr)
    return fail(dng::Status::kInvalidArgument, "scene, field, material and out_index must not be NULL", out_message,
                capacity);
  dng::Diagnostic diag;
  dng::Body body;
  const dng::Status status = dng::Body::create(&field->view, toMaterial(*material), &body, &diag);
  if (status != dng::Status::kOk) return report(status, diag, out_message, capacity);
  try {
    reserveOneMore(scene);
  } catch (const std::bad_alloc&) {
    return fail(dng::Status::kOutOfMemory, "out of memory", out_message, capacity);
  }
  // The new body takes the last index, so it goes last in the packed list too: no repacking.
  scene->index_fresh = false;
  scene->active_slot.push_back(std::int32_t(scene->active.size()));
  scene->active.push_back(body);
  scene->active_body.push_back(std::uint32_t(scene->bodies.size()));
  scene->bodies.push_back(body);
  scene->enabled.push_back(1);
  *out_index = uint32_t(scene->bodies.size() - 1);
  return report(dng::Status::kOk, diag, out_message, capacity);
}

dng_status dng_scene_set_transform(dng_scene* scene, uint32_t body, const float m[12], char* out_message,
                                   size_t capacity) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr || m == nullptr)
    return fail(dng::Status::kInvalidArgument, "no such scene or body, or the matrix is NULL", out_message, capacity);
  dng::Diagnostic diag;
  const dng::Status status = b->setTransform(m, &diag);
  syncActive(scene, body);
  return report(status, diag, out_message, capacity);
}

dng_status dng_scene_set_velocity(dng_scene* scene, uint32_t body, const float linear[3], const float angular[3]) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr || linear == nullptr || angular == nullptr) return DNG_INVALID_ARGUMENT;
  b->setVelocity({linear[0], linear[1], linear[2]}, {angular[0], angular[1], angular[2]});
  syncActive(scene, body);
  return DNG_OK;
}

dng_status dng_scene_set_material(dng_scene* scene, uint32_t body, const dng_material* material, char* out_message,
                                  size_t capacity) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr || material == nullptr)
    return fail(dng::Status::kInvalidArgument, "no such scene or body, or material is NULL", out_message, capacity);
  dng::Diagnostic diag;
  const dng::Status status = b->setMaterial(toMaterial(*material), &diag);
  syncActive(scene, body);
  return report(status, diag, out_message, capacity);
}

uint32_t dng_scene_body_count(const dng_scene* scene) { return scene != nullptr ? uint32_t(scene->bodies.size()) : 0u; }

dng_status dng_scene_remove_body(dng_scene* scene, uint32_t body) {
  if (bodyAt(scene, body) == nullptr) return DNG_INVALID_ARGUMENT;
  scene->bodies[body] = scene->bodies.back(); // the last body takes the freed index
  scene->enabled[body] = scene->enabled.back();
  scene->bodies.pop_back();
  scene->enabled.pop_back();
  scene->active_slot.pop_back();
  rebuildActive(scene);
  return DNG_OK;
}

dng_status dng_scene_set_body_enabled(dng_scene* scene, uint32_t body, int32_t enabled) {
  if (bodyAt(scene, body) == nullptr) return DNG_INVALID_ARGUMENT;
  scene->enabled[body] = enabled != 0 ? 1 : 0;
  rebuildActive(scene);
  return DNG_OK;
}

int32_t dng_scene_body_enabled(const dng_scene* scene, uint32_t body) {
  if (scene == nullptr || body >= scene->bodies.size()) return -1;
  return scene->enabled[body];
}

dng_status dng_scene_body_bounds(const dng_scene* scene, uint32_t body, float out_min[3], float out_max[3]) {
  if (scene == nullptr || body >= scene->bodies.size() || out_min == nullptr || out_max == nullptr)
    return DNG_INVALID_ARGUMENT;
  const dng::Body& b = scene->bodies[body];
  const dng::Vec3f lo = b.boundsMin(), hi = b.boundsMax();
  out_min[0] = lo.x, out_min[1] = lo.y, out_min[2] = lo.z;
  out_max[0] = hi.x, out_max[1] = hi.y, out_max[2] = hi.z;
  return DNG_OK;
}

int32_t dng_scene_body_proves_outside(const dng_scene* scene, uint32_t body, const float point[3]) {
  if (scene == nullptr || body >= scene->bodies.size() || point == nullptr) return -1;
  return scene->bodies[body].provesOutside({point[0], point[1], point[2]}) ? 1 : 0;
}

dng_status dng_scene_prepare_step(dng_scene* scene, float dt, char* out_message, size_t capacity) {
  if (scene == nullptr) return fail(dng::Status::kInvalidArgument, "scene must not be NULL", out_message, capacity);
  dng::Diagnostic diag;
  const dng::Status status = scene->index.rebuild(scene->active.data(), scene->active.size(), dt, &diag);
  scene->index_fresh = status == dng::Status::kOk;
  return report(status, diag, out_message, capacity);
}

// stepParticles numbers bodies by their place in the packed array; the caller gets scene indices.
dng_status dng_scene_step(const dng_scene* scene, const dng_particles* p, float dt, char* out_message,
                          size_t capacity) {
  if (scene == nullptr || p == nullptr)
    return fail(dng::Status::kInvalidArgument, "scene and particles must not be NULL", out_message, capacity);
  const dng::ParticleSpan span{p->position_x, p->position_y,  p->position_z, p->position_stride,
                               p->velocity_x, p->velocity_y,  p->velocity_z, p->velocity_stride,
                               p->count,      p->out_contact, p->out_body};
  dng::Diagnostic diag;
  // The index serves only the dt it was built for; any other step tests every body, with the same results.
  const bool indexed = scene->index_fresh && scene->index.dt() == dt;
  const dng::Status status =
      indexed ? dng::stepParticles(span, dt, scene->active.data(), scene->active.size(), scene->index, &diag)
              : dng::stepParticles(span, dt, scene->active.data(), scene->active.size(), &diag);
  if (status == dng::Status::kOk && p->out_body != nullptr && scene->active.size() != scene->bodies.size()) {
    for (std::size_t n = 0; n < p->count; ++n) {
      if (p->out_body[n] >= 0) p->out_body[n] = std::int32_t(scene->active_body[std::size_t(p->out_body[n])]);
    }
  }
  return report(status, diag, out_message, capacity);
}

} // extern "C"
