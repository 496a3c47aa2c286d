// Fig. 7 of the paper: a stream coming from the right flows around a shaft, with
// rho_in / rho_out = 12 / 3, 3 / 6 (and a reduced flow distance), and 3 / -3.
//   dng_fig7_shaft_flow [OUTPUT_FOLDER]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  const std::string out = outputFolder(argc, argv);
  const struct {
    const char* name;
    float rho_in, rho_out, distance;
  } variants[] = {{"fig7a_12_3", 12, 3, 0.2f}, {"fig7b_3_6", 3, 6, 0.1f}, {"fig7c_3_minus3", 3, -3, 0.2f}};
  for (const auto& v : variants) {
    RunOptions options;
    options.picture_prefix = out + "/" + v.name;
    const StreamResult r = runShaftStream(v.rho_in, v.rho_out, v.distance, options);
    std::printf("%s\n", r.stats.json(v.name).c_str());
    std::printf("{\"sample\":\"%s\",\"fraction_downstream\":%.3f,\"mean_downstream_offset\":%.3f}\n", v.name,
                double(r.fraction_downstream), double(r.mean_downstream_offset));
    if (r.stats.inside != 0) return 1;
  }
  return 0;
}
