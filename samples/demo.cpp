// The README demo's particle scene: particles rain on a baked mesh (the Stanford bunny), bounce,
// slide with drag and flow off it. Prints one JSON line of statistics; exits 1 if any particle ends
// inside the mesh.
//   dng_demo MESH.dng [OUTPUT_FOLDER] [UP_AXIS: x, y or z; default z]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  const dng::File file = openFieldArgument(argc, argv, "[OUTPUT_FOLDER] [x|y|z]");
  RunOptions options;
  options.picture_prefix = outputFolder(argc, argv, 2) + "/demo";
  const int up = argc > 3 && argv[3][0] >= 'x' && argv[3][0] <= 'z' ? argv[3][0] - 'x' : 2;
  const SceneStats stats = runDemo(file.view(), up, options);
  std::printf("%s\n", stats.json("demo").c_str());
  return stats.inside == 0 ? 0 : 1;
}
