// dngbake: bake meshes and scenes into a .dng distance/normal grid. Thin over the baker library: parse
// options, run bake(), report. Exit codes: exit_codes.h (docs/BAKING.md).
#include "dng/baker/bake.h"

#include "command_line.h"
#include "exit_codes.h"
#include "import_options.h"
#include "machine_memory.h"
#include "memory_cap.h"
#include "standard_output.h"
#include "terminal.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>

namespace {

using namespace dng::baker;
using namespace dng::tools;

std::atomic<bool> g_interrupted{false};

// The first signal asks the bake to stop at its next progress report. Once the writes have begun there
// are none: the bake then finishes and reports success, so what it says is always what happened (the
// exit code and the report follow bake()'s status, never this flag). Loading a mesh has no reports
// either, so a second signal ends the process the default way: a person pressing Ctrl-C twice must not
// be ignored. signal() and raise() are async-signal-safe.
extern "C" void onSignal(int sig) {
  if (g_interrupted.exchange(true)) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

struct CommandLine {
  BakeInputs inputs;
  std::string output;
  std::string export_vdb;
  BakeOptions bake;
  bool json = false;
  bool quiet = false;
  std::string memory_limit = "auto"; ///< "auto", "none" or a number of bytes (memoryLimitValue)
};

// The auto limit leaves a tenth of the free memory to what the cap does not see at once: allocations
// around operator new, the file's pages, the kernel's own.
constexpr int kAutoLimitPercent = 90;

// A size: decimal digits (never octal: CLI11 would read 010G as 8 GiB), then a unit CLI11 knows (k =
// 1024) or none for bytes. 0 when it is not one or is zero.
std::uint64_t sizeInBytes(const std::string& text) {
  std::size_t digits = 0;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits])))
    ++digits;
  if (digits == 0 || digits > 15) return 0;
  std::string unit = "1" + text.substr(digits); // one of the unit, whose bytes CLI11 knows
  try {
    if (!CLI::AsSizeValue(false)(unit).empty()) return 0;
  } catch (const CLI::ValidationError&) { // an unknown unit
    return 0;
  }
  const std::uint64_t number = std::strtoull(text.substr(0, digits).c_str(), nullptr, 10);
  const std::uint64_t factor = std::strtoull(unit.c_str(), nullptr, 10);
  return factor != 0 && number <= UINT64_MAX / factor ? number * factor : 0;
}

// --memory-limit's values: auto, none, or a size turned into bytes.
CLI::Validator memoryLimitValue() {
  return CLI::Validator(
      [](std::string& text) {
        if (text == "auto" || text == "none") return std::string();
        const std::uint64_t bytes = sizeInBytes(text);
        if (bytes == 0) return "must be auto, none or a size such as 6G or 800M, got '" + text + "'";
        text = std::to_string(bytes);
        return std::string();
      },
      "auto|none|SIZE");
}

// The cap --memory-limit asks for, in bytes of resident memory; 0: none. Auto: what this process holds
// now plus kAutoLimitPercent of what the machine and its cgroups leave free (no cap where that is unknown).
std::uint64_t memoryLimitBytes(const std::string& value) {
  if (value == "none") return 0;
  if (value != "auto") return std::strtoull(value.c_str(), nullptr, 10);
  const std::optional<std::uint64_t> headroom = memoryHeadroomBytes();
  if (!headroom) return 0;
  return residentBytes() + *headroom / 100 * kAutoLimitPercent;
}

// What the auto limit is, in words.
std::string autoLimitWords() {
  return ", what it held at the start and " + std::to_string(kAutoLimitPercent) + "% of the memory then free";
}

std::string megabytes(std::uint64_t bytes) {
  if (bytes < 1000000) return std::to_string(bytes) + " bytes";
  char text[32];
  std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / 1e6);
  return text;
}

// Progress: one redrawn line on stderr, only for a person watching a terminal.
struct Progress {
  bool draw = false;
  static bool update(void* self, const char* stage, double fraction) {
    auto* p = static_cast<Progress*>(self);
    if (p->draw) {
      std::fprintf(stderr, "\r\033[Kdngbake: %-9s %3d%%", stage, int(fraction * 100.0 + 0.5));
      std::fflush(stderr);
    }
    return !g_interrupted.load();
  }
  void finish() const {
    if (draw) std::fprintf(stderr, "\r\033[K");
  }
};

bool wantProgress(const CommandLine& cl) { return !cl.json && !cl.quiet && dng::tools::stderrIsTerminal(); }

void addOptions(CLI::App& app, CommandLine& cl) {
  dng::tools::addImportOptions(app, cl.inputs);
  app.add_option("-o,--output", cl.output, "the .dng file to write")->required();
  const std::map<std::string, NormalMode> modes{
      {"normal-blur", NormalMode::kNormalBlur}, {"potential", NormalMode::kPotential}, {"exact", NormalMode::kExact}};
  app.add_option("--mode", cl.bake.mode, "normals: normal-blur (paper method 1), potential (method 2), exact")
      ->transform(CLI::CheckedTransformer(modes, CLI::ignore_case));
  auto* resolution = app.add_option("--resolution", cl.bake.resolution, "voxels along the longest axis (default 128)");
  app.add_option("--voxel-size", cl.bake.voxel_size, "voxel edge in mesh units")
      ->check(dng::tools::finitePositive())
      ->excludes(resolution);
  auto* band = app.add_option("--band", cl.bake.band_voxels, "field thickness in voxels (default 4)");
  auto* speed =
      app.add_option("--max-speed", cl.bake.max_speed, "fastest particle, mesh units/s (with --dt)")->excludes(band);
  auto* dt = app.add_option("--dt", cl.bake.dt, "simulation step in seconds (with --max-speed)")->excludes(band);
  speed->needs(dt);
  dt->needs(speed);
  app.add_option("--blur-radius", cl.bake.blur_radius,
                 "blur kernel radius in voxels, 1-8; the paper uses 2-4 (default 3)");
  app.add_option("--blur-rounds", cl.bake.blur_rounds, "blur rounds (default 3)");
  const std::map<std::string, SignMode> signs{
      {"auto", SignMode::kAuto}, {"winding", SignMode::kWinding}, {"pseudonormal", SignMode::kPseudonormal}};
  app.add_option("--sign", cl.bake.sign, "inside test: auto, winding, pseudonormal")
      ->transform(CLI::CheckedTransformer(signs, CLI::ignore_case));
  const std::map<std::string, dng::format::Encoding> encodings{{"bricked", dng::format::Encoding::kBricked},
                                                               {"dense", dng::format::Encoding::kDense}};
  app.add_option("--encoding", cl.bake.encoding, "bricked (default) or dense")
      ->transform(CLI::CheckedTransformer(encodings, CLI::ignore_case));
  app.add_option("--brick-size", cl.bake.brick.brick_size, "4, 8 (default) or 16")->check(CLI::IsMember({4u, 8u, 16u}));
  app.add_option("--tolerance", cl.bake.brick.tolerance_distance, "plane/far tile tolerance in voxels (default 0.02)");
  app.add_flag("!--no-lift", cl.bake.lift,
               "leave out the LIFT section (a file about a quarter smaller, a third in exact mode); accurate "
               "queries then read the lowered values");
  app.add_flag("!--no-second-planes", cl.bake.second_planes,
               "leave out the PLN2 section (bricked): particles beside edges are then proven outside less often");
  app.add_option("--export-vdb", cl.export_vdb, "also write distance and normal grids as OpenVDB");
  app.add_option("--memory-limit", cl.memory_limit,
                 "stop with 'out of memory' (exit 4) rather than outgrow this: auto (default: what it holds at the "
                 "start and " +
                     std::to_string(kAutoLimitPercent) +
                     "% of the memory then free, the container's limit included), none, or a size such as 6G")
      ->transform(memoryLimitValue());
  app.add_option("--threads", cl.bake.threads, "worker threads (default: all); the output never depends on it");
  app.add_flag("--json", cl.json, "print a versioned JSON report on stdout");
  app.add_flag("-q,--quiet", cl.quiet, "no progress, no summary");
  app.set_version_flag("--version", DNG_TOOL_VERSION);
}

nlohmann::ordered_json vec3(dng::Vec3f v) { return {v.x, v.y, v.z}; }

int exitCodeFor(BakeError error) {
  switch (error) {
  case BakeError::kOk: return kExitOk;
  case BakeError::kBadOption: return kExitUsage;
  case BakeError::kIo: return kExitIo;
  case BakeError::kInvalidInput: return kExitInvalid;
  case BakeError::kInternal: return kExitInternal;
  case BakeError::kUnsupported: return kExitUnsupported;
  case BakeError::kCancelled: return kExitInterrupted;
  }
  return kExitInternal;
}

// Whether a failure is the memory limit's, whatever a library made of the std::bad_alloc it caused
// (tinygltf's parser catches it and reports a broken file).
bool stoppedByMemoryLimit(const BakeStatus& status) {
  return !status.ok() && status.code != BakeError::kCancelled && memoryCapReached();
}

int exitCodeFor(const BakeStatus& status) {
  return stoppedByMemoryLimit(status) ? kExitInternal : exitCodeFor(status.code);
}

// What the user reads on failure: the status's sentence, or for a cancel what it means for the output;
// after the memory limit stopped the bake, that it did and which limit it was.
std::string failureMessage(const CommandLine& cl, const BakeStatus& status) {
  if (status.code == BakeError::kCancelled) return "interrupted; " + cl.output + " was not written";
  if (!stoppedByMemoryLimit(status)) return status.message;
  const std::string limit = " (the bake reached its memory limit, " + megabytes(memoryCap()) +
                            (cl.memory_limit == "auto" ? autoLimitWords() : "") + ": --memory-limit)";
  if (status.code == BakeError::kInternal) return status.message + limit;
  return "out of memory while baking" + limit + "; " + status.message;
}

nlohmann::ordered_json reportJson(const CommandLine& cl, const BakeReport& r, const BakeStatus& status) {
  nlohmann::ordered_json j;
  j["format"] = "dngbake-report";
  j["version"] = 1;
  j["input"] = cl.inputs.paths.empty() ? "" : cl.inputs.paths.front();
  j["inputs"] = dng::tools::importReportJson(r.inputs);
  j["units"] = lengthUnitName(r.units);
  j["output"] = cl.output;
  j["ok"] = status.ok();
  if (!status.ok()) j["error"] = {{"exit_code", exitCodeFor(status)}, {"message", failureMessage(cl, status)}};
  const MeshReport& m = r.mesh;
  j["mesh"] = {{"vertices", m.vertices},
               {"triangles", m.triangles},
               {"components", m.components},
               {"boundary_edges", m.boundary_edges},
               {"hole_edges", m.hole_edges},
               {"non_manifold_edges", m.non_manifold_edges},
               {"degenerate_triangles", m.degenerate_triangles},
               {"non_finite_vertices", m.non_finite_vertices},
               {"misoriented_edges", m.misoriented_edges},
               {"closed", m.closed()},
               {"signed_volume", m.signed_volume},
               {"sign_method", r.sign},
               {"bounds_min", vec3(m.bounds_min)},
               {"bounds_max", vec3(m.bounds_max)},
               {"source_xxh64", r.source_hash}};
  const dng::format::GridGeometry& g = r.grid;
  j["grid"] = {{"origin", vec3(g.origin)},
               {"voxel_size", g.voxel_size},
               {"dims", {g.dims[0], g.dims[1], g.dims[2]}},
               {"band", g.band},
               {"band_voxels", g.voxel_size > 0 ? g.band / g.voxel_size : 0.0f}};
  const dng::format::EncodeStats& e = r.encode;
  j["encoder"] = {{"far_outside_tiles", e.tiles.far_outside},
                  {"far_inside_tiles", e.tiles.far_inside},
                  {"plane_tiles", e.tiles.plane},
                  {"brick_tiles", e.tiles.brick},
                  {"band_voxels", e.band_voxels},
                  {"max_distance_error_voxels", e.max_distance_error_voxels},
                  {"max_normal_error_degrees", e.max_normal_error_deg},
                  {"max_lifted_error_voxels", e.max_lifted_error_voxels},
                  {"second_plane_blocks", e.second_plane_blocks},
                  {"second_planes", e.second_planes},
                  {"payload_bytes", e.payload_bytes}};
  j["working_store"] = {{"blocks", r.band_blocks}, {"peak_memory_bytes", r.peak_memory_bytes}};
  j["working_store"]["memory_limit_bytes"] = memoryCap() > 0 ? nlohmann::ordered_json(memoryCap()) : nullptr;
  j["output_bytes"] = r.output_bytes;
  nlohmann::ordered_json timings = nlohmann::ordered_json::object();
  for (const auto& [stage, seconds] : r.stage_seconds)
    timings[stage] = seconds;
  j["seconds"] = timings;
  j["warnings"] = r.warnings;
  return j;
}

void printSummary(const CommandLine& cl, const BakeReport& r) {
  double total = 0.0;
  for (const auto& stage : r.stage_seconds)
    total += stage.second;
  const std::string input =
      cl.inputs.paths.front() +
      (cl.inputs.paths.size() > 1 ? " (+" + std::to_string(cl.inputs.paths.size() - 1) + ")" : "");
  std::fprintf(stderr, "dngbake: %s -> %s: %llu triangles, %u x %u x %u voxels of %g, %llu bytes, %.2f s\n",
               input.c_str(), cl.output.c_str(), (unsigned long long)r.mesh.triangles, r.grid.dims[0], r.grid.dims[1],
               r.grid.dims[2], double(r.grid.voxel_size), (unsigned long long)r.output_bytes, total);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"dngbake: bake a mesh into a distance/normal grid (.dng)", "dngbake"};
  CommandLine cl;
  addOptions(app, cl);
  if (const int code = dng::tools::parseOrExitCode(app, argc, argv); code >= 0)
    return finishStandardOutput("dngbake", code); // --help and --version print there
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  setMemoryCap(memoryLimitBytes(cl.memory_limit));
  Progress progress{wantProgress(cl)};
  BakeReport report;
  const BakeStatus status = bake(cl.inputs, {cl.output, cl.export_vdb}, cl.bake, &Progress::update, &progress, &report);
  progress.finish();
  if (cl.json) {
    const auto json = reportJson(cl, report, status); // paths are bytes, not always UTF-8: never throw
    std::printf("%s\n", json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace).c_str());
  }
  if (!cl.quiet && !cl.json) {
    for (const std::string& w : report.warnings)
      std::fprintf(stderr, "dngbake: warning: %s\n", w.c_str());
  }
  if (!status.ok()) {
    std::fprintf(stderr, "dngbake: %s%s\n",
                 status.code == BakeError::kCancelled ? "" : "error: ", failureMessage(cl, status).c_str());
    return finishStandardOutput("dngbake", exitCodeFor(status));
  }
  if (!cl.quiet && !cl.json) printSummary(cl, report);
  return finishStandardOutput("dngbake", kExitOk); // the .dng is whole either way: only the report was lost
}
