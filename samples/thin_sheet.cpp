// A thin open sheet (Debian's blade.off, or any sheet) baked in potential mode repels particles from
// both sides (paper §3.1, method 2).
//   dngbake blade.off -o blade.dng --mode potential
//   dng_thin_sheet blade.dng [OUTPUT_FOLDER]
#include "dng/file.h"
#include "figures.h"
#include "sample_main.h"

#include <cstdio>

int main(int argc, char** argv) {
  using namespace dng::samples;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SHEET.dng [OUTPUT_FOLDER]\n", argv[0]);
    return 1;
  }
  dng::File file;
  dng::Diagnostic diag;
  if (dng::File::open(argv[1], &file, &diag) != dng::Status::kOk) {
    std::fprintf(stderr, "dng_thin_sheet: %s: %s\n", argv[1], diag.message);
    return 2;
  }
  RunOptions options;
  options.picture_prefix = outputFolder(argc, argv, 2) + "/thin_sheet";
  const SheetResult r = runSheet(file.view(), options);
  std::printf("%s\n", r.stats.json("thin_sheet").c_str());
  std::printf("{\"sample\":\"thin_sheet\",\"crossed\":%zu}\n", r.crossed);
  return r.crossed == 0 && r.stats.inside == 0 ? 0 : 1;
}
