/* The C ABI from C: versions, open a file, its info and metadata, single and batch samples, place
 * bodies, step particles through the scene, disable and remove bodies, step through the broadphase.
 * Uses tests/golden/bricked_box.dng: a box of half extent 6.25 centred at the origin, grid
 * [-12, 12)^3 of unit voxels, band 2. */
#include "dng/dng.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;
static int checks = 0;

#define CHECK(condition)                                                                                               \
  do {                                                                                                                 \
    ++checks;                                                                                                          \
    if (!(condition)) {                                                                                                \
      ++failures;                                                                                                      \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #condition);                                    \
    }                                                                                                                  \
  } while (0)

static void test_versions(void) {
  CHECK(dng_version() == DNG_VERSION);
  CHECK(dng_version_compatible(DNG_VERSION) == 1);
  CHECK(dng_version_compatible(((uint32_t)(DNG_VERSION_MAJOR + 1) << 16)) == 0);
  /* A program built against an older minor version of this major one still runs; a newer one does not. */
  CHECK(dng_version_compatible((uint32_t)DNG_VERSION_MAJOR << 16) == 1);
  CHECK(dng_version_compatible(((uint32_t)DNG_VERSION_MAJOR << 16) | ((uint32_t)(DNG_VERSION_MINOR + 1) << 8)) == 0);
  CHECK(strcmp(dng_status_string(DNG_TRUNCATED), "file truncated") == 0);
  CHECK(strcmp(dng_version_string(), DNG_VERSION_STRING) == 0);
}

static void test_info(const dng_field* box) {
  dng_field_info info;
  char small[8];
  size_t length;
  memset(&info, 0xAB, sizeof info);
  CHECK(dng_field_get_info(box, &info) == DNG_OK);
  CHECK(info.bounds_min[0] == -12.0f && info.bounds_min[1] == -12.0f && info.bounds_min[2] == -12.0f);
  CHECK(info.bounds_max[0] == 12.0f && info.bounds_max[2] == 12.0f);
  CHECK(info.voxel_size == 1.0f);
  CHECK(info.dims[0] == 24 && info.dims[1] == 24 && info.dims[2] == 24);
  CHECK(info.band == 2.0f);
  CHECK(fabsf(info.guaranteed_reach - (2.0f - 0.8660254f)) < 1e-6f);
  CHECK(info.encoding == DNG_ENCODING_BRICKED);
  CHECK(info.brick_size > 0);
  CHECK(info.format_version[0] == 1);
  {
    /* The golden file was written by this tree's writer: the newest version, which the library reads. */
    char newest[16];
    snprintf(newest, sizeof newest, "%u.%u", (unsigned)info.format_version[0], (unsigned)info.format_version[1]);
    CHECK(strcmp(dng_format_version_string(), newest) == 0);
  }
  CHECK(info.file_bytes > 0);
  CHECK(info.conservative_planes == 0); /* written by the test writer, not dngbake (tests/install checks 1) */
  CHECK(dng_field_get_info(NULL, &info) == DNG_INVALID_ARGUMENT);
  CHECK(dng_field_get_info(box, NULL) == DNG_INVALID_ARGUMENT);

  /* Sizing call, then a truncated copy that is still NUL-terminated. */
  length = dng_field_metadata(box, NULL, 0);
  CHECK(length > 0);
  memset(small, 'x', sizeof small);
  CHECK(dng_field_metadata(box, small, sizeof small) == length);
  CHECK(small[sizeof small - 1] == '\0' && strlen(small) == sizeof small - 1);
  {
    char* text = (char*)malloc(length + 1);
    CHECK(dng_field_metadata(box, text, length + 1) == length);
    CHECK(text[0] == '{' && strlen(text) == length);
    free(text);
  }
  CHECK(dng_field_metadata(NULL, small, sizeof small) == 0 && small[0] == '\0');
}

/* Points inside structs (stride 20), answers into structs (stride 32): same as one-by-one sampling. */
static void test_batch(const dng_field* box) {
  typedef struct {
    float xyz[3];
    float pad[2];
  } point_t;
  typedef struct {
    dng_sample sample;
    uint32_t marker[3];
  } answer_t;
  enum { kCount = 150 };
  static point_t points[kCount];
  static answer_t answers[kCount];
  int i, same = 0, untouched = 0;
  uint32_t mode;
  for (mode = DNG_INTERPOLATION_NEAREST; mode <= DNG_INTERPOLATION_ACCURATE; ++mode) {
    for (i = 0; i < kCount; ++i) {
      points[i].xyz[0] = -14.0f + 0.19f * (float)i;
      points[i].xyz[1] = 0.3f;
      points[i].xyz[2] = -0.7f + 0.01f * (float)i;
      answers[i].marker[0] = 0xC0FFEEu;
    }
    CHECK(dng_field_sample_batch(box, points[0].xyz, sizeof(point_t), kCount, &answers[0].sample, sizeof(answer_t),
                                 mode) == DNG_OK);
    for (i = 0; i < kCount; ++i) {
      const dng_sample one = dng_field_sample(box, points[i].xyz[0], points[i].xyz[1], points[i].xyz[2], mode);
      same += one.status == answers[i].sample.status && (one.distance == answers[i].sample.distance ||
                                                         (isinf(one.distance) && isinf(answers[i].sample.distance)));
      untouched += answers[i].marker[0] == 0xC0FFEEu;
    }
  }
  CHECK(same == 3 * kCount);
  CHECK(untouched == 3 * kCount);
  CHECK(dng_field_sample_batch(box, points[0].xyz, 8, kCount, &answers[0].sample, sizeof(answer_t), 0) ==
        DNG_INVALID_ARGUMENT);
  CHECK(dng_field_sample_batch(box, points[0].xyz, 12, kCount, &answers[0].sample, 8, 0) == DNG_INVALID_ARGUMENT);
  CHECK(dng_field_sample_batch(NULL, points[0].xyz, 12, kCount, &answers[0].sample, sizeof(dng_sample), 0) ==
        DNG_INVALID_ARGUMENT);
  CHECK(dng_field_sample_batch(box, NULL, 12, 0, NULL, sizeof(dng_sample), 0) == DNG_OK);
}

static void test_open_errors(void) {
  char message[256] = "unchanged";
  dng_field* field = (dng_field*)&message; /* must be reset to NULL on failure */
  CHECK(dng_field_open_file("/nonexistent/box.dng", &field, message, sizeof message) == DNG_IO_ERROR);
  CHECK(field == NULL);
  CHECK(strstr(message, "box.dng") != NULL);
  {
    /* Every byte zero: not a .dng file. malloc memory is suitably aligned. */
    void* zeros = calloc(1, 4096);
    CHECK(dng_field_open_memory(zeros, 4096, &field, NULL, 0) == DNG_BAD_MAGIC);
    free(zeros);
  }
  CHECK(dng_field_open_file(NULL, &field, message, sizeof message) == DNG_INVALID_ARGUMENT);
  {
    /* Caller memory: none, misaligned (rule V2) or empty (V3); the field stays NULL each time. */
    unsigned char* bytes = (unsigned char*)calloc(1, 4096 + 8);
    field = (dng_field*)&message;
    CHECK(dng_field_open_memory(NULL, 4096, &field, message, sizeof message) == DNG_INVALID_ARGUMENT);
    CHECK(field == NULL && strstr(message, "V2") != NULL);
    CHECK(dng_field_open_memory(bytes + 4, 4096, &field, message, sizeof message) == DNG_INVALID_ARGUMENT);
    CHECK(field == NULL && strstr(message, "aligned") != NULL);
    CHECK(dng_field_open_memory(bytes, 0, &field, message, sizeof message) == DNG_TRUNCATED);
    CHECK(field == NULL);
    CHECK(dng_field_open_memory(bytes, 4096, NULL, message, sizeof message) == DNG_INVALID_ARGUMENT);
    free(bytes);
  }
}

static void test_sampling(const dng_field* box) {
  dng_sample s = dng_field_sample(box, 6.75f, 0.25f, -0.5f, DNG_INTERPOLATION_NEAREST);
  CHECK(s.status == DNG_SAMPLE_IN_BAND);
  CHECK(fabsf(s.distance - 0.5f) < 0.05f);
  CHECK(s.normal[0] > 0.99f);
  s = dng_field_sample(box, 6.75f, 0.25f, -0.5f, DNG_INTERPOLATION_ACCURATE); /* the face at x = 6.25 */
  CHECK(s.status == DNG_SAMPLE_IN_BAND);
  CHECK(fabsf(s.distance - 0.5f) < 0.01f);
  CHECK(s.normal[0] > 0.999f);
  s = dng_field_sample(box, 0.0f, 0.0f, 0.0f, DNG_INTERPOLATION_TRILINEAR);
  CHECK(s.status == DNG_SAMPLE_FAR_INSIDE);
  s = dng_field_sample(box, 50.0f, 0.0f, 0.0f, DNG_INTERPOLATION_NEAREST);
  CHECK(s.status == DNG_SAMPLE_NO_FIELD);
  s = dng_field_sample(NULL, 0.0f, 0.0f, 0.0f, DNG_INTERPOLATION_NEAREST);
  CHECK(s.status == DNG_SAMPLE_NO_FIELD);
  CHECK(dng_field_verify(box, NULL, 0) == DNG_OK);
}

/* The box placed at x = 10, scaled by 2 (half extent 12.5), particles thrown at its +x face. */
static void test_stepping(const dng_field* box) {
  enum { kCount = 100 };
  static float px[kCount], py[kCount], pz[kCount], vx[kCount], vy[kCount], vz[kCount];
  static uint8_t contact[kCount];
  static int32_t touched[kCount];
  const float place[12] = {2, 0, 0, 10, 0, 2, 0, 0, 0, 0, 2, 0};
  const float shear[12] = {2, 1, 0, 10, 0, 2, 0, 0, 0, 0, 2, 0};
  const float zero3[3] = {0, 0, 0};
  char message[256];
  dng_scene* scene = NULL;
  dng_material material;
  dng_particles particles;
  uint32_t body = 99;
  int i, step, bounced = 0, outside = 0;

  CHECK(dng_scene_create(&scene) == DNG_OK);
  dng_material_default(&material);
  material.restitution = 0.0f; /* would stop the particles at the face; replaced below */
  material.collision_distance = 0.2f;
  CHECK(dng_scene_add_body(scene, box, &material, &body, message, sizeof message) == DNG_OK);
  CHECK(body == 0);
  material.restitution = -1.0f;
  CHECK(dng_scene_set_material(scene, body, &material, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "restitution") != NULL);
  CHECK(dng_scene_set_material(scene, 3, &material, message, sizeof message) == DNG_INVALID_ARGUMENT);
  material.restitution = 0.8f; /* the bounce-back checked after stepping shows this one took effect */
  CHECK(dng_scene_set_material(scene, body, &material, message, sizeof message) == DNG_OK);
  CHECK(dng_scene_set_transform(scene, body, place, message, sizeof message) == DNG_OK);
  CHECK(dng_scene_set_transform(scene, body, shear, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "shear") != NULL);
  CHECK(dng_scene_set_velocity(scene, 7, zero3, zero3) == DNG_INVALID_ARGUMENT);

  for (i = 0; i < kCount; ++i) {
    px[i] = 40.0f;
    py[i] = -10.0f + 0.2f * (float)i;
    pz[i] = 3.0f;
    vx[i] = -60.0f;
    vy[i] = vz[i] = 0.0f;
  }
  particles.position_x = px, particles.position_y = py, particles.position_z = pz;
  particles.velocity_x = vx, particles.velocity_y = vy, particles.velocity_z = vz;
  particles.position_stride = particles.velocity_stride = sizeof(float);
  particles.count = kCount;
  particles.out_contact = contact;
  particles.out_body = touched;
  for (step = 0; step < 60; ++step) {
    CHECK(dng_scene_step(scene, &particles, 1.0f / 60.0f, message, sizeof message) == DNG_OK);
    for (i = 0; i < kCount; ++i)
      bounced += contact[i] && touched[i] == 0;
  }
  for (i = 0; i < kCount; ++i)
    outside += px[i] > 10.0f + 12.5f && vx[i] > 0.0f;
  CHECK(bounced >= kCount);
  CHECK(outside == kCount);
  CHECK(dng_scene_step(scene, &particles, -1.0f, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "dt") != NULL);
  { /* a body whose velocity is not a number moves no particle, with or without the broadphase */
    const float drift[3] = {NAN, 0.0f, 0.0f}, still[3] = {0.0f, 0.0f, 0.0f};
    const float before = px[0];
    CHECK(dng_scene_set_velocity(scene, 0, drift, still) == DNG_OK);
    CHECK(dng_scene_prepare_step(scene, 1.0f / 60.0f, message, sizeof message) == DNG_INVALID_ARGUMENT);
    CHECK(dng_scene_step(scene, &particles, 1.0f / 60.0f, message, sizeof message) == DNG_INVALID_ARGUMENT);
    CHECK(strstr(message, "finite motion") != NULL);
    CHECK(px[0] == before);
  }
  dng_scene_destroy(scene);
}

/* Two boxes side by side: count, bounds, disable, remove (the last body takes the index). */
static void test_scene_queries(const dng_field* box) {
  const float left[12] = {1, 0, 0, -30, 0, 1, 0, 0, 0, 0, 1, 0};
  const float right[12] = {1, 0, 0, 30, 0, 1, 0, 0, 0, 0, 1, 0};
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  float px = 30.0f + 6.25f + 0.5f, py = 0.0f, pz = 0.0f, vx = -20.0f, vy = 0.0f, vz = 0.0f;
  const float beside[3] = {30.0f + 6.25f + 0.5f, 0.0f, 0.0f}, centre[3] = {30.0f, 0.0f, 0.0f};
  uint8_t contact = 0;
  int32_t touched = -7;
  dng_scene* scene = NULL;
  dng_material material;
  dng_particles one;
  uint32_t a = 99, b = 99;

  CHECK(dng_scene_body_count(NULL) == 0);
  CHECK(dng_scene_create(&scene) == DNG_OK);
  CHECK(dng_scene_body_count(scene) == 0);
  dng_material_default(&material);
  material.collision_distance = 0.2f;
  CHECK(dng_scene_add_body(scene, box, &material, &a, NULL, 0) == DNG_OK);
  CHECK(dng_scene_add_body(scene, box, &material, &b, NULL, 0) == DNG_OK);
  CHECK(a == 0 && b == 1 && dng_scene_body_count(scene) == 2);
  CHECK(dng_scene_set_transform(scene, a, left, NULL, 0) == DNG_OK);
  CHECK(dng_scene_set_transform(scene, b, right, NULL, 0) == DNG_OK);
  CHECK(dng_scene_body_bounds(scene, b, lo, hi) == DNG_OK);
  CHECK(lo[0] == 18.0f && hi[0] == 42.0f && lo[1] == -12.0f && hi[2] == 12.0f);
  CHECK(dng_scene_body_bounds(scene, 2, lo, hi) == DNG_INVALID_ARGUMENT);
  CHECK(lo[0] == 18.0f); /* untouched on failure */
  CHECK(dng_scene_body_enabled(scene, a) == 1 && dng_scene_body_enabled(scene, 5) == -1);
  /* Spawn points: half a unit outside the right box's +x face is proven outside, its centre is not. */
  CHECK(dng_scene_body_proves_outside(scene, b, beside) == 1);
  CHECK(dng_scene_body_proves_outside(scene, b, centre) == 0);
  CHECK(dng_scene_body_proves_outside(scene, a, beside) == 1); /* the left box is far away */
  CHECK(dng_scene_body_proves_outside(NULL, b, beside) == -1);
  CHECK(dng_scene_body_proves_outside(scene, 2, beside) == -1);
  CHECK(dng_scene_body_proves_outside(scene, b, NULL) == -1);

  /* A particle half a unit outside the right box's +x face, moving in. */
  memset(&one, 0, sizeof one);
  one.position_x = &px, one.position_y = &py, one.position_z = &pz;
  one.velocity_x = &vx, one.velocity_y = &vy, one.velocity_z = &vz;
  one.position_stride = one.velocity_stride = sizeof(float);
  one.count = 1;
  one.out_contact = &contact;
  one.out_body = &touched;
  /* Disable the left box: the right one is now the only packed body, yet out_body names index 1. */
  CHECK(dng_scene_set_body_enabled(scene, a, 0) == DNG_OK);
  CHECK(dng_scene_body_enabled(scene, a) == 0);
  CHECK(dng_scene_step(scene, &one, 1.0f / 60.0f, NULL, 0) == DNG_OK);
  CHECK(contact == 1 && touched == 1 && vx > 0.0f);

  /* Disabled, the right box lets the particle through untouched. */
  CHECK(dng_scene_set_body_enabled(scene, b, 0) == DNG_OK);
  px = 30.0f + 6.25f + 0.5f, vx = -20.0f;
  CHECK(dng_scene_step(scene, &one, 1.0f / 60.0f, NULL, 0) == DNG_OK);
  CHECK(contact == 0 && touched == -1 && vx == -20.0f);

  /* Remove the left box: the right one (last) takes index 0 and keeps its place and its state. */
  CHECK(dng_scene_remove_body(scene, a) == DNG_OK);
  CHECK(dng_scene_body_count(scene) == 1);
  CHECK(dng_scene_body_enabled(scene, 0) == 0);
  CHECK(dng_scene_body_bounds(scene, 0, lo, hi) == DNG_OK && lo[0] == 18.0f);
  CHECK(dng_scene_set_body_enabled(scene, 0, 1) == DNG_OK);
  px = 30.0f + 6.25f + 0.5f, vx = -20.0f;
  CHECK(dng_scene_step(scene, &one, 1.0f / 60.0f, NULL, 0) == DNG_OK);
  CHECK(contact == 1 && touched == 0 && vx > 0.0f);
  CHECK(dng_scene_remove_body(scene, 1) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_remove_body(scene, 0) == DNG_OK && dng_scene_body_count(scene) == 0);
  CHECK(dng_scene_remove_body(NULL, 0) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_set_body_enabled(scene, 0, 1) == DNG_INVALID_ARGUMENT);
  dng_scene_destroy(scene);
}

/* Forty boxes in a row, every other one spinning, particles thrown at each: a scene stepped through its
 * broadphase (dng_scene_prepare_step) ends bit for bit where the same scene stepped without it does,
 * also after a change makes the broadphase stale and with a disabled body. */
enum { kRowBoxes = 40, kRowParticles = 400 };
typedef struct RowState {
  float px[kRowParticles], py[kRowParticles], pz[kRowParticles], vx[kRowParticles], vy[kRowParticles],
      vz[kRowParticles];
  uint8_t contact[kRowParticles];
  int32_t touched[kRowParticles];
} RowState;

static dng_scene* row_scene(const dng_field* box) {
  dng_scene* scene = NULL;
  dng_material material;
  uint32_t i, index;
  const float spin[3] = {0.0f, 0.0f, 2.0f}, still[3] = {0.0f, 0.0f, 0.0f};
  CHECK(dng_scene_create(&scene) == DNG_OK);
  dng_material_default(&material);
  material.collision_distance = 0.2f;
  for (i = 0; i < kRowBoxes; ++i) {
    const float place[12] = {1, 0, 0, 30.0f * (float)i, 0, 1, 0, 0, 0, 0, 1, 0};
    CHECK(dng_scene_add_body(scene, box, &material, &index, NULL, 0) == DNG_OK);
    CHECK(dng_scene_set_transform(scene, index, place, NULL, 0) == DNG_OK);
    CHECK(dng_scene_set_velocity(scene, index, still, i % 2 ? spin : still) == DNG_OK);
  }
  CHECK(dng_scene_set_body_enabled(scene, 7, 0) == DNG_OK);
  return scene;
}

static void row_particles(RowState* state, dng_particles* out) {
  int n;
  for (n = 0; n < kRowParticles; ++n) {
    state->px[n] = 30.0f * (float)(n % kRowBoxes) + 9.0f + 0.01f * (float)n;
    state->py[n] = -8.0f + 0.04f * (float)n;
    state->pz[n] = 3.0f - 0.01f * (float)n;
    state->vx[n] = -50.0f - 0.1f * (float)n;
    state->vy[n] = 5.0f;
    state->vz[n] = n % 3 == 0 ? 200.0f : 0.0f; /* some long moves too */
  }
  memset(out, 0, sizeof *out);
  out->position_x = state->px, out->position_y = state->py, out->position_z = state->pz;
  out->velocity_x = state->vx, out->velocity_y = state->vy, out->velocity_z = state->vz;
  out->position_stride = out->velocity_stride = sizeof(float);
  out->count = kRowParticles;
  out->out_contact = state->contact;
  out->out_body = state->touched;
}

static void test_scene_broadphase(const dng_field* box) {
  static RowState plain_state, fast_state;
  const float moved[12] = {1, 0, 0, 31.0f, 0, 1, 0, 0.5f, 0, 0, 1, 0};
  const float dt = 1.0f / 60.0f;
  dng_scene* plain = row_scene(box);
  dng_scene* fast = row_scene(box);
  dng_particles plain_particles, fast_particles;
  char message[256];
  int step, n, contacts = 0;
  row_particles(&plain_state, &plain_particles);
  row_particles(&fast_state, &fast_particles);
  CHECK(dng_scene_prepare_step(NULL, dt, NULL, 0) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_prepare_step(fast, -dt, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "dt") != NULL);
  for (step = 0; step < 30; ++step) {
    if (step == 20) { /* a change: the broadphase is stale until the next prepare, and unused meanwhile */
      CHECK(dng_scene_set_transform(plain, 1, moved, NULL, 0) == DNG_OK);
      CHECK(dng_scene_set_transform(fast, 1, moved, NULL, 0) == DNG_OK);
    }
    if (step < 20 || step >= 25) CHECK(dng_scene_prepare_step(fast, dt, message, sizeof message) == DNG_OK);
    CHECK(dng_scene_step(plain, &plain_particles, dt, NULL, 0) == DNG_OK);
    CHECK(dng_scene_step(fast, &fast_particles, dt, NULL, 0) == DNG_OK);
    for (n = 0; n < kRowParticles; ++n)
      contacts += fast_state.contact[n];
  }
  CHECK(memcmp(&plain_state, &fast_state, sizeof plain_state) == 0);
  CHECK(contacts > kRowParticles / 2); /* the particles met the boxes: the comparison says something */
  /* Another dt than the prepared one: stepped without the broadphase, still fine. */
  CHECK(dng_scene_step(fast, &fast_particles, 0.5f * dt, NULL, 0) == DNG_OK);
  dng_scene_destroy(plain);
  dng_scene_destroy(fast);
}

/* The optional sections' bits, on the golden files that have them and on the plain box. */
static void test_flags(const dng_field* box) {
  static const struct {
    const char* path;
    uint32_t flags;
  } kFiles[] = {{DNG_GOLDEN_DIR "/bricked_box_lifted.dng", DNG_FIELD_HAS_LIFT},
                {DNG_GOLDEN_DIR "/bricked_box_graded.dng", DNG_FIELD_HAS_LIFT | DNG_FIELD_HAS_GRADIENT},
                {DNG_GOLDEN_DIR "/bricked_box_shaded.dng", DNG_FIELD_HAS_LIFT | DNG_FIELD_HAS_SHADING},
                {DNG_GOLDEN_DIR "/bricked_box_second_planes.dng", DNG_FIELD_HAS_LIFT | DNG_FIELD_HAS_SECOND_PLANES}};
  char message[256];
  size_t i;
  CHECK(dng_field_flags(box) == 0);
  CHECK(dng_field_flags(NULL) == 0);
  for (i = 0; i < sizeof kFiles / sizeof kFiles[0]; ++i) {
    dng_field* field = NULL;
    CHECK(dng_field_open_file(kFiles[i].path, &field, message, sizeof message) == DNG_OK);
    CHECK(dng_field_flags(field) == kFiles[i].flags);
    dng_field_close(field);
  }
}

/* Documented error paths: each call is refused before it writes anything, and what it leaves alone is
 * checked to be as it was. */
static void test_refusals(const dng_field* box) {
  enum { kCount = 4 };
  float px[kCount] = {20, 21, 22, 23}, py[kCount] = {0}, pz[kCount] = {0};
  float vx[kCount] = {-1, -1, -1, -1}, vy[kCount] = {0}, vz[kCount] = {0};
  float points[3 * kCount] = {0};
  dng_sample answers[kCount];
  const float place[12] = {1, 0, 0, 3, 0, 1, 0, 0, 0, 0, 1, 0};
  const float not_finite[12] = {1, 0, 0, NAN, 0, 1, 0, 0, 0, 0, 1, 0};
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  char message[256], tiny[4];
  dng_scene* scene = NULL;
  dng_material material;
  dng_particles particles;
  uint32_t body = 0;
  int i, kept = 0;

  /* A count whose span at these strides wraps around the address space, and bad strides: nothing
   * written. (A real count and stride would have read and written past the arrays.) */
  memset(answers, 0x5A, sizeof answers);
  CHECK(dng_field_sample_batch(box, points, 12, SIZE_MAX / 12 + 1, answers, sizeof(dng_sample), 0) ==
        DNG_INVALID_ARGUMENT);
  CHECK(dng_field_sample_batch(box, points, 12, SIZE_MAX / sizeof(dng_sample) + 1, answers, sizeof(dng_sample), 0) ==
        DNG_INVALID_ARGUMENT);
  CHECK(dng_field_sample_batch(box, points, 14, kCount, answers, sizeof(dng_sample), 0) == DNG_INVALID_ARGUMENT);
  for (i = 0; i < (int)sizeof answers; ++i)
    kept += ((const unsigned char*)answers)[i] == 0x5A;
  CHECK(kept == (int)sizeof answers);

  CHECK(dng_field_verify(NULL, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "NULL") != NULL);
  CHECK(dng_scene_create(NULL) == DNG_INVALID_ARGUMENT);
  CHECK(strcmp(dng_status_string(-1), "unknown status") == 0);

  CHECK(dng_scene_create(&scene) == DNG_OK);
  dng_material_default(&material);
  CHECK(dng_scene_add_body(NULL, box, &material, &body, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_add_body(scene, NULL, &material, &body, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_add_body(scene, box, NULL, &body, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_add_body(scene, box, &material, NULL, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_body_count(scene) == 0);
  CHECK(dng_scene_add_body(scene, box, &material, &body, message, sizeof message) == DNG_OK);
  CHECK(dng_scene_set_velocity(scene, body, NULL, lo) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_set_velocity(scene, body, lo, NULL) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_body_bounds(scene, body, NULL, hi) == DNG_INVALID_ARGUMENT);
  CHECK(dng_scene_body_bounds(scene, body, lo, NULL) == DNG_INVALID_ARGUMENT);
  {
    const float nowhere[3] = {NAN, 0.0f, 0.0f}, far_out[3] = {INFINITY, 0.0f, 0.0f};
    CHECK(dng_scene_body_proves_outside(scene, body, nowhere) == 0);
    CHECK(dng_scene_body_proves_outside(scene, body, far_out) == 0);
    CHECK(dng_scene_body_proves_outside(scene, body, NULL) == -1);
  }
  CHECK(dng_scene_set_transform(scene, body, place, message, sizeof message) == DNG_OK);
  /* A refused transform keeps the previous one; a message cut to the capacity stays NUL-terminated. */
  memset(tiny, 'x', sizeof tiny);
  CHECK(dng_scene_set_transform(scene, body, not_finite, tiny, 3) == DNG_INVALID_ARGUMENT);
  CHECK(tiny[2] == '\0' && strlen(tiny) == 2 && tiny[3] == 'x');
  CHECK(dng_scene_body_bounds(scene, body, lo, hi) == DNG_OK);
  CHECK(lo[0] == -9.0f && hi[0] == 15.0f && lo[1] == -12.0f);

  /* The step refuses a span that cannot be memory, and a stride that is not whole floats, leaving every
   * particle as it was. */
  particles.position_x = px, particles.position_y = py, particles.position_z = pz;
  particles.velocity_x = vx, particles.velocity_y = vy, particles.velocity_z = vz;
  particles.position_stride = particles.velocity_stride = sizeof(float);
  particles.out_contact = NULL;
  particles.out_body = NULL;
  particles.count = SIZE_MAX / 4 + 1;
  CHECK(dng_scene_step(scene, &particles, 0.1f, message, sizeof message) == DNG_INVALID_ARGUMENT);
  CHECK(strstr(message, "fit in memory") != NULL);
  particles.count = kCount;
  particles.velocity_stride = 6;
  CHECK(dng_scene_step(scene, &particles, 0.1f, message, sizeof message) == DNG_INVALID_ARGUMENT);
  kept = 0;
  for (i = 0; i < kCount; ++i)
    kept += px[i] == 20.0f + (float)i && vx[i] == -1.0f;
  CHECK(kept == kCount);
  dng_scene_destroy(scene);
}

/* A body at rest scaled past about 1e18: its reach's length overflows a float, which must not make the
 * scene unsteppable (it did: 0 spin times an infinite reach read as a motion that is not finite). */
static void test_huge_resting_body(const dng_field* box) {
  const float huge[12] = {1e18f, 0, 0, 0, 0, 1e18f, 0, 0, 0, 0, 1e18f, 0};
  float x = 3e19f, y = 0.0f, z = 0.0f, vx = -1.0f, vy = 0.0f, vz = 0.0f;
  char message[256];
  dng_scene* scene = NULL;
  dng_material material;
  dng_particles particles;
  uint32_t body = 0;
  CHECK(dng_scene_create(&scene) == DNG_OK);
  dng_material_default(&material);
  CHECK(dng_scene_add_body(scene, box, &material, &body, message, sizeof message) == DNG_OK);
  CHECK(dng_scene_set_transform(scene, body, huge, message, sizeof message) == DNG_OK);
  CHECK(dng_scene_prepare_step(scene, 1.0f / 60.0f, message, sizeof message) == DNG_OK);
  particles.position_x = &x, particles.position_y = &y, particles.position_z = &z;
  particles.velocity_x = &vx, particles.velocity_y = &vy, particles.velocity_z = &vz;
  particles.position_stride = particles.velocity_stride = sizeof(float);
  particles.count = 1;
  particles.out_contact = NULL;
  particles.out_body = NULL;
  CHECK(dng_scene_step(scene, &particles, 1.0f / 60.0f, message, sizeof message) == DNG_OK);
  dng_scene_destroy(scene);
}

int main(void) {
  char message[256];
  dng_field* box = NULL;
  test_versions();
  test_open_errors();
  if (dng_field_open_file(DNG_GOLDEN_DIR "/bricked_box.dng", &box, message, sizeof message) != DNG_OK) {
    fprintf(stderr, "cannot open the golden box: %s\n", message);
    return 1;
  }
  test_sampling(box);
  test_info(box);
  test_flags(box);
  test_batch(box);
  test_stepping(box);
  test_scene_queries(box);
  test_scene_broadphase(box);
  test_refusals(box);
  test_huge_resting_body(box);
  dng_field_close(box);
  printf("c_api_test: %d passed, %d failed\n", checks - failures, failures);
  return failures == 0 ? 0 : 1;
}
