// A thin open sheet (Debian's blade.off, or any sheet) baked in potential mode repels particles from
// both sides (paper §3.1, method 2).
//   dngbake blade.off -o blade.dng --mode potential
//   dng_thin_sheet blade.dng [OUTPUT_FOLDER]
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  const dng::File file = openFieldArgument(argc, argv, "[OUTPUT_FOLDER]");
  RunOptions options;
  options.picture_prefix = outputFolder(argc, argv, 2) + "/thin_sheet";
  const SheetResult r = runSheet(file.view(), options);
  std::printf("%s\n", r.stats.json("thin_sheet").c_str());
  std::printf("{\"sample\":\"thin_sheet\",\"crossed\":%zu}\n", r.crossed);
  return r.crossed == 0 && r.stats.inside == 0 ? 0 : 1;
}
