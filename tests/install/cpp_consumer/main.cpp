// An out-of-tree C++ program against the installed dngrid package: open a baked file, sample it,
// drop particles on it. Usage: cpp_consumer FILE.dng. Exit 0 when every particle stayed outside.
#include <dng/file.h>
#include <dng/forces.h>
#include <dng/particles.h>

#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cpp_consumer FILE.dng\n");
    return 1;
  }
  dng::File file;
  dng::Diagnostic diag;
  if (dng::File::open(argv[1], &file, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "cpp_consumer: %s\n", diag.message);
    return 2;
  }
  const dng::View& view = file.view();
  const dng::GridInfo& g = view.grid();
  const dng::Vec3f size = dng::Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  const dng::Vec3f centre = g.origin + size * 0.5f;
  const bool inside_centre =
      view.sample(centre, dng::Interpolation::kTrilinear).status == dng::SampleStatus::kFarInside;

  dng::Material material;
  material.collision_distance = 0.1f * g.voxel_size; // docs/RUNTIME.md: at least a tenth of a voxel
  dng::Body body;
  if (dng::Body::create(&view, material, &body, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "cpp_consumer: %s\n", diag.message);
    return 3;
  }
  const std::size_t n = 256;
  std::vector<float> px(n), py(n), pz(n), vx(n, 0.0f), vy(n, 0.0f), vz(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    px[i] = centre.x + 0.02f * size.x * float(int(i % 16) - 8);
    py[i] = centre.y + 0.02f * size.y * float(int(i / 16) - 8);
    pz[i] = g.origin.z + size.z - g.voxel_size;
  }
  dng::ParticleSpan span;
  span.position_x = px.data(), span.position_y = py.data(), span.position_z = pz.data();
  span.velocity_x = vx.data(), span.velocity_y = vy.data(), span.velocity_z = vz.data();
  span.count = n;
  const float dt = 1.0f / 60.0f;
  for (int step = 0; step < 240; ++step) {
    dng::applyGravity(span, {0, 0, -9.81f}, dt);
    if (dng::stepParticles(span, dt, &body, 1, &diag) != dng::Status::kOk) {
      std::fprintf(stderr, "cpp_consumer: %s\n", diag.message);
      return 4;
    }
  }
  std::size_t inside = 0;
  for (std::size_t i = 0; i < n; ++i)
    inside += view.sample({px[i], py[i], pz[i]}).distance < 0.0f;
  std::printf("cpp_consumer: %u x %u x %u voxels, centre %s, %zu of %zu particles inside after 4 s\n", g.dims[0],
              g.dims[1], g.dims[2], inside_centre ? "inside" : "not inside", inside, n);
  return inside_centre && inside == 0 ? 0 : 5;
}
