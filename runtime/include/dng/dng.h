/* dng.h: the C ABI of the dngrid runtime (libdngrid).
 *
 * Plain C89-compatible declarations: opaque handles, fixed-width integers and size_t only, a status
 * code on every call that can fail plus an optional message buffer the caller supplies. Nothing here
 * throws, aborts or allocates except the create/open calls, dng_scene_add_body and dng_scene_prepare_step.
 * Thread safety: a dng_field may be sampled from any number of threads; a dng_scene may be stepped by
 * any number of threads at once (disjoint particles) but must not be changed meanwhile.
 *
 * Check at start-up that the library matches the header you compiled against:
 *   if (!dng_version_compatible(DNG_VERSION)) { ... }
 */
#ifndef DNG_DNG_H
#define DNG_DNG_H

#include <stddef.h>
#include <stdint.h>

#include "dng/version.h"

#if defined(_WIN32)
#if defined(DNG_BUILDING_LIBRARY)
#define DNG_API __declspec(dllexport)
#else
#define DNG_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define DNG_API __attribute__((visibility("default")))
#else
#define DNG_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Status: the same numbers as dng::Status in C++. ---- */
typedef int32_t dng_status;
#define DNG_OK 0
#define DNG_INVALID_ARGUMENT 1
#define DNG_IO_ERROR 2
#define DNG_UNSUPPORTED_HOST 3
#define DNG_TRUNCATED 4
#define DNG_TRAILING_BYTES 5
#define DNG_BAD_MAGIC 6
#define DNG_UNSUPPORTED_VERSION 7
#define DNG_BAD_HEADER 8
#define DNG_HEADER_HASH_MISMATCH 9
#define DNG_BAD_SECTION_TABLE 10
#define DNG_SECTION_TABLE_HASH_MISMATCH 11
#define DNG_SECTION_OUT_OF_BOUNDS 12
#define DNG_SECTION_MISALIGNED 13
#define DNG_SECTION_OVERLAP 14
#define DNG_UNKNOWN_REQUIRED_SECTION 15
#define DNG_DUPLICATE_SECTION 16
#define DNG_MISSING_SECTION 17
#define DNG_BAD_GRID 18
#define DNG_UNSUPPORTED_ENCODING 19
#define DNG_BAD_PAYLOAD_SIZE 20
#define DNG_BAD_TILE_ENTRY 21
#define DNG_BAD_VALUE 22
#define DNG_SECTION_HASH_MISMATCH 23
#define DNG_OUT_OF_MEMORY 24
#define DNG_NONZERO_PADDING 25

/** Static English description of a status; never NULL. */
DNG_API const char* dng_status_string(dng_status status);

/** DNG_VERSION of the library itself. */
DNG_API uint32_t dng_version(void);
/** 1 when a program built against header version `header_version` (pass DNG_VERSION) can use this
 *  library: same major version, and the library's minor version is at least the header's. Else 0. */
DNG_API int32_t dng_version_compatible(uint32_t header_version);
/** The library's version as text, "major.minor.patch" (DNG_VERSION_STRING of the library, which may
 *  differ from the header's). Static storage; never NULL. Thread-safe. */
DNG_API const char* dng_version_string(void);
/** The newest .dng format version this library reads, "major.minor". Static; never NULL. Thread-safe. */
DNG_API const char* dng_format_version_string(void);

/* ---- Fields ---- */
typedef struct dng_field dng_field;

#define DNG_SAMPLE_NO_FIELD 0
#define DNG_SAMPLE_FAR_OUTSIDE 1
#define DNG_SAMPLE_FAR_INSIDE 2
#define DNG_SAMPLE_IN_BAND 3

#define DNG_INTERPOLATION_NEAREST 0
#define DNG_INTERPOLATION_TRILINEAR 1
#define DNG_INTERPOLATION_ACCURATE 2 /* closest to the true distance; not a bound (docs/RUNTIME.md) */

/** One query result; see docs/RUNTIME.md for what each status means. */
typedef struct dng_sample {
  float distance;
  float normal[3];
  uint32_t status; /* DNG_SAMPLE_* */
} dng_sample;

/** Maps and validates a .dng file. On success *out_field owns the mapping (dng_field_close frees it).
 *  On failure *out_field is NULL and, when out_message is not NULL, a NUL-terminated explanation of at
 *  most message_capacity bytes is written there. Safe on any file. */
DNG_API dng_status dng_field_open_file(const char* path, dng_field** out_field, char* out_message,
                                       size_t message_capacity);
/** Validates caller-owned bytes (8-byte aligned) without copying; they must outlive the field. */
DNG_API dng_status dng_field_open_memory(const void* bytes, size_t size, dng_field** out_field, char* out_message,
                                         size_t message_capacity);
/** Recomputes every section hash (the full check, O(file size)). DNG_INVALID_ARGUMENT for a NULL field. */
DNG_API dng_status dng_field_verify(const dng_field* field, char* out_message, size_t message_capacity);
/** Frees a field; NULL is allowed. Close bodies' scenes first. */
DNG_API void dng_field_close(dng_field* field);
/** The field at a grid-local point. A NULL field answers DNG_SAMPLE_NO_FIELD. */
DNG_API dng_sample dng_field_sample(const dng_field* field, float x, float y, float z, uint32_t interpolation);

/** Samples `count` points: point n is three floats at byte offset n * point_stride from `points`
 *  (stride >= 12), its answer is written at byte offset n * sample_stride from `out_samples` (stride >=
 *  sizeof(dng_sample); both strides multiples of 4). Rejects a NULL field or pointer (when count > 0),
 *  short or unaligned strides and a count whose span would not fit in memory with DNG_INVALID_ARGUMENT
 *  before writing anything. Thread-safe, no allocation. */
DNG_API dng_status dng_field_sample_batch(const dng_field* field, const float* points, size_t point_stride,
                                          size_t count, dng_sample* out_samples, size_t sample_stride,
                                          uint32_t interpolation);

#define DNG_ENCODING_DENSE 0
#define DNG_ENCODING_BRICKED 1

/** What a field holds. Lengths are in the grid's local units (the units the mesh was baked in). */
typedef struct dng_field_info {
  float bounds_min[3];          /* the grid's minimum corner (its origin) */
  float bounds_max[3];          /* bounds_min + dims * voxel_size */
  float voxel_size;             /* voxel edge */
  uint32_t dims[3];             /* voxels per axis */
  float band;                   /* distances are stored for |d| < band */
  float guaranteed_reach;       /* band - sqrt(3)/2 voxel_size: nearer points always answer in band */
  uint32_t encoding;            /* DNG_ENCODING_* */
  uint32_t brick_size;          /* bricked: brick edge in voxels; 0 for dense */
  uint32_t format_version[2];   /* the file's .dng version: major, minor */
  uint32_t conservative_planes; /* 1 when no voxel plane overestimates the distance (format 1.1 bakes):
                                   what dng_scene_step's walk needs to stop every particle */
  uint64_t file_bytes;          /* size of the file or memory block */
} dng_field_info;

/** Fills *out_info. DNG_INVALID_ARGUMENT (nothing written) when either is NULL. Thread-safe. */
DNG_API dng_status dng_field_get_info(const dng_field* field, dng_field_info* out_info);

/* What a field carries besides its distances and normals: bits of dng_field_flags. */
#define DNG_FIELD_CONSERVATIVE_PLANES 1u /* as dng_field_info.conservative_planes */
#define DNG_FIELD_HAS_LIFT                                                                                             \
  2u /* LIFT section: accurate queries read the distances from before the                                              \
        conservative lowering (docs/FORMAT.md 5.2) */
#define DNG_FIELD_HAS_GRADIENT                                                                                         \
  4u /* GRAD section: accurate queries read the distance's own gradient                                                \
        beside blurred normals (docs/FORMAT.md 5.3) */
#define DNG_FIELD_HAS_SHADING                                                                                          \
  8u /* SHAD section: queries and responses read the bake mode's normals                                               \
        beside planes that carry the distance's own (docs/FORMAT.md 5.4) */
#define DNG_FIELD_HAS_SECOND_PLANES                                                                                    \
  16u /* PLN2 section: second bounds beside edges and creases, which the step's walk reads                             \
         where a voxel's own plane proves nothing (docs/FORMAT.md 5.5) */
/** The DNG_FIELD_* bits that hold for the field; 0 when field is NULL. Bits not defined here are 0.
 *  Thread-safe. (A function, not a dng_field_info member, so that the struct keeps its size.) */
DNG_API uint32_t dng_field_flags(const dng_field* field);
/** Copies the bake's metadata (UTF-8 JSON, docs/BAKING.md) into out_text, truncated to capacity - 1
 *  bytes and NUL-terminated when capacity > 0; out_text may be NULL when capacity is 0. Returns the
 *  metadata's full length in bytes without the NUL (0 when the file has none or field is NULL), so a
 *  first call with capacity 0 sizes the buffer. Thread-safe. */
DNG_API size_t dng_field_metadata(const dng_field* field, char* out_text, size_t capacity);

/* ---- Materials, scenes of bodies, stepping ---- */
#define DNG_RESPONSE_IMPACT 0
#define DNG_RESPONSE_SPRING 1
#define DNG_RESPONSE_NONE 2

/** Mirrors dng::Material (dng/body.h); fill it with dng_material_default first. */
typedef struct dng_material {
  uint32_t response;        /* DNG_RESPONSE_* */
  float restitution;        /* beta */
  float collision_distance; /* L, world units */
  float spring_stiffness;   /* 1/s^2 */
  float spring_distance;    /* world units; 0 = the field's band */
  float drag;               /* delta, 1/s */
  float contact_distance;   /* theta, world units */
  float flow_in;            /* rho_in, world units/s^2 */
  float flow_out;           /* rho_out */
  float flow_distance;      /* world units */
  uint32_t swept;           /* 1 = 256 walk samples per step instead of 24 (docs/RUNTIME.md) */
} dng_material;

DNG_API void dng_material_default(dng_material* out_material);

/** A set of bodies stepped together. Bodies refer to fields, which must outlive the scene. */
typedef struct dng_scene dng_scene;

DNG_API dng_status dng_scene_create(dng_scene** out_scene);
DNG_API void dng_scene_destroy(dng_scene* scene);
/** Adds a body of `field` at the identity transform; its index is written to *out_index. */
DNG_API dng_status dng_scene_add_body(dng_scene* scene, const dng_field* field, const dng_material* material,
                                      uint32_t* out_index, char* out_message, size_t message_capacity);
/** Row-major 3x4 [s*R | t]; shear, non-uniform scale and reflections are rejected. */
DNG_API dng_status dng_scene_set_transform(dng_scene* scene, uint32_t body, const float row_major_3x4[12],
                                           char* out_message, size_t message_capacity);
/** World linear velocity and angular velocity (rad/s) about the body origin. */
DNG_API dng_status dng_scene_set_velocity(dng_scene* scene, uint32_t body, const float linear[3],
                                          const float angular[3]);
DNG_API dng_status dng_scene_set_material(dng_scene* scene, uint32_t body, const dng_material* material,
                                          char* out_message, size_t message_capacity);

/** Number of bodies in the scene (enabled or not); 0 for NULL. Body indices run from 0 to count - 1. */
DNG_API uint32_t dng_scene_body_count(const dng_scene* scene);
/** Removes a body. The last body takes its index (indices stay 0..count-1); every other index is
 *  unchanged. DNG_INVALID_ARGUMENT for a NULL scene or an index out of range. No allocation; O(bodies). */
DNG_API dng_status dng_scene_remove_body(dng_scene* scene, uint32_t body);
/** A disabled body keeps its index, transform, velocity and material but is skipped by dng_scene_step.
 *  Bodies start enabled. DNG_INVALID_ARGUMENT for a NULL scene or an index out of range. O(bodies). */
DNG_API dng_status dng_scene_set_body_enabled(dng_scene* scene, uint32_t body, int32_t enabled);
/** 1 when the body is enabled, 0 when disabled, -1 for a NULL scene or an index out of range. */
DNG_API int32_t dng_scene_body_enabled(const dng_scene* scene, uint32_t body);
/** The body's world-space axis-aligned bounding box (its grid under its transform). On failure (NULL
 *  argument, index out of range: DNG_INVALID_ARGUMENT) nothing is written. */
DNG_API dng_status dng_scene_body_bounds(const dng_scene* scene, uint32_t body, float out_min[3], float out_max[3]);
/** 1 when a particle placed at the world point `point` could be moved by dng_scene_step as far as this
 *  body goes: its field proves the point outside (dng::Body::provesOutside). 0 where the step would never
 *  move it, inside included, and for a non-finite point; -1 for a NULL argument or an index out of range.
 *  For testing spawn points. */
DNG_API int32_t dng_scene_body_proves_outside(const dng_scene* scene, uint32_t body, const float point[3]);

/** Mirrors dng::ParticleSpan: strides in bytes. out_contact and out_body may be NULL; when set they are
 *  packed arrays of count elements (no stride), element n for particle n. */
typedef struct dng_particles {
  float* position_x;
  float* position_y;
  float* position_z;
  size_t position_stride;
  float* velocity_x;
  float* velocity_y;
  float* velocity_z;
  size_t velocity_stride;
  size_t count;
  uint8_t* out_contact;
  int32_t* out_body;
} dng_particles;

/** Builds the scene's broadphase (dng::BodyIndex) for steps of dt seconds, so that dng_scene_step
 *  tests each particle only against the bodies near it. Call it once per frame after placing the bodies
 *  and before stepping (on one thread, before the step fans out). It stays in use until the scene
 *  changes (any set_*, add, remove or enable call) or a step asks for another dt; meanwhile steps test
 *  every enabled body, with the same results. May allocate: DNG_OUT_OF_MEMORY; DNG_INVALID_ARGUMENT for
 *  a NULL scene, dt not finite and > 0, or an enabled body whose velocities give no finite motion over
 *  dt. */
DNG_API dng_status dng_scene_prepare_step(dng_scene* scene, float dt, char* out_message, size_t message_capacity);

/** One step of dt seconds for every particle against every enabled body of the scene
 *  (dng::stepParticles), through the broadphase when dng_scene_prepare_step built it for this scene
 *  and dt. out_body receives scene body indices. DNG_INVALID_ARGUMENT, before any particle is touched,
 *  for a NULL scene or particle array (count > 0), dt not finite and > 0, strides that are not whole
 *  floats or whose span would not fit in memory, and an enabled body whose velocities give no finite
 *  motion over dt. No allocation. */
DNG_API dng_status dng_scene_step(const dng_scene* scene, const dng_particles* particles, float dt, char* out_message,
                                  size_t message_capacity);

#ifdef __cplusplus
}
#endif

#endif /* DNG_DNG_H */
