// Fig. 3 of the paper: particles falling on an object. (a) bouncy, beta = 0.7; (b) slippery,
// beta = 0; (c) high drag, beta = 0, delta = 2, theta = 1 voxel.
//   dng_fig3_falling [OUTPUT_FOLDER]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  const std::string out = outputFolder(argc, argv);
  const struct {
    const char* name;
    float restitution, drag;
  } variants[] = {{"fig3a_bouncy", 0.7f, 0.0f}, {"fig3b_slippery", 0.0f, 0.0f}, {"fig3c_drag", 0.0f, 2.0f}};
  for (const auto& v : variants) {
    RunOptions options;
    options.picture_prefix = out + "/" + v.name;
    const FallingResult r = runFalling(v.restitution, v.drag, options);
    std::printf("%s\n", r.stats.json(v.name).c_str());
    std::printf("{\"sample\":\"%s\",\"mean_rebound_height\":%.3f,\"fraction_resting_on_top\":%.3f}\n", v.name,
                double(r.mean_rebound_height), double(r.fraction_resting_on_top));
    if (r.stats.inside != 0) return 1;
  }
  return 0;
}
