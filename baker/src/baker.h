// The baker's stages, declared in one place (DESIGN.md §4). Each stage lives in its own .cpp:
//   load_mesh.cpp   OpenMesh parsing into a triangle soup
//   import_*.cpp    one importer per family of formats behind one interface (import.h)
//   reader_guards.cpp   checks for inputs OpenMesh's readers mishandle, run before them
//   check_mesh.cpp  mesh diagnostics and the "can this be baked" decision
//   closest_point.cpp   Embree closest-point queries
//   winding_number.cpp  fast generalized winding number on an Embree-built BVH (the sign)
//   pseudonormal.cpp    sign by angle-weighted pseudonormals (closed manifold meshes only)
//   grid_placement.cpp  where the grid goes, how fine, how thick the band
//   band_grid.cpp       the working store: the band as sparse OpenVDB grids (band_grid.h)
//   distance_field.cpp  the band's blocks, exact unsigned distance, sign, exact normals (TBB over blocks)
//   normal_modes.cpp    surface rasterization for the paper's normal-blur and potential-gradient normals
//   blurred_normals.cpp the paper's blur on OpenVDB grids, and each method's normals from it
//   bake.cpp            the whole pipeline with timings, progress and cancel
//   write_file.cpp      atomic output: temporary file, fsync, rename
//   export_vdb.cpp      the band grids written as a .vdb
// Only band_grid.cpp, blurred_normals.cpp and export_vdb.cpp include OpenVDB: each takes ~25 s to compile.
#pragma once

#include "band_grid.h"
#include "dng/format/vec3.h"
#include "dng/format/writer.h"
#include "import.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dng {
namespace baker {

/// Documented exit codes of the tools (docs/BAKING.md); every baker error carries one.
enum class ExitCode : int {
  kOk = 0,
  kUsage = 1,        ///< bad command line
  kIo = 2,           ///< a file could not be read or written
  kInvalidInput = 3, ///< the input is unusable (empty, non-finite, all degenerate)
  kInternal = 4,     ///< a bug or resource failure
  kUnsupported = 5,  ///< a format or feature this build does not handle
};

/// Result of a baker stage: ok, or a code plus a sentence for the user.
struct [[nodiscard]] BakeStatus {
  ExitCode code = ExitCode::kOk;
  std::string message;
  bool ok() const { return code == ExitCode::kOk; }
  static BakeStatus success() { return {}; }
  static BakeStatus failure(ExitCode c, std::string m) { return {c, std::move(m)}; }
  /// What every stage returns when its progress callback asked to stop.
  static BakeStatus cancelled() { return {ExitCode::kInternal, "cancelled"}; }
};

/// Triangles exactly as the file gave them (polygons fanned into triangles), with no merging,
/// splitting or dropping: non-manifold and open input survives intact.
struct TriangleSoup {
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::uint64_t polygons = 0;               ///< faces read, before triangulation
  std::uint64_t faces_with_bad_index = 0;   ///< faces that referred to missing vertices (skipped)
  std::vector<std::string> reader_messages; ///< what OpenMesh's reader reported, one line each
};

/// Loads OBJ, OFF, PLY, STL or OM with OpenMesh's readers. Errors: kIo when the file cannot be
/// opened or parsed, kUnsupported for other extensions. Not thread-safe (OpenMesh's IO registry and
/// log streams are global).
BakeStatus loadMesh(const std::string& path, TriangleSoup* out_soup);

/// What the checks found. Edges are counted by vertex index pairs.
struct MeshReport {
  std::uint64_t vertices = 0;
  std::uint64_t triangles = 0;
  std::uint64_t non_finite_vertices = 0;
  std::uint64_t degenerate_triangles = 0; ///< repeated vertex or zero area
  std::uint64_t boundary_edges = 0;       ///< used by one triangle: the mesh is open
  std::uint64_t non_manifold_edges = 0;   ///< used by three or more triangles
  std::uint64_t components = 0;           ///< connected by shared vertices
  std::uint64_t misoriented_edges = 0;    ///< shared by two triangles that run it the same way
  double signed_volume = 0.0;             ///< > 0 when a closed mesh's faces point outwards
  Vec3f bounds_min;
  Vec3f bounds_max;
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  /// Closed, manifold, consistently oriented and facing outwards: pseudonormals are exact here.
  bool wellFormedSolid() const { return closed() && misoriented_edges == 0 && signed_volume > 0.0; }
};

MeshReport checkMesh(const TriangleSoup& soup);

/// kInvalidInput when the mesh cannot be baked: no triangles, non-finite coordinates, or every
/// triangle degenerate. Open and non-manifold meshes are fine (the sign is robust to them).
BakeStatus requireBakeable(const MeshReport& report);

/// Exact closest points on a soup's triangles through Embree's BVH (rtcPointQuery). Degenerate and
/// non-finite triangles are left out. Queries are const and thread-safe.
class ClosestPointIndex {
public:
  ClosestPointIndex();
  ~ClosestPointIndex();
  ClosestPointIndex(const ClosestPointIndex&) = delete;
  ClosestPointIndex& operator=(const ClosestPointIndex&) = delete;

  /// Builds the BVH over `soup`, which must outlive the index. kInternal when Embree fails.
  BakeStatus build(const TriangleSoup& soup);

  struct Hit {
    bool found = false;    ///< false when no triangle is within the radius
    float distance = 0.0f; ///< unsigned
    Vec3f point;           ///< closest point on the surface
    std::uint32_t triangle = 0;
  };
  /// The closest surface point within `radius` of `p`; a small radius makes far queries cheap.
  Hit query(Vec3f p, float radius) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The generalized winding number of a triangle soup (Jacobson et al. 2013), fast through a
/// hierarchy of dipole clusters (Barill et al. 2018): exact solid angles near the query, one dipole
/// per distant cluster. Robust on open meshes and soups: inside where w > 0.5. The hierarchy is
/// Embree's BVH builder (rtcBuildBVH). Evaluation is const and thread-safe.
class WindingNumber {
public:
  WindingNumber();
  ~WindingNumber();
  WindingNumber(const WindingNumber&) = delete;
  WindingNumber& operator=(const WindingNumber&) = delete;

  BakeStatus build(const TriangleSoup& soup);
  double evaluate(Vec3f q) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Sign by angle-weighted pseudonormals (Baerentzen & Aanaes 2005): O(1) after the closest point,
/// exact for closed manifold meshes and refused for any other. Queries are const and thread-safe.
class PseudonormalSign {
public:
  PseudonormalSign();
  ~PseudonormalSign();
  PseudonormalSign(const PseudonormalSign&) = delete;
  PseudonormalSign& operator=(const PseudonormalSign&) = delete;

  /// kInvalidInput unless the mesh is a well-formed solid (closed, manifold, consistently oriented).
  BakeStatus build(const TriangleSoup& soup, const MeshReport& report);
  /// Whether `p` is inside, given its closest surface point on `triangle`.
  bool inside(Vec3f p, Vec3f closest, std::uint32_t triangle) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
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
};

/// Grid geometry for a mesh: padding >= band on every side, band from --band or from the fastest
/// particle's travel per step plus View::guaranteedReach's half-diagonal guard. Warnings (e.g. a band
/// wider than a quarter of the grid) are appended to *io_warnings.
BakeStatus placeGrid(const MeshReport& mesh, const BakeOptions& options, format::GridGeometry* out_grid,
                     std::vector<std::string>* io_warnings);

/// Progress of the long stages: stage name and fraction in [0, 1]. Returning false cancels the bake.
using ProgressFn = bool (*)(void* user, const char* stage, double fraction);

/// Fills `out` (empty, over the grid placeGrid chose): exact distance (Embree) at every voxel within
/// the band, sign (winding number, or pseudonormals when `pseudonormals` is given), exact normals,
/// then BandGrid::finishBand. Deterministic whatever the thread count.
BakeStatus computeDistanceField(const TriangleSoup& soup, const PseudonormalSign* pseudonormals, ProgressFn progress,
                                void* progress_user, BandGrid* out);

/// Replaces the band's normals by the paper's method 1 (normal-blur) or 2 (potential gradient);
/// exact mode keeps them. Surface voxels are those any triangle overlaps (exact triangle/box test).
BakeStatus applyNormalMode(const TriangleSoup& soup, const BakeOptions& options, ProgressFn progress,
                           void* progress_user, BandGrid* io);

/// Lowers every band voxel's distance until its plane, d + n . (p - c), is at most the true signed
/// distance everywhere in the voxel's cell (conservative_planes.cpp says how the bound is found), and
/// marks the grid format::kGridFlagConservativePlanes. Runs after the normals are final; with exact
/// normals the tangent part of the bound is zero. Reports stage "conservative"; cancel as the others.
BakeStatus makePlanesConservative(bool exact_normals, ProgressFn progress, void* progress_user, BandGrid* io);

/// A voxel the surface overlaps, with the average normal of the triangles overlapping it.
struct SurfaceVoxel {
  std::array<std::int32_t, 3> ijk;
  Vec3f normal;
};

/// Method 1's blur (paper §3.1): the surface normals blurred with the tent kernel of `radius` (1-8) for
/// `rounds` rounds, surface voxels reset after each; every band voxel the blur reaches takes the
/// normalized result, the others keep their normal. Reports stage "normals" after each pass; a false
/// return from `progress` cancels (kInternal, "cancelled", the band half-updated).
BakeStatus blurNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                       BandGrid* io, ProgressFn progress = nullptr, void* progress_user = nullptr);

/// Method 2 (paper §3.1): occupancy 1 at surface voxels blurred the same way; band voxels take the
/// normalized downhill gradient by central differences, oriented into the hemisphere of their exact
/// normal, where the gradient is not flat. Progress and cancel as blurNormals.
BakeStatus potentialNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                            BandGrid* io, ProgressFn progress = nullptr, void* progress_user = nullptr);

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

/// The files to bake into one field (their union) and how to read them (import.h).
struct BakeInputs {
  std::vector<std::string> paths;
  ImportOptions import;
  UnitOptions units;
};

/// Where the optional extra outputs go; empty means none.
struct BakeOutputs {
  std::string dng;
  std::string vdb;
};

/// The whole bake: load, check, place, distance, normals, encode, write outputs.dng (and outputs.vdb
/// when set) atomically.
BakeStatus bake(const std::string& input_path, const BakeOutputs& outputs, const BakeOptions& options,
                ProgressFn progress, void* progress_user, BakeReport* out_report);
/// The same over several inputs, scene selection and units.
BakeStatus bake(const BakeInputs& inputs, const BakeOutputs& outputs, const BakeOptions& options, ProgressFn progress,
                void* progress_user, BakeReport* out_report);

/// Writes the band as two OpenVDB grids, "distance" (a level set: FloatGrid, background = band,
/// active = band voxels) and "normal" (Vec3SGrid), in the .dng's world placement, to `path` atomically.
BakeStatus exportVdb(const BandGrid& band, const std::string& path);

/// Writes `bytes` to `path` through a temporary file in the same folder, fsync and rename: readers
/// see the old file or the new one, never a partial one. The temporary is removed on failure.
BakeStatus writeFileAtomically(const std::string& path, const std::vector<std::uint8_t>& bytes);

} // namespace baker
} // namespace dng
