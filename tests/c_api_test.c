/* The C ABI from C: open a file, sample it, place a body, step particles through the scene.
 * Uses tests/golden/bricked_box.dng: a box of half extent 6.25 centred at the origin, grid
 * [-12, 12)^3 of unit voxels, band 2. */
#include "dng/dng.h"

#include <math.h>
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
  CHECK(strcmp(dng_status_string(DNG_TRUNCATED), "file truncated") == 0);
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
}

static void test_sampling(const dng_field* box) {
  dng_sample s = dng_field_sample(box, 6.75f, 0.25f, -0.5f, DNG_INTERPOLATION_NEAREST);
  CHECK(s.status == DNG_SAMPLE_IN_BAND);
  CHECK(fabsf(s.distance - 0.5f) < 0.05f);
  CHECK(s.normal[0] > 0.99f);
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
  material.restitution = 0.8f;
  material.collision_distance = 0.2f;
  CHECK(dng_scene_add_body(scene, box, &material, &body, message, sizeof message) == DNG_OK);
  CHECK(body == 0);
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
  test_stepping(box);
  dng_field_close(box);
  printf("c_api_test: %d passed, %d failed\n", checks - failures, failures);
  return failures == 0 ? 0 : 1;
}
