// libFuzzer target for mesh loading: OpenMesh's readers behind our guards (reader_guards.h), then
// the mesh checks. The first byte picks the format, the rest is the file. Any crash or abort is a bug:
// every malformed mesh must come back as a status with a message. OpenMesh itself is not
// instrumented, so coverage guides only through our code; its asserts and crashes still show.
// Every input it found that crashed, hung or exhausted memory is in mesh_regressions/ (CI replays them
// through `bash setup.sh fuzz`); open-ended runs are `bash setup.sh fuzz-meshes [SECONDS]`.
#include "stages.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {"obj", "off", "ply", "stl", "om"};
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/dng_fuzz_mesh_" + std::to_string(::getpid()) +
                           "." + kExtensions[data[0] % 5];
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data + 1, 1, size - 1, file);
  std::fclose(file);
  dng::baker::TriangleSoup soup;
  if (dng::baker::loadMesh(path, &soup).ok()) (void)dng::baker::requireBakeable(dng::baker::checkMesh(soup));
  std::remove(path.c_str());
  return 0;
}
