// Fig. 8 of the paper: an explosion among buildings: a radial blast, gravity, air drag, collision
// avoidance and surface flow together, the gas flowing around the corners. Six buildings share one
// field; the ground is another.
//   dng_fig8_explosion [OUTPUT_FOLDER]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  RunOptions options;
  options.picture_prefix = outputFolder(argc, argv) + "/fig8_explosion";
  const ExplosionResult r = runExplosion(options);
  std::printf("%s\n", r.stats.json("fig8_explosion").c_str());
  std::printf("{\"sample\":\"fig8_explosion\",\"fraction_beyond_buildings\":%.3f}\n",
              double(r.fraction_beyond_buildings));
  return r.stats.inside == 0 ? 0 : 1;
}
