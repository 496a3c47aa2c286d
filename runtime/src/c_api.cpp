// The C ABI (dng/dng.h) over the C++ runtime. Handles are heap objects made at open/create time;
// nothing else allocates. No exception can leave: the only throwing operation (vector growth in
// dng_scene_add_body) is caught and reported as DNG_OUT_OF_MEMORY.
#include "dng/dng.h"
#include "dng/file.h"
#include "dng/particles.h"

#include <cstdio>
#include <cstring>
#include <new>
#include <vector>

struct dng_field {
  dng::File file; // owner when opened from a path
  dng::View view; // what queries use (points into file, or into caller memory)
};

struct dng_scene {
  std::vector<dng::Body> bodies;
};

namespace {

static_assert(sizeof(dng_sample) == sizeof(dng::Sample), "dng_sample mirrors dng::Sample");
static_assert(DNG_SECTION_HASH_MISMATCH == int(dng::Status::kSectionHashMismatch), "status numbers match");
static_assert(DNG_OUT_OF_MEMORY == int(dng::Status::kOutOfMemory), "status numbers match");
static_assert(DNG_NONZERO_PADDING == int(dng::Status::kNonZeroPadding), "status numbers match");

dng_status report(dng::Status status, const dng::Diagnostic& diag, char* out, std::size_t capacity) {
  if (out != nullptr && capacity > 0) {
    const char* text = status == dng::Status::kOk ? "" : diag.message[0] ? diag.message : dng::statusString(status);
    // C callers get one string: the rule leads it, as in dngdump's findings ("V8: file is truncated...").
    const bool ruled = status != dng::Status::kOk && diag.rule[0] != '\0';
    std::snprintf(out, capacity, "%s%s%s", ruled ? diag.rule : "", ruled ? ": " : "", text);
  }
  return dng_status(status);
}

dng_status fail(dng::Status status, const char* text, char* out, std::size_t capacity) {
  dng::Diagnostic diag;
  std::snprintf(diag.message, sizeof diag.message, "%s", text);
  return report(status, diag, out, capacity);
}

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

} // namespace

extern "C" {

const char* dng_status_string(dng_status status) { return dng::statusString(dng::Status(status)); }

uint32_t dng_version(void) { return DNG_VERSION; }

int32_t dng_version_compatible(uint32_t header_version) {
  const uint32_t major = header_version >> 16, minor = (header_version >> 8) & 0xFFu;
  return major == DNG_VERSION_MAJOR && minor <= DNG_VERSION_MINOR ? 1 : 0;
}

dng_status dng_field_open_file(const char* path, dng_field** out_field, char* out_message, size_t capacity) {
  if (out_field == nullptr) return fail(dng::Status::kInvalidArgument, "out_field is NULL", out_message, capacity);
  *out_field = nullptr;
  auto* field = new (std::nothrow) dng_field;
  if (field == nullptr) return fail(dng::Status::kOutOfMemory, "out of memory", out_message, capacity);
  dng::Diagnostic diag;
  const dng::Status status = dng::File::open(path, &field->file, &diag);
  if (status != dng::Status::kOk) {
    delete field;
    return report(status, diag, out_message, capacity);
  }
  field->view = field->file.view();
  *out_field = field;
  return report(status, diag, out_message, capacity);
}

dng_status dng_field_open_memory(const void* bytes, size_t size, dng_field** out_field, char* out_message,
                                 size_t capacity) {
  if (out_field == nullptr) return fail(dng::Status::kInvalidArgument, "out_field is NULL", out_message, capacity);
  *out_field = nullptr;
  auto* field = new (std::nothrow) dng_field;
  if (field == nullptr) return fail(dng::Status::kOutOfMemory, "out of memory", out_message, capacity);
  dng::Diagnostic diag;
  const dng::Status status = dng::View::open(bytes, size, &field->view, &diag);
  if (status != dng::Status::kOk) {
    delete field;
    return report(status, diag, out_message, capacity);
  }
  *out_field = field;
  return report(status, diag, out_message, capacity);
}

dng_status dng_field_verify(const dng_field* field, char* out_message, size_t capacity) {
  if (field == nullptr) return fail(dng::Status::kInvalidArgument, "field is NULL", out_message, capacity);
  dng::Diagnostic diag;
  return report(field->view.verifyHashes(&diag), diag, out_message, capacity);
}

void dng_field_close(dng_field* field) { delete field; }

dng_sample dng_field_sample(const dng_field* field, float x, float y, float z, uint32_t interpolation) {
  const dng::View empty;
  const dng::View& view = field != nullptr ? field->view : empty;
  const auto mode =
      interpolation == DNG_INTERPOLATION_TRILINEAR ? dng::Interpolation::kTrilinear : dng::Interpolation::kNearest;
  const dng::Sample s = view.sample({x, y, z}, mode);
  return dng_sample{s.distance, {s.normal.x, s.normal.y, s.normal.z}, uint32_t(s.status)};
}

void dng_material_default(dng_material* out) {
  if (out == nullptr) return;
  const dng::Material m;
  *out = dng_material{uint32_t(m.response), m.restitution,   m.collision_distance, m.spring_stiffness,
                      m.spring_distance,    m.drag,          m.contact_distance,   m.flow_in,
                      m.flow_out,           m.flow_distance, m.swept ? 1u : 0u};
}

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
    scene->bodies.push_back(body);
  } catch (const std::bad_alloc&) {
    return fail(dng::Status::kOutOfMemory, "out of memory", out_message, capacity);
  }
  *out_index = uint32_t(scene->bodies.size() - 1);
  return DNG_OK;
}

dng_status dng_scene_set_transform(dng_scene* scene, uint32_t body, const float m[12], char* out_message,
                                   size_t capacity) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr) return fail(dng::Status::kInvalidArgument, "no such scene or body", out_message, capacity);
  dng::Diagnostic diag;
  return report(b->setTransform(m, &diag), diag, out_message, capacity);
}

dng_status dng_scene_set_velocity(dng_scene* scene, uint32_t body, const float linear[3], const float angular[3]) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr || linear == nullptr || angular == nullptr) return DNG_INVALID_ARGUMENT;
  b->setVelocity({linear[0], linear[1], linear[2]}, {angular[0], angular[1], angular[2]});
  return DNG_OK;
}

dng_status dng_scene_set_material(dng_scene* scene, uint32_t body, const dng_material* material, char* out_message,
                                  size_t capacity) {
  dng::Body* b = bodyAt(scene, body);
  if (b == nullptr || material == nullptr)
    return fail(dng::Status::kInvalidArgument, "no such scene or body, or material is NULL", out_message, capacity);
  dng::Diagnostic diag;
  return report(b->setMaterial(toMaterial(*material), &diag), diag, out_message, capacity);
}

dng_status dng_scene_step(const dng_scene* scene, const dng_particles* p, float dt, char* out_message,
                          size_t capacity) {
  if (scene == nullptr || p == nullptr)
    return fail(dng::Status::kInvalidArgument, "scene and particles must not be NULL", out_message, capacity);
  const dng::ParticleSpan span{p->position_x, p->position_y,  p->position_z, p->position_stride,
                               p->velocity_x, p->velocity_y,  p->velocity_z, p->velocity_stride,
                               p->count,      p->out_contact, p->out_body};
  dng::Diagnostic diag;
  return report(dng::stepParticles(span, dt, scene->bodies.data(), scene->bodies.size(), &diag), diag, out_message,
                capacity);
}

} // extern "C"
