/* An out-of-tree program in C, built against an installed libdngrid through pkg-config
 * (setup.sh package): open a baked file, read its info, sample a batch, step particles at it.
 * Usage: c_consumer FILE.dng. Exit 0 when every particle thrown at the surface bounced. */
#include <dng/dng.h>

#include <stdio.h>

enum { kCount = 64 };

int main(int argc, char** argv) {
  char message[256];
  dng_field* field = NULL;
  dng_field_info info;
  uint32_t flags;
  dng_scene* scene = NULL;
  dng_material material;
  dng_particles particles = {0};
  dng_sample samples[kCount];
  float points[kCount][3], px[kCount], py[kCount], pz[kCount], vx[kCount], vy[kCount], vz[kCount];
  float centre[3], top;
  uint32_t body = 0;
  int i, step, in_band = 0, bounced = 0;

  if (argc != 2 || !dng_version_compatible(DNG_VERSION)) {
    fprintf(stderr, "usage: c_consumer FILE.dng (library %s)\n", dng_version_string());
    return 1;
  }
  if (dng_field_open_file(argv[1], &field, message, sizeof message) != DNG_OK) {
    fprintf(stderr, "c_consumer: %s\n", message);
    return 2;
  }
  dng_field_get_info(field, &info);
  for (i = 0; i < 3; ++i)
    centre[i] = 0.5f * (info.bounds_min[i] + info.bounds_max[i]);
  /* A column of points through the centre, top to bottom: some must cross the surface's band. */
  for (i = 0; i < kCount; ++i) {
    points[i][0] = centre[0];
    points[i][1] = centre[1];
    points[i][2] = info.bounds_min[2] + (info.bounds_max[2] - info.bounds_min[2]) * ((float)i + 0.5f) / kCount;
  }
  dng_field_sample_batch(field, points[0], sizeof points[0], kCount, samples, sizeof samples[0],
                         DNG_INTERPOLATION_TRILINEAR);
  for (i = 0; i < kCount; ++i)
    in_band += samples[i].status == DNG_SAMPLE_IN_BAND;

  /* Particles falling onto the top of the shape from just inside the grid's top. */
  dng_scene_create(&scene);
  dng_material_default(&material);
  material.collision_distance = 0.1f * info.voxel_size;
  if (dng_scene_add_body(scene, field, &material, &body, message, sizeof message) != DNG_OK) {
    fprintf(stderr, "c_consumer: %s\n", message);
    return 3;
  }
  top = info.bounds_max[2] - info.voxel_size;
  for (i = 0; i < kCount; ++i) {
    px[i] = centre[0] + 0.05f * info.voxel_size * (float)(i % 8);
    py[i] = centre[1] + 0.05f * info.voxel_size * (float)(i / 8);
    pz[i] = top;
    vx[i] = vy[i] = 0.0f;
    vz[i] = -info.guaranteed_reach * 30.0f; /* the design speed at dt = 1/30 */
  }
  particles.position_x = px, particles.position_y = py, particles.position_z = pz;
  particles.velocity_x = vx, particles.velocity_y = vy, particles.velocity_z = vz;
  particles.position_stride = particles.velocity_stride = sizeof(float);
  particles.count = kCount;
  for (step = 0; step < 300; ++step)
    dng_scene_step(scene, &particles, 1.0f / 30.0f, NULL, 0);
  for (i = 0; i < kCount; ++i)
    bounced += vz[i] > 0.0f || pz[i] > centre[2];
  printf("c_consumer: dngrid %s, format %s, %u x %u x %u voxels, %d of %d samples in band, %d of %d particles "
         "stayed above the surface, conservative planes %u\n",
         dng_version_string(), dng_format_version_string(), info.dims[0], info.dims[1], info.dims[2], in_band, kCount,
         bounced, kCount, info.conservative_planes);
  flags = dng_field_flags(field);
  dng_scene_destroy(scene);
  dng_field_close(field);
  /* dngbake's files promise conservative planes (format 1.1) and, by default, carry LIFT (1.2). */
  return in_band > 0 && bounced == kCount && info.conservative_planes == 1 &&
                 (flags & (DNG_FIELD_CONSERVATIVE_PLANES | DNG_FIELD_HAS_LIFT)) ==
                     (DNG_FIELD_CONSERVATIVE_PLANES | DNG_FIELD_HAS_LIFT)
             ? 0
             : 4;
}
