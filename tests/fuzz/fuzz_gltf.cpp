// libFuzzer target for the glTF importer: tinygltf's parser, then our accessor checks and scene walk
// (import_gltf.cpp, gltf_accessor.cpp). The first byte picks .gltf or .glb, the rest is the file. Any
// crash, hang or sanitizer report is a bug: every malformed file must come back as a status. tinygltf
// (Debian's shared library) is not instrumented; its crashes still show.
// Findings live in gltf_regressions/, replayed by `bash setup.sh fuzz`; open-ended runs are
// `bash setup.sh fuzz-scenes [SECONDS]`.
#include "stages.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") + "/dng_fuzz_gltf_" + std::to_string(::getpid()) +
                           (data[0] % 2 == 0 ? ".gltf" : ".glb");
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data + 1, 1, size - 1, file);
  std::fclose(file);
  dng::baker::TriangleSoup soup;
  dng::baker::ImportReport report;
  report.format = data[0] % 2 == 0 ? "gltf" : "glb";
  (void)dng::baker::importGltf(path, {}, &soup, &report);
  std::remove(path.c_str());
  return 0;
}
