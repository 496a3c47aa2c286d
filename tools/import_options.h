// dngbake's input options (several files, --scene, --node, units) and their part of the --json report.
#pragma once

#include "dng/baker/bake.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace dng {
namespace tools {

/// Adds the positional inputs and --scene, --node, --units, --source-units, --scale, filling `inputs`.
void addImportOptions(CLI::App& app, baker::BakeInputs& inputs);

/// The report's "inputs" array: per file its importer, units, scale, triangles, skipped primitives
/// and, for scene files, per node its mesh, triangles, skipped primitives and transform.
nlohmann::ordered_json importReportJson(const std::vector<baker::ImportReport>& inputs);

} // namespace tools
} // namespace dng
