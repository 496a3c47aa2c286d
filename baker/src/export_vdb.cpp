// --export-vdb: the baked band as OpenVDB grids, for a look in Houdini or Blender. The working store
// already is a level set (background = band) and a normal grid in the right placement, so exporting is
// writing them. "distance" is the distance itself: the copy kept from before the conservative lowering
// when there is one (the LIFT section's source), and then the lowered values go beside it as
// "conservative_distance", what the runtime's nearest query reads. "normal" is the distance's own
// (the planes'); the blurred modes add "shading", their normals (the SHAD section's source).
#include "band_grid_vdb.h"
#include "stages.h"

#include <new>

namespace dng {
namespace baker {

BakeStatus exportVdb(const BandGrid& band, const std::string& temp, const std::string& path) {
  try {
    openvdb::io::File file(temp);
    const BandGrid::Impl& grids = band.impl();
    openvdb::GridPtrVec written;
    if (grids.accurate == nullptr) {
      written = {grids.distance, grids.normal};
    } else {
      openvdb::FloatGrid::Ptr lowered = grids.distance->copy(); // shares the tree, own name
      lowered->setName("conservative_distance");
      written = {grids.accurate, lowered, grids.normal};
    }
    if (grids.shading != nullptr) written.push_back(grids.shading);
    file.write(written);
    file.close();
  } catch (const std::bad_alloc&) {
    throw; // out of memory, not an I/O error; the staged outputs remove the temporary file
  } catch (const std::exception& e) {
    return BakeStatus::failure(BakeError::kIo, "cannot write '" + path + "': " + e.what());
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
