// libFuzzer target for the assimp importer (import_assimp.cpp), in process, so that assimp's crashes
// show (dngbake runs it in a child process, where a crash becomes exit code 3). The first byte picks the
// extension (so the reader), the rest is the file. assimp is a shared library and not instrumented:
// coverage guides only through our code. Findings: assimp_regressions/, which import_test bakes
// through dngbake. Run with `bash setup.sh fuzz-assimp [SECONDS]`.
#include "stages.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {"fbx", "dae", "3ds", "ac", "x", "lwo", "ase", "ms3d", "off", "nff"};
  const char* extension = kExtensions[data[0] % 10];
  const char* tmp = std::getenv("TMPDIR");
  const std::string path =
      std::string(tmp != nullptr ? tmp : "/tmp") + "/dng_fuzz_assimp_" + std::to_string(::getpid()) + "." + extension;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data + 1, 1, size - 1, file);
  std::fclose(file);
  dng::baker::TriangleSoup soup;
  dng::baker::ImportReport report;
  report.format = extension;
  (void)dng::baker::importAssimpInProcess(path, {}, &soup, &report);
  std::remove(path.c_str());
  return 0;
}
