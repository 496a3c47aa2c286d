// --export-vdb: the baked band as OpenVDB grids, for a look in Houdini or Blender. The working store
// already is a level set ("distance", background = band) and a normal grid in the right placement,
// so exporting is writing them.
#include "band_grid_vdb.h"
#include "stages.h"

#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace dng {
namespace baker {

BakeStatus exportVdb(const BandGrid& band, const std::string& path) {
  // Same promise as the .dng: the old file or the new one, never half of one.
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  try {
    openvdb::io::File file(temp);
    file.write({band.impl().distance, band.impl().normal});
    file.close();
  } catch (const std::exception& e) {
    std::remove(temp.c_str());
    return BakeStatus::failure(BakeError::kIo, "cannot write '" + path + "': " + e.what());
  }
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::remove(temp.c_str());
    return BakeStatus::failure(BakeError::kIo, "cannot replace '" + path + "': " + error.message());
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
