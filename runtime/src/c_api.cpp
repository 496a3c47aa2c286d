// The C ABI (dng/dng.h) over the C++ runtime: versions, fields and materials (scenes are in
// c_api_scene.cpp). Handles are heap objects made at open/create time; besides them only
// dng_scene_add_body (the body arrays) and dng_scene_prepare_step (the broadphase) allocate. No exception
// can leave: both catch std::bad_alloc (BodyIndex::rebuild inside) and report DNG_OUT_OF_MEMORY.
#include "c_api_internal.h"
#include "strided.h"

#include "dng/format/layout.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <new>

namespace dng {
namespace c_api {

dng_status report(Status status, const Diagnostic& diag, char* out, std::size_t capacity) {
  if (out != nullptr && capacity > 0) {
    const char* text = status == Status::kOk ? "" : diag.message[0] ? diag.message : statusString(status);
    // C callers get one string: the rule leads it, as in dngdump's findings ("V8: file is truncated...").
    const bool ruled = status != Status::kOk && diag.rule[0] != '\0';
    std::snprintf(out, capacity, "%s%s%s", ruled ? diag.rule : "", ruled ? ": " : "", text);
  }
  return dng_status(status);
}

dng_status fail(Status status, const char* text, char* out, std::size_t capacity) {
  Diagnostic diag;
  std::snprintf(diag.message, sizeof diag.message, "%s", text);
  return report(status, diag, out, capacity);
}

} // namespace c_api
} // namespace dng

namespace {

using dng::c_api::fail;
using dng::c_api::report;

static_assert(sizeof(dng_sample) == sizeof(dng::Sample), "dng_sample mirrors dng::Sample");
static_assert(DNG_SECTION_HASH_MISMATCH == int(dng::Status::kSectionHashMismatch), "status numbers match");
static_assert(DNG_OUT_OF_MEMORY == int(dng::Status::kOutOfMemory), "status numbers match");
static_assert(DNG_NONZERO_PADDING == int(dng::Status::kNonZeroPadding), "status numbers match");
static_assert(DNG_ENCODING_BRICKED == int(dng::format::Encoding::kBricked), "encoding numbers match");

dng_sample toC(const dng::Sample& s) {
  return dng_sample{s.distance, {s.normal.x, s.normal.y, s.normal.z}, uint32_t(s.status)};
}

dng::Interpolation toInterpolation(uint32_t interpolation) {
  if (interpolation == DNG_INTERPOLATION_ACCURATE) return dng::Interpolation::kAccurate;
  return interpolation == DNG_INTERPOLATION_TRILINEAR ? dng::Interpolation::kTrilinear : dng::Interpolation::kNearest;
}

// "major.minor" of the format this library reads, spelt at compile time (no allocation at run time).
static_assert(dng::format::kVersionMajor < 10 && dng::format::kVersionMinor < 10, "widen kFormatVersion");
constexpr char kFormatVersion[] = {char('0' + dng::format::kVersionMajor), '.', char('0' + dng::format::kVersionMinor),
                                   '\0'};

} // namespace

extern "C" {

const char* dng_status_string(dng_status status) { return dng::statusString(dng::Status(status)); }

uint32_t dng_version(void) { return DNG_VERSION; }

int32_t dng_version_compatible(uint32_t header_version) {
  const uint32_t major = header_version >> 16, minor = (header_version >> 8) & 0xFFu;
  return major == DNG_VERSION_MAJOR && minor <= DNG_VERSION_MINOR ? 1 : 0;
}

const char* dng_version_string(void) { return DNG_VERSION_STRING; }

const char* dng_format_version_string(void) { return kFormatVersion; }

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
  return toC(view.sample({x, y, z}, toInterpolation(interpolation)));
}

// The runtime's batch query writes packed samples; a small stack buffer carries them to the caller's
// stride, so any layout costs one copy and no allocation.
dng_status dng_field_sample_batch(const dng_field* field, const float* points, size_t point_stride, size_t count,
                                  dng_sample* out_samples, size_t sample_stride, uint32_t interpolation) {
  if (field == nullptr || (count > 0 && (points == nullptr || out_samples == nullptr)) || point_stride < 12 ||
      point_stride % 4 != 0 || sample_stride < sizeof(dng_sample) || sample_stride % 4 != 0 ||
      !dng::spanFits(count, point_stride) || !dng::spanFits(count, sample_stride))
    return DNG_INVALID_ARGUMENT;
  constexpr std::size_t kChunk = 64;
  dng::Sample chunk[kChunk];
  auto* out_bytes = reinterpret_cast<unsigned char*>(out_samples);
  const auto* point_bytes = reinterpret_cast<const unsigned char*>(points);
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t n = std::min(kChunk, count - first);
    field->view.sampleBatch(reinterpret_cast<const float*>(point_bytes + first * point_stride), point_stride, n, chunk,
                            toInterpolation(interpolation));
    for (std::size_t k = 0; k < n; ++k) {
      const dng_sample s = toC(chunk[k]);
      std::memcpy(out_bytes + (first + k) * sample_stride, &s, sizeof s);
    }
  }
  return DNG_OK;
}

dng_status dng_field_get_info(const dng_field* field, dng_field_info* out_info) {
  if (field == nullptr || out_info == nullptr) return DNG_INVALID_ARGUMENT;
  const dng::View& view = field->view;
  const dng::GridInfo& g = view.grid();
  dng_field_info info{};
  const float origin[3] = {g.origin.x, g.origin.y, g.origin.z};
  for (int a = 0; a < 3; ++a) {
    info.bounds_min[a] = origin[a];
    info.bounds_max[a] = origin[a] + float(g.dims[a]) * g.voxel_size;
    info.dims[a] = g.dims[a];
  }
  info.voxel_size = g.voxel_size;
  info.band = g.band;
  info.guaranteed_reach = view.guaranteedReach();
  info.encoding = uint32_t(g.encoding);
  info.brick_size = g.brick_size;
  info.format_version[0] = view.versionMajor();
  info.format_version[1] = view.versionMinor();
  info.conservative_planes = view.conservativePlanes() ? 1u : 0u;
  info.file_bytes = view.sizeBytes();
  *out_info = info;
  return DNG_OK;
}

uint32_t dng_field_flags(const dng_field* field) {
  if (field == nullptr) return 0;
  const dng::View& view = field->view;
  return (view.conservativePlanes() ? DNG_FIELD_CONSERVATIVE_PLANES : 0u) | (view.hasLift() ? DNG_FIELD_HAS_LIFT : 0u) |
         (view.hasGradient() ? DNG_FIELD_HAS_GRADIENT : 0u) | (view.hasShading() ? DNG_FIELD_HAS_SHADING : 0u) |
         (view.hasSecondPlanes() ? DNG_FIELD_HAS_SECOND_PLANES : 0u);
}

size_t dng_field_metadata(const dng_field* field, char* out_text, size_t capacity) {
  const std::string_view text = field != nullptr ? field->view.metadata() : std::string_view();
  if (out_text != nullptr && capacity > 0) {
    const std::size_t n = std::min(text.size(), capacity - 1);
    if (n > 0) std::memcpy(out_text, text.data(), n);
    out_text[n] = '\0';
  }
  return text.size();
}

void dng_material_default(dng_material* out) {
  if (out == nullptr) return;
  const dng::Material m;
  *out = dng_material{uint32_t(m.response), m.restitution,   m.collision_distance, m.spring_stiffness,
                      m.spring_distance,    m.drag,          m.contact_distance,   m.flow_in,
                      m.flow_out,           m.flow_distance, m.swept ? 1u : 0u};
}

} // extern "C"
