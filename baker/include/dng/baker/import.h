// The importer interface: every input format becomes triangles appended to one TriangleSoup, in the
// file's own units with its node transforms applied, plus an ImportReport. The rest of the baker
// sees only the soup. One importer per file:
//   import_openmesh.cpp  OBJ, OFF, PLY, STL, OM through OpenMesh (load_mesh.cpp)
//   import_gltf.cpp      glTF 2.0 (.gltf, .glb) through tinygltf
//   import_assimp.cpp    FBX, COLLADA, 3DS, Blender and assimp's other formats
//   import_isolated.cpp  an importer in a child process, for readers that crash on bad files
//   import_inputs.cpp    the choice of importer, several inputs into one soup, units
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dng {
namespace baker {

struct BakeStatus;
struct TriangleSoup;

/// What to take from scene files (glTF, assimp formats). Mesh files (OBJ, OFF, ...) are taken whole.
struct ImportOptions {
  int scene = -1;                 ///< scene index; -1 = the file's default scene (else the first)
  std::vector<std::string> nodes; ///< bake only the subtrees of nodes with these names; empty = all
};

/// Length units the baker can convert between; kUnknown when a format does not say.
enum class LengthUnit { kUnknown, kMetre, kCentimetre, kMillimetre, kKilometre, kInch, kFoot };

/// "m", "cm", "mm", "km", "in", "ft" or "unknown".
const char* lengthUnitName(LengthUnit unit);
/// Parses a name lengthUnitName gives (not "unknown"); false for anything else.
bool parseLengthUnit(const std::string& name, LengthUnit* out_unit);
/// Metres per unit; 0 for kUnknown.
double metresPerUnit(LengthUnit unit);

/// How the inputs' coordinates become the field's: converted from each file's units into `field`
/// (when both are known), then multiplied by `scale`.
struct UnitOptions {
  LengthUnit field = LengthUnit::kUnknown;   ///< --units; kUnknown = keep the files' numbers
  LengthUnit assumed = LengthUnit::kUnknown; ///< --source-units: the units of files that do not say
  double scale = 1.0;                        ///< --scale, after the conversion
};

/// One node whose mesh was taken.
struct NodeImport {
  std::string name;            ///< the node's name, or "#<index>" when it has none
  std::string mesh;            ///< the mesh's name, or "#<index>"
  std::uint64_t triangles = 0; ///< triangles this node added
  std::uint64_t skipped_primitives = 0;
  std::array<double, 16> transform; ///< node to file, column-major (as glTF writes matrices)
};

/// What one input file contributed.
struct ImportReport {
  std::string path;
  std::string format;                      ///< "gltf", "glb", "obj", "off", ... (lower-case extension)
  std::string importer;                    ///< "openmesh", "tinygltf" or "assimp"
  LengthUnit units = LengthUnit::kUnknown; ///< what the file says its units are
  double scale = 1.0;                      ///< file coordinates -> field coordinates (units conversion times --scale)
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t skipped_primitives = 0;   ///< points, lines: reported, not baked
  std::vector<NodeImport> nodes;          ///< scene files: every node that added or skipped geometry
  std::vector<std::string> matched_nodes; ///< the ImportOptions::nodes names this file has
  std::vector<std::string> messages;      ///< what the reader reported and what was skipped, one line each
  std::string source_hash;                ///< XXH64 of the file, hex
};

/// An importer: reads `path`, appends its triangles (file units, node transforms applied) to
/// *io_soup and fills *out_report (units, triangles, nodes, messages). Errors carry the exit codes of
/// docs/BAKING.md: kIo (missing or unreadable file or buffer), kInvalidInput (malformed or
/// out-of-range data), kUnsupported (a required extension or feature it does not handle). On error
/// *io_soup may hold part of the file: the caller drops it. Not thread-safe.
using ImportFn = BakeStatus (*)(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                                ImportReport* out_report);

BakeStatus importOpenMesh(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                          ImportReport* out_report);
BakeStatus importGltf(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                      ImportReport* out_report);
/// assimp in a child process (importIsolated): a reader that crashes is invalid input, not a crash.
BakeStatus importAssimp(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                        ImportReport* out_report);
/// assimp in this process: for the fuzzer, which must see the crashes importAssimp contains.
BakeStatus importAssimpInProcess(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                                 ImportReport* out_report);

/// Runs `importer` in a forked child and appends what it read to *io_soup. A child killed by a signal
/// (a reader crashing on a malformed file) gives kInvalidInput naming the signal; *io_report keeps the
/// fields set before the call (importer, format) and takes the child's report. The child runs one
/// importer and exits; a reader that hangs hangs the caller (Ctrl-C ends both). POSIX only.
BakeStatus importIsolated(ImportFn importer, const std::string& path, const ImportOptions& options,
                          TriangleSoup* io_soup, ImportReport* io_report);

/// Whether assimp reads files with this lower-case extension (no dot). OpenMesh's and glTF's are
/// taken by their own importers first.
bool assimpReads(const std::string& extension);

/// The importer for a path's extension (case-insensitive), or nullptr when none handles it.
ImportFn importerFor(const std::string& path);

/// Every input into one soup (their union), each scaled per `units`; out_reports gets one report per
/// input in order; warnings (an input whose units are unknown) are appended to *io_warnings. kUsage
/// when a --node name matches no node of any input or --scene is out of range, kInvalidInput when the
/// selection holds no triangles or an input (without --node) holds none, kUnsupported for an unknown
/// extension, and the importers' errors; every message names the file.
BakeStatus importInputs(const std::vector<std::string>& paths, const ImportOptions& options, const UnitOptions& units,
                        TriangleSoup* out_soup, std::vector<ImportReport>* out_reports,
                        std::vector<std::string>* io_warnings);

/// The field's length unit: units.field when given, else the one unit every input is in (each file's
/// own, or units.assumed), else kUnknown.
LengthUnit fieldUnit(const UnitOptions& units, const std::vector<ImportReport>& reports);

} // namespace baker
} // namespace dng
