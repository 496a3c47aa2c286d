// What every sample program does with its command line: an output folder for pictures.
#pragma once

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

} // namespace samples
} // namespace dng
