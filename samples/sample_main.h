// What every sample program does with its command line: an output folder for pictures.
#pragma once

#include "dng/file.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dng {
namespace samples {

/// argv[1] if given, else "out"; created if missing.
inline std::string outputFolder(int argc, char** argv, int index = 1) {
  const std::string folder = argc > index ? argv[index] : "out";
  std::filesystem::create_directories(folder);
  return folder;
}

/// Maps argv[1] as a .dng file, or prints the usage or the reason and exits (1 usage, 2 unreadable).
inline File openFieldArgument(int argc, char** argv, const char* usage_tail) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FIELD.dng %s\n", argv[0], usage_tail);
    std::exit(1);
  }
  File file;
  Diagnostic diag;
  if (File::open(argv[1], &file, &diag) != Status::kOk) {
    std::fprintf(stderr, "%s: %s: %s\n", argv[0], argv[1], diag.message);
    std::exit(2);
  }
  return file;
}

} // namespace samples
} // namespace dng
