// Fig. 6 of the paper: a particle stream flowing around a sphere, from the side and from above
// (surface flow with rho_in = 12, rho_out = 3).
//   dng_fig6_sphere_flow [OUTPUT_FOLDER]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  const std::string out = outputFolder(argc, argv);
  for (bool above : {false, true}) {
    const char* name = above ? "fig6b_from_above" : "fig6a_from_side";
    RunOptions options;
    options.picture_prefix = out + "/" + name;
    const StreamResult r = runSphereStream(above, options);
    std::printf("%s\n", r.stats.json(name).c_str());
    std::printf("{\"sample\":\"%s\",\"fraction_downstream\":%.3f,\"mean_downstream_offset\":%.3f}\n", name,
                double(r.fraction_downstream), double(r.mean_downstream_offset));
    if (r.stats.inside != 0) return 1;
  }
  return 0;
}
