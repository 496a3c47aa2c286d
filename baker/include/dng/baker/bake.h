// The baker's public API: bake a mesh file into a .dng, with every option it depends on and a report of
// what it did. dngbake is a thin program over bake(); engines' content pipelines may call it directly.
// The stages behind it are internal (baker/src/stages.h); docs/DESIGN.md explains them.
#pragma once

#include "dng/baker/import.h"
#include "dng/format/vec3.h"
#include "dng/format/writer.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dng {
namespace baker {

/// Why a bake failed. Not exit codes: dngbake maps these to its exit codes (tools/exit_codes.h).
enum class BakeError : int {
  kOk = 0,
  kBadOption,    ///< an option value is out of range, or options contradict each other or the mesh
  kIo,           ///< a file could not be read or written
  kInvalidInput, ///< the mesh is unusable (empty, non-finite, all degenerate)
  kInternal,     ///< a bug or a resource failure (out of memory, Embree, OpenVDB)
  kUnsupported,  ///< a format or feature this build does not handle
  kCancelled,    ///< the progress callback asked to stop
};

/// Result of a bake or of one of its stages: ok, or a code plus a sentence for the user.
struct [[nodiscard]] BakeStatus {
  BakeError code = BakeError::kOk;
  std::string message;
  bool ok() const { return code == BakeError::kOk; }
  static BakeStatus success() { return {}; }
  static BakeStatus failure(BakeError c, std::string m) { return {c, std::move(m)}; }
  /// What every stage returns when its progress callback asked to stop.
  static BakeStatus cancelled() { return {BakeError::kCancelled, "cancelled"}; }
};

/// What the mesh checks found. Edges are counted by vertex index pairs (hole_edges: by position).
struct MeshReport {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t non_finite_vertices = 0;
  std::uint64_t degenerate_triangles = 0; ///< repeated vertex or zero area
  std::uint64_t boundary_edges = 0;       ///< used by one triangle: the mesh is open
  /// Boundary edges that stay so when vertices at the same position count as one: the mesh's holes
  /// (a seam of repeated vertices, as files write where normals or texture coordinates change, is none).
  std::uint64_t hole_edges = 0;
  std::uint64_t non_manifold_edges = 0; ///< used by three or more triangles
  std::uint64_t components = 0;         ///< connected by shared vertices
  std::uint64_t misoriented_edges = 0;  ///< shared by two triangles that run it the same way
  double signed_volume = 0.0;           ///< > 0 when a closed mesh's faces point outwards
  Vec3f bounds_min;
  Vec3f bounds_max;
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  /// Closed, manifold, consistently oriented and facing outwards: pseudonormals are exact here.
  bool wellFormedSolid() const { return closed() && misoriented_edges == 0 && signed_volume > 0.0; }
};

/// How normals are made (paper §3.1, plus an exact mode).
enum class NormalMode { kNormalBlur, kPotential, kExact };
/// How inside is told from outside. kAuto: pseudonormals for well-formed solids (exact and O(1) after
/// the closest point), the winding number for everything else (robust on open meshes and soups).
enum class SignMode { kAuto, kWinding, kPseudonormal };

const char* normalModeName(NormalMode mode);

/// Everything a bake depends on. Lengths in mesh units.
struct BakeOptions {
  NormalMode mode = NormalMode::kNormalBlur;
  std::uint32_t resolution = 128; ///< voxels along the longest axis of the padded box (when voxel_size is 0)
  float voxel_size = 0.0f;        ///< explicit voxel edge; 0 = derive from resolution
  float band_voxels = 4.0f;       ///< field thickness in voxels (ignored when max_speed and dt are set)
  float max_speed = 0.0f;         ///< fastest particle, mesh units per second
  float dt = 0.0f;                ///< simulation step, seconds
  std::uint32_t blur_radius = 3;  ///< blurred modes: kernel radius in voxels (paper: 2-4)
  std::uint32_t blur_rounds = 3;  ///< blurred modes: rounds K
  SignMode sign = SignMode::kAuto;
  format::Encoding encoding = format::Encoding::kBricked;
  format::BrickOptions brick;
  std::uint32_t threads = 0; ///< 0 = all cores; the output never depends on it
  /// Write the LIFT section: what takes the lowered (conservative) distances back to the accurate ones
  /// for Interpolation::kAccurate queries. About a third of a bricked file; the step never reads it.
  /// (The blurred modes' SHAD section, their normals beside the distance's own, is always written.)
  bool lift = true;
  /// Write the PLN2 section (bricked only): second bounds beside edges and creases, which let the
  /// runtime's step prove particles outside there where one plane per voxel cannot (docs/FORMAT.md §5.5).
  bool second_planes = true;
};

/// Limits checkBakeOptions enforces.
inline constexpr std::uint32_t kMinResolution = 8;
/// The baker's own cap on voxels per axis (memory and time), far below the format's limit
/// (format::kMaxAxisVoxels).
inline constexpr std::uint32_t kMaxBakeAxisVoxels = 2048;
/// The smallest voxel OpenVDB's grids take (its maps refuse a voxel whose volume is below 3e-15).
inline constexpr float kMinVoxelSize = 1.5e-5f;
inline constexpr std::uint32_t kMaxBlurRadius = 8;
inline constexpr std::uint32_t kMaxBlurRounds = 32;

/// kBadOption, naming the option, when any value of `options` is out of range or two contradict each
/// other; checks nothing that needs the mesh. bake() calls it before any other work.
BakeStatus checkBakeOptions(const BakeOptions& options);

/// Progress of the long stages: stage name and fraction in [0, 1]. Returning false cancels the bake.
using ProgressFn = bool (*)(void* user, const char* stage, double fraction);

/// What a bake did, for the JSON report.
struct BakeReport {
  MeshReport mesh;
  std::vector<std::string> warnings;
  format::GridGeometry grid;
  format::EncodeStats encode;
  std::uint64_t output_bytes = 0;
  std::string source_hash; ///< XXH64 of the input file, hex
  std::string sign;        ///< the sign method used: "winding" or "pseudonormal"
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::uint64_t band_blocks = 0;           ///< 8^3 leaves of the working store holding band voxels
  std::uint64_t peak_memory_bytes = 0;     ///< the process's peak resident memory when the bake ended
  std::vector<ImportReport> inputs;        ///< one per input file, in order
  LengthUnit units = LengthUnit::kUnknown; ///< the field's length unit
};

/// The files to bake into one field (their union) and how to read them (dng/baker/import.h).
struct BakeInputs {
  std::vector<std::string> paths;
  ImportOptions import;
  UnitOptions units;
};

/// Where the outputs go: the .dng (required) and, when not empty, an OpenVDB export of the band.
struct BakeOutputs {
  std::string dng;
  std::string vdb;
};

/// The whole bake: check the options, load, check the mesh, place, distance, normals, encode, write
/// outputs.dng (and outputs.vdb when set) atomically. Nothing is written unless every stage before
/// the writes succeeded; a cancel (progress returning false) during the writes is not honoured, so
/// kCancelled always means nothing was written. Never throws. `out_report` may be null.
BakeStatus bake(const std::string& input_path, const BakeOutputs& outputs, const BakeOptions& options,
                ProgressFn progress, void* progress_user, BakeReport* out_report);
/// The same over several inputs, scene selection and units.
BakeStatus bake(const BakeInputs& inputs, const BakeOutputs& outputs, const BakeOptions& options, ProgressFn progress,
                void* progress_user, BakeReport* out_report);

} // namespace baker
} // namespace dng
