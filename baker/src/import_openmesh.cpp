// OBJ, OFF, PLY, STL and OM through OpenMesh's readers (load_mesh.cpp, behind reader_guards.cpp),
// appended to the soup. These formats have no nodes and do not say their units.
#include "dng/baker/import.h"

#include "stages.h"

namespace dng {
namespace baker {

BakeStatus importOpenMesh(const std::string& path, const ImportOptions&, TriangleSoup* io_soup,
                          ImportReport* out_report) {
  out_report->importer = "openmesh";
  out_report->units = LengthUnit::kUnknown;
  TriangleSoup mesh;
  const BakeStatus status = loadMesh(path, &mesh);
  if (!status.ok()) return status;
  const auto base = std::uint32_t(io_soup->vertices.size());
  io_soup->vertices.insert(io_soup->vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  for (const auto& t : mesh.triangles)
    io_soup->triangles.push_back({base + t[0], base + t[1], base + t[2]});
  io_soup->polygons += mesh.polygons;
  io_soup->faces_with_bad_index += mesh.faces_with_bad_index;
  out_report->triangles = mesh.triangles.size();
  for (const std::string& m : mesh.reader_messages)
    out_report->messages.push_back("reader: " + m);
  if (mesh.faces_with_bad_index > 0)
    out_report->messages.push_back(std::to_string(mesh.faces_with_bad_index) +
                                   " faces referred to missing vertices and were skipped");
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
