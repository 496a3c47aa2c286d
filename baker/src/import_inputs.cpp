// Several input files into one triangle soup: the importer for each, units, the --node check.
#include "dng/baker/import.h"

#include "stages.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <unistd.h>

namespace dng {
namespace baker {

namespace {

struct UnitEntry {
  LengthUnit unit;
  const char* name;
  double metres;
};
constexpr UnitEntry kUnits[] = {{LengthUnit::kMetre, "m", 1.0},         {LengthUnit::kCentimetre, "cm", 0.01},
                                {LengthUnit::kMillimetre, "mm", 0.001}, {LengthUnit::kKilometre, "km", 1000.0},
                                {LengthUnit::kInch, "in", 0.0254},      {LengthUnit::kFoot, "ft", 0.3048}};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// File coordinates -> field coordinates for one input. Also records the factor in the report.
double inputScale(const UnitOptions& units, ImportReport* report, std::vector<std::string>* warnings) {
  const LengthUnit source = report->units != LengthUnit::kUnknown ? report->units : units.assumed;
  double factor = 1.0;
  if (units.field != LengthUnit::kUnknown) {
    if (source == LengthUnit::kUnknown)
      warnings->push_back("'" + report->path + "' does not say its units: taken as " + lengthUnitName(units.field) +
                          " (--source-units sets them)");
    else
      factor = metresPerUnit(source) / metresPerUnit(units.field);
  }
  report->scale = factor * units.scale;
  return report->scale;
}

// An input path must name a regular file this process can read: said here, with the system's reason,
// before any reader guesses (a folder named by its extension, a file without read permission, a FIFO
// a reader would wait on).
BakeStatus checkReadable(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) return BakeStatus::failure(BakeError::kIo, "'" + path + "': no such file");
  if (std::filesystem::is_directory(status))
    return BakeStatus::failure(BakeError::kIo, "'" + path + "' is a directory, not a mesh file");
  if (!std::filesystem::is_regular_file(status))
    return BakeStatus::failure(BakeError::kIo, "'" + path + "' is not a regular file (a device, pipe or socket)");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return BakeStatus::failure(BakeError::kIo, "'" + path + "': cannot open: " + std::strerror(errno));
  ::close(fd);
  return BakeStatus::success();
}

BakeStatus importOne(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                     ImportReport* out_report) {
  out_report->path = path;
  out_report->format = lowerExtension(path);
  if (BakeStatus readable = checkReadable(path); !readable.ok()) return readable;
  const ImportFn importer = importerFor(path);
  if (importer == nullptr)
    return BakeStatus::failure(BakeError::kUnsupported, "'" + path + "': unknown mesh format '." + out_report->format +
                                                            "' (use .gltf, .glb, .obj, .off, .ply, .stl or "
                                                            "a format assimp reads: .fbx, .dae, .3ds, .blend, ...)");
  const std::size_t first_vertex = io_soup->vertices.size();
  const BakeStatus status = importer(path, options, io_soup, out_report);
  out_report->vertices = io_soup->vertices.size() - first_vertex;
  if (status.ok() || status.message.compare(0, path.size() + 2, "'" + path + "'") == 0) return status;
  return BakeStatus::failure(status.code, "'" + path + "': " + status.message);
}

} // namespace

const char* lengthUnitName(LengthUnit unit) {
  for (const UnitEntry& e : kUnits)
    if (e.unit == unit) return e.name;
  return "unknown";
}

bool parseLengthUnit(const std::string& name, LengthUnit* out_unit) {
  for (const UnitEntry& e : kUnits) {
    if (name == e.name) {
      *out_unit = e.unit;
      return true;
    }
  }
  return false;
}

double metresPerUnit(LengthUnit unit) {
  for (const UnitEntry& e : kUnits)
    if (e.unit == unit) return e.metres;
  return 0.0;
}

LengthUnit fieldUnit(const UnitOptions& units, const std::vector<ImportReport>& reports) {
  if (units.field != LengthUnit::kUnknown) return units.field;
  LengthUnit common = LengthUnit::kUnknown;
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const LengthUnit u = reports[i].units != LengthUnit::kUnknown ? reports[i].units : units.assumed;
    if (i > 0 && u != common) return LengthUnit::kUnknown;
    common = u;
  }
  return common;
}

ImportFn importerFor(const std::string& path) {
  const std::string ext = lowerExtension(path);
  static const char* const kOpenMesh[] = {"obj", "off", "ply", "stl", "om"}; // loadMesh refuses .om, saying why
  if (std::find(std::begin(kOpenMesh), std::end(kOpenMesh), ext) != std::end(kOpenMesh)) return &importOpenMesh;
  if (ext == "gltf" || ext == "glb") return &importGltf;
  return assimpReads(ext) ? &importAssimp : nullptr;
}

BakeStatus importInputs(const std::vector<std::string>& paths, const ImportOptions& options, const UnitOptions& units,
                        TriangleSoup* out_soup, std::vector<ImportReport>* out_reports,
                        std::vector<std::string>* io_warnings) {
  *out_soup = TriangleSoup();
  out_reports->assign(paths.size(), ImportReport());
  if (!(units.scale > 0.0) || !std::isfinite(float(units.scale)))
    return BakeStatus::failure(BakeError::kBadOption, "--scale must be a finite number > 0");
  // A scene index means nothing to mesh files, which hold one mesh: asked of them alone it is a mistake
  // (as a --node no input has), not something to ignore.
  const auto is_mesh_file = [](const std::string& path) { return importerFor(path) == &importOpenMesh; };
  if (options.scene >= 0 && !paths.empty() && std::all_of(paths.begin(), paths.end(), is_mesh_file))
    return BakeStatus::failure(BakeError::kBadOption, "--scene " + std::to_string(options.scene) +
                                                          ": no input is a scene file (glTF or a format assimp "
                                                          "reads); mesh files hold one mesh");
  for (std::size_t i = 0; i < paths.size(); ++i) {
    ImportReport& report = (*out_reports)[i];
    const std::size_t first_vertex = out_soup->vertices.size();
    const BakeStatus status = importOne(paths[i], options, out_soup, &report);
    if (!status.ok()) return status;
    // A lone empty mesh file is left to requireBakeable ("no faces", with the reader's messages); an
    // empty scene, or one empty input among several (the union would hide it), is said here.
    // Mesh files are taken whole, --node or not; scenes may hold none of the nodes asked for.
    const bool mesh_file = report.importer == "openmesh";
    if (report.triangles == 0 && (mesh_file ? paths.size() > 1 : options.nodes.empty())) {
      const std::string why = report.messages.empty() ? "" : " (" + report.messages.front() + ")";
      return BakeStatus::failure(
          BakeError::kInvalidInput,
          "'" + paths[i] + "': " + (mesh_file ? "the mesh has no faces" : "the scene holds no triangles") + why);
    }
    const auto factor = float(inputScale(units, &report, io_warnings));
    if (factor != 1.0f) {
      for (std::size_t v = first_vertex; v < out_soup->vertices.size(); ++v)
        out_soup->vertices[v] = out_soup->vertices[v] * factor;
    }
  }
  for (const std::string& name : options.nodes) {
    const bool found = std::any_of(out_reports->begin(), out_reports->end(), [&](const ImportReport& r) {
      return std::find(r.matched_nodes.begin(), r.matched_nodes.end(), name) != r.matched_nodes.end();
    });
    if (!found)
      return BakeStatus::failure(BakeError::kBadOption, "--node '" + name + "': no input has a node of that name");
  }
  if (!options.nodes.empty() && out_soup->triangles.empty())
    return BakeStatus::failure(BakeError::kInvalidInput, "the selected nodes hold no triangles");
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
