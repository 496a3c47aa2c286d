// The whole bake (docs/DESIGN.md §5): options, load, check, place, distance and sign, normals,
// encode, write.
#include "stages.h"

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <xxhash.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <new>
#include <sys/resource.h>

namespace dng {
namespace baker {

namespace {

using Clock = std::chrono::steady_clock;

const char* encodingName(format::Encoding e) { return e == format::Encoding::kDense ? "dense" : "bricked"; }

// XXH64 of the input file, hex: recorded so a pipeline can tell which source a .dng came from. Read
// in chunks through libxxhash's streaming API, so a large mesh is not held in memory a second time.
// The digest equals format::xxhash64 of the whole file (tests/hash_test.cpp compares the two).
BakeStatus hashFile(const std::string& path, std::string* out_hex) {
  std::ifstream in(path, std::ios::binary);
  std::unique_ptr<XXH64_state_t, decltype(&XXH64_freeState)> state(XXH64_createState(), &XXH64_freeState);
  if (!in || state == nullptr || XXH64_reset(state.get(), 0) != XXH_OK)
    return BakeStatus::failure(BakeError::kIo, "cannot read '" + path + "' to hash it");
  std::vector<char> chunk(1 << 20);
  while (in) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    if (XXH64_update(state.get(), chunk.data(), std::size_t(in.gcount())) != XXH_OK)
      return BakeStatus::failure(BakeError::kInternal, "hashing '" + path + "' failed");
  }
  if (!in.eof()) return BakeStatus::failure(BakeError::kIo, "cannot read '" + path + "' to hash it");
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)XXH64_digest(state.get()));
  *out_hex = hex;
  return BakeStatus::success();
}

// Which files went in: the first file's hash as before, then every file with its format, units,
// scale and (for scene files) the nodes taken. Names, not paths: paths differ between machines.
nlohmann::ordered_json sourceJson(const BakeReport& report) {
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const ImportReport& input : report.inputs) {
    nlohmann::ordered_json file = {{"format", input.format},
                                   {"xxh64", input.source_hash},
                                   {"units", lengthUnitName(input.units)},
                                   {"scale", input.scale},
                                   {"triangles", input.triangles}};
    if (!input.nodes.empty()) {
      nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
      for (const NodeImport& node : input.nodes)
        nodes.push_back(node.name);
      file["nodes"] = nodes;
    }
    files.push_back(file);
  }
  return {{"xxh64", report.source_hash}, {"files", files}};
}

nlohmann::ordered_json unitsJson(const BakeReport& report) { return {{"field", lengthUnitName(report.units)}}; }

// The META section: the tool, the mode, every parameter and the source, as UTF-8 JSON. No clock and
// no path: the same mesh and options must give the same bytes wherever and whenever they are baked.
std::string metadataJson(const BakeOptions& o, const format::GridGeometry& g, const BakeReport& report) {
  const std::string& sign = report.sign;
  nlohmann::ordered_json meta;
  meta["tool"] = "dngbake";
  meta["tool_version"] = DNG_TOOL_VERSION;
  meta["mode"] = normalModeName(o.mode);
  meta["parameters"] = {{"voxel_size", g.voxel_size},
                        {"band_voxels", g.band / g.voxel_size},
                        {"resolution", o.resolution},
                        {"max_speed", o.max_speed},
                        {"dt", o.dt},
                        {"blur_radius", o.blur_radius},
                        {"blur_rounds", o.blur_rounds},
                        {"sign", sign},
                        {"encoding", encodingName(o.encoding)},
                        {"brick_size", o.brick.brick_size},
                        {"tolerance_voxels", o.brick.tolerance_distance},
                        {"tolerance_degrees", o.brick.tolerance_normal_deg},
                        {"lift", o.lift},
                        {"second_planes", o.second_planes}};
  meta["conservative_planes"] = (g.flags & format::kGridFlagConservativePlanes) != 0;
  // Files baked before dngbake checked its planes at the cells' points against the triangles lack this
  // (BAKING.md, "Conservative planes"): a reader can tell them apart and bake them again.
  meta["planes_checked_on_triangles"] = (g.flags & format::kGridFlagConservativePlanes) != 0;
  meta["source"] = sourceJson(report);
  meta["units"] = unitsJson(report);
  return meta.dump();
}

// The inputs through their importers (import.h), each file hashed; the soup is in field units.
BakeStatus loadInputs(const BakeInputs& inputs, TriangleSoup* out_soup, BakeReport* report) {
  BakeStatus status =
      importInputs(inputs.paths, inputs.import, inputs.units, out_soup, &report->inputs, &report->warnings);
  for (const ImportReport& input : report->inputs) { // also on failure: the reader may say why
    for (const std::string& m : input.messages)
      report->warnings.push_back(inputs.paths.size() > 1 ? "'" + input.path + "': " + m : m);
  }
  if (!status.ok()) return status;
  for (ImportReport& input : report->inputs) {
    if (!(status = hashFile(input.path, &input.source_hash)).ok()) return status;
  }
  report->source_hash = report->inputs.front().source_hash;
  report->units = fieldUnit(inputs.units, report->inputs);
  return BakeStatus::success();
}

// A mesh with holes that still encloses space deeper than the band: the winding number calls that space
// inside, and a particle that gets there through a hole is not walked (RUNTIME.md, "Limits").
std::string holesWarning(const MeshReport& mesh) {
  return "the mesh has holes (" + std::to_string(mesh.hole_edges) +
         " open edges) yet encloses space, which the field takes for inside: particles that get in through a "
         "hole are not kept from passing out through the surface (docs/RUNTIME.md, \"Limits\"); fill the holes "
         "if it is meant as a solid";
}

class StageTimer {
public:
  explicit StageTimer(BakeReport* report) : report_(report), start_(Clock::now()) {}
  void done(const char* stage) {
    const auto now = Clock::now();
    report_->stage_seconds.emplace_back(stage, std::chrono::duration<double>(now - start_).count());
    start_ = now;
  }

private:
  BakeReport* report_;
  Clock::time_point start_;
};

bool reportStage(ProgressFn progress, void* user, const char* stage) {
  return progress == nullptr || progress(user, stage, 1.0);
}

// A baker progress callback seen as the writer's, for one stage.
struct StageProgress {
  ProgressFn progress;
  void* user;
  const char* stage;
  static bool report(void* self, double fraction) {
    const auto* p = static_cast<const StageProgress*>(self);
    return p->progress == nullptr || p->progress(p->user, p->stage, fraction);
  }
};

BakeStatus bakeStages(const BakeInputs& inputs, const BakeOutputs& outputs, const BakeOptions& options,
                      ProgressFn progress, void* user, BakeReport* report) {
  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.threads);
  StageTimer timer(report);
  TriangleSoup soup;
  BakeStatus status = loadInputs(inputs, &soup, report);
  if (!status.ok()) return status;
  timer.done("load");
  if (!reportStage(progress, user, "load")) return BakeStatus::cancelled();

  report->mesh = checkMesh(soup);
  if (!(status = requireBakeable(report->mesh)).ok()) {
    if (soup.faces_with_bad_index > 0) // usually coordinates the reader could not parse, such as "nan"
      status.message += " (" + std::to_string(soup.faces_with_bad_index) +
                        " faces referred to vertices the file does not define; unparsable coordinates?)";
    return status;
  }
  if (!(status = placeGrid(report->mesh, options, &report->grid, &report->warnings)).ok()) return status;
  timer.done("check");

  // auto: pseudonormals where they are exact (and faster: O(1) after the closest point), the winding
  // number wherever the mesh is open, non-manifold or inconsistently oriented.
  PseudonormalSign pseudonormals;
  const bool use_pseudonormals =
      options.sign == SignMode::kPseudonormal || (options.sign == SignMode::kAuto && report->mesh.wellFormedSolid());
  report->sign = use_pseudonormals ? "pseudonormal" : "winding";
  if (use_pseudonormals && !(status = pseudonormals.build(soup, report->mesh)).ok()) return status;
  BandGrid band(report->grid);
  status = computeDistanceField(soup, use_pseudonormals ? &pseudonormals : nullptr, progress, user, &band);
  if (!status.ok()) return status;
  report->band_blocks = band.blockCount();
  if (report->mesh.hole_edges > 0 && band.hasFarInside()) report->warnings.push_back(holesWarning(report->mesh));
  timer.done("distance");
  if (!(status = applyNormalMode(soup, options, progress, user, &band)).ok()) return status;
  timer.done("normals");
  if (!reportStage(progress, user, "normals")) return BakeStatus::cancelled();
  // Second planes are tested against the triangles as a solid's (conservative_planes.cpp): for
  // closed, consistently oriented meshes only, and only the bricked encoding stores them.
  const bool second_planes =
      options.second_planes && options.encoding == format::Encoding::kBricked && report->mesh.wellFormedSolid();
  status = makePlanesConservative(options.lift, soup, second_planes, progress, user, &band);
  if (!status.ok()) return status;
  report->grid.flags = band.grid().flags;
  timer.done("conservative");

  const std::string meta = metadataJson(options, report->grid, *report);
  StageProgress encode_progress{progress, user, "encode"};
  format::EncodeHooks hooks;
  hooks.progress = {&StageProgress::report, &encode_progress};
  hooks.parallel_for = [](std::size_t count, const std::function<void(std::size_t)>& task) {
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) { task(i); });
  };
  format::EncodeResult encoded = options.encoding == format::Encoding::kDense
                                     ? format::encodeDense(band, meta, hooks)
                                     : format::encodeBricked(band, options.brick, meta, hooks);
  if (encoded.code == format::EncodeError::kCancelled) return BakeStatus::cancelled();
  if (!encoded.ok()) return BakeStatus::failure(BakeError::kInternal, "encoding failed: " + encoded.error);
  report->encode = encoded.stats;
  timer.done("encode");
  // From here on nothing cancels: a bake that starts writing finishes (bake.h), and says so.

  // Both outputs are written in full before either replaces a file: a failure leaves both as they were.
  StagedOutputs staged;
  if (!outputs.vdb.empty()) {
    std::string temp;
    if (!(status = staged.reserve(outputs.vdb, &temp)).ok()) return status;
    if (!(status = exportVdb(band, temp, outputs.vdb)).ok()) return status;
    timer.done("export_vdb");
  }
  if (!(status = staged.write(outputs.dng, encoded.bytes)).ok()) return status;
  if (!(status = staged.commit()).ok()) return status;
  report->output_bytes = encoded.bytes.size();
  timer.done("write");
  return BakeStatus::success();
}

// Peak resident memory of the process so far (Linux reports ru_maxrss in KiB), 0 when unknown.
std::uint64_t peakMemoryBytes() {
  struct rusage usage {};
  return ::getrusage(RUSAGE_SELF, &usage) == 0 ? std::uint64_t(usage.ru_maxrss) * 1024u : 0u;
}

} // namespace

// Nothing is written before the last stage, so an exception (memory running out in the band's grids,
// an OpenVDB or TBB error) leaves no output behind; it only has to become a status instead of an abort.
BakeStatus bake(const std::string& input, const BakeOutputs& outputs, const BakeOptions& options, ProgressFn progress,
                void* user, BakeReport* report) {
  BakeInputs inputs;
  inputs.paths = {input};
  return bake(inputs, outputs, options, progress, user, report);
}

BakeStatus bake(const BakeInputs& inputs, const BakeOutputs& outputs, const BakeOptions& options, ProgressFn progress,
                void* user, BakeReport* report) {
  // Every option first: a bad value must cost nothing and be reported as the usage error it is.
  if (BakeStatus checked = checkBakeOptions(options); !checked.ok()) return checked;
  if (BakeStatus checked = checkOutputPaths(inputs.paths, outputs); !checked.ok()) return checked;
  BakeReport unused; // the stages fill a report as they go, wanted or not
  if (report == nullptr) report = &unused;
  BakeStatus status;
  try {
    status = bakeStages(inputs, outputs, options, progress, user, report);
  } catch (const std::bad_alloc&) {
    status = outOfMemoryFailure();
  } catch (const std::exception& e) {
    status = BakeStatus::failure(BakeError::kInternal, std::string("internal error: ") + e.what());
  }
  report->peak_memory_bytes = peakMemoryBytes(); // also when memory ran out: how far the bake got
  return status;
}

} // namespace baker
} // namespace dng
