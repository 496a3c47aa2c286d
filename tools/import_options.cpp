// dngbake's input options and the per-file, per-node part of its JSON report.
#include "import_options.h"

#include "command_line.h"

#include <cmath>

namespace dng {
namespace tools {

namespace {

CLI::Validator lengthUnit() {
  return CLI::Validator(
      [](std::string& name) {
        baker::LengthUnit unit;
        return baker::parseLengthUnit(name, &unit) ? std::string() : "unknown unit '" + name + "'";
      },
      "m|cm|mm|km|in|ft");
}

} // namespace

void addImportOptions(CLI::App& app, baker::BakeInputs& inputs) {
  app.add_option("inputs", inputs.paths,
                 "mesh or scene files, baked into one field (.gltf .glb .obj .off .ply .stl, or any "
                 "format assimp reads: .fbx .dae .3ds .blend ...)")
      ->required();
  app.add_option("--scene", inputs.import.scene, "scene files: the scene to bake (default: the file's default)")
      ->check(wholeAtLeastZero());
  app.add_option("--node", inputs.import.nodes, "scene files: bake only this node's subtree (repeatable)")
      ->allow_extra_args(false); // one name per --node: the next word is an input again
  app.add_option_function<std::string>(
         "--units", [&inputs](const std::string& name) { baker::parseLengthUnit(name, &inputs.units.field); },
         "the field's unit; inputs in other known units are converted")
      ->check(lengthUnit());
  app.add_option_function<std::string>(
         "--source-units", [&inputs](const std::string& name) { baker::parseLengthUnit(name, &inputs.units.assumed); },
         "the unit of inputs that do not say theirs (OBJ, OFF, PLY, STL, ...)")
      ->check(lengthUnit());
  app.add_option("--scale", inputs.units.scale, "multiply every coordinate by this, after unit conversion (> 0)")
      ->check(finitePositive());
}

nlohmann::ordered_json importReportJson(const std::vector<baker::ImportReport>& inputs) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const baker::ImportReport& in : inputs) {
    nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
    for (const baker::NodeImport& node : in.nodes)
      nodes.push_back({{"name", node.name},
                       {"mesh", node.mesh},
                       {"triangles", node.triangles},
                       {"skipped_primitives", node.skipped_primitives},
                       {"transform", node.transform}});
    files.push_back({{"path", in.path},
                     {"format", in.format},
                     {"importer", in.importer},
                     {"units", baker::lengthUnitName(in.units)},
                     {"scale", in.scale},
                     {"vertices", in.vertices},
                     {"triangles", in.triangles},
                     {"skipped_primitives", in.skipped_primitives},
                     {"nodes", nodes},
                     {"messages", in.messages},
                     {"xxh64", in.source_hash}});
  }
  return files;
}

} // namespace tools
} // namespace dng
