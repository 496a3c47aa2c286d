// dng_query: the smallest useful runtime program. Maps a .dng file, checks it, and prints the field
// at the points given on the command line (grid-local coordinates).
//
//   dng_query FILE.dng X Y Z [X Y Z ...]
#include "dng/file.h"

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc < 2 || (argc - 2) % 3 != 0) {
    std::fprintf(stderr, "usage: %s FILE.dng [X Y Z]...\n", argv[0]);
    return 1;
  }
  dng::File file;
  dng::Diagnostic diag;
  if (dng::File::open(argv[1], &file, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "dng_query: %s: %s (%s)\n", argv[1], dng::statusString(diag.status), diag.message);
    return 2;
  }
  const dng::GridInfo& grid = file.view().grid();
  std::printf("%u x %u x %u voxels of %g, band %g\n", grid.dims[0], grid.dims[1], grid.dims[2], double(grid.voxel_size),
              double(grid.band));
  for (int a = 2; a + 2 < argc; a += 3) {
    const dng::Vec3f p{std::strtof(argv[a], nullptr), std::strtof(argv[a + 1], nullptr),
                       std::strtof(argv[a + 2], nullptr)};
    const dng::Sample s = file.view().sample(p);
    if (s.status == dng::SampleStatus::kNoField) {
      std::printf("%g %g %g: none\n", double(p.x), double(p.y), double(p.z));
    } else {
      std::printf("%g %g %g: distance %g normal %g %g %g\n", double(p.x), double(p.y), double(p.z), double(s.distance),
                  double(s.normal.x), double(s.normal.y), double(s.normal.z));
    }
  }
  // On a full disk what printf wrote is lost: say so rather than exit 0 with the answers missing.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "dng_query: cannot write to standard output\n");
    return 2;
  }
  return 0;
}
