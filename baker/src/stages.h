// Internal to the baker: its stages, declared in one place (docs/DESIGN.md §5); the public
// API is dng/baker/bake.h. Each stage lives in its own .cpp:
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
//   bake_options.cpp    checkBakeOptions: every option value, before any work
//   conservative_planes.cpp  every band voxel's plane lowered to a bound of the distance over its cell
//   second_planes.cpp   second bounds beside edges and creases, proven against the triangles
//   bake.cpp            the whole pipeline with timings, progress and cancel
//   write_file.cpp      atomic output: temporary file, fsync, rename
//   export_vdb.cpp      the band grids written as a .vdb
// Only band_grid.cpp, blurred_normals.cpp and export_vdb.cpp include OpenVDB: each takes ~25 s to compile.
#pragma once

#include "band_grid.h"
#include "dng/baker/bake.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dng {
namespace baker {

/// Triangles exactly as the file gave them (polygons fanned into triangles), with no merging,
/// splitting or dropping: non-manifold and open input survives intact.
struct TriangleSoup {
  std::vector<Vec3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::uint64_t polygons = 0;               ///< faces read, before triangulation
  std::uint64_t faces_with_bad_index = 0;   ///< faces that referred to missing vertices (skipped)
  std::vector<std::string> reader_messages; ///< what OpenMesh's reader reported, one line each
};

/// Loads OBJ, OFF, PLY or STL with OpenMesh's readers. Errors: kIo when the file cannot be opened or
/// parsed, kInvalidInput for what the reader guards refuse (reader_guards.h), kUnsupported for other
/// extensions, OpenMesh's .om among them (with what to do instead). Not thread-safe (OpenMesh's IO
/// registry and log streams are global).
BakeStatus loadMesh(const std::string& path, TriangleSoup* out_soup);

/// The failure for memory running out in any stage (std::bad_alloc: the machine's, or dngbake's
/// --memory-limit): kInternal, saying what to change. Stages that catch what a library throws let
/// std::bad_alloc through to bake(), which reports this; a process of its own (import_isolated.cpp)
/// reports it itself. Inline: the fuzz targets build the importers without bake.cpp.
inline BakeStatus outOfMemoryFailure() {
  return BakeStatus::failure(BakeError::kInternal, "out of memory while baking: use a larger --voxel-size, a smaller "
                                                   "--resolution or a thinner --band");
}

MeshReport checkMesh(const TriangleSoup& soup);

/// kInvalidInput when the mesh cannot be baked: no triangles, non-finite coordinates, or every
/// triangle degenerate. Open and non-manifold meshes are fine (the sign is robust to them).
BakeStatus requireBakeable(const MeshReport& report);

/// A number as a message writes it (printf's %g): 1.5e-05, 3e+31, 0.0454545.
inline std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

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

  /// Calls visit(triangle) for every triangle of the soup (degenerate ones left out, as above) that
  /// comes within `radius` of `p`, in no particular order.
  template <class Visit> void forEachTriangleNear(Vec3f p, float radius, Visit&& visit) const {
    forEachNear(
        p, radius, nullptr, [](void* user, std::uint32_t t) { (*static_cast<Visit*>(user))(t); }, &visit);
  }
  /// The same for the triangles `wanted(triangle)` also accepts: a cheap test asked first, before the
  /// exact distance, of each triangle the walk reaches, in the order the visits come. A test that
  /// reads what earlier visits wrote sees what it would see asked inside the visit.
  template <class Wanted, class Visit>
  void forEachTriangleNear(Vec3f p, float radius, Wanted&& wanted, Visit&& visit) const {
    struct Both {
      Wanted& wanted;
      Visit& visit;
    } both{wanted, visit};
    forEachNear(
        p, radius, [](void* user, std::uint32_t t) { return static_cast<Both*>(user)->wanted(t); },
        [](void* user, std::uint32_t t) { static_cast<Both*>(user)->visit(t); }, &both);
  }

private:
  void forEachNear(Vec3f p, float radius, bool (*wanted)(void* user, std::uint32_t triangle),
                   void (*visit)(void* user, std::uint32_t triangle), void* user) const;
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

/// Grid geometry for a mesh: padding >= band on every side, band from --band or from the fastest
/// particle's travel per step plus View::guaranteedReach's half-diagonal guard. Warnings (e.g. a band
/// wider than a quarter of the grid) are appended to *io_warnings.
BakeStatus placeGrid(const MeshReport& mesh, const BakeOptions& options, format::GridGeometry* out_grid,
                     std::vector<std::string>* io_warnings);

/// Fills `out` (empty, over the grid placeGrid chose): exact distance (Embree) at every voxel within
/// the band, sign (winding number, or pseudonormals when `pseudonormals` is given), exact normals,
/// then BandGrid::finishBand. Deterministic whatever the thread count.
BakeStatus computeDistanceField(const TriangleSoup& soup, const PseudonormalSign* pseudonormals, ProgressFn progress,
                                void* progress_user, BandGrid* out);

/// Gives the band shading normals by the paper's method 1 (normal-blur) or 2 (potential gradient),
/// BandGrid::startShading; the normals stay the distance's own, the planes'. Exact mode adds none. Surface voxels are
/// those any triangle overlaps (exact triangle/box test).
BakeStatus applyNormalMode(const TriangleSoup& soup, const BakeOptions& options, ProgressFn progress,
                           void* progress_user, BandGrid* io);

/// Lowers every band voxel's distance until its plane, d + n . (p - c), is at most the true signed
/// distance everywhere in the voxel's cell (conservative_planes.cpp says how the bound is found), and
/// marks the grid format::kGridFlagConservativePlanes. The band's normals must be the distance's own
/// (every mode keeps them; the blurred ones are shading normals). Reports stage "conservative"; cancel
/// as the others. With `keep_accurate` the band keeps the distances from before the lowering
/// (BandGrid::keepAccurateDistances). Every plane is also checked against `soup`'s triangles. With
/// `second_planes` (only for a closed, consistently oriented `soup`: the field's inside changes only
/// across its surface) it also gives the voxels beside edges a second plane where one adds provable
/// clearance, checked against the triangles (BandGrid::startSecondPlanes).
BakeStatus makePlanesConservative(bool keep_accurate, const TriangleSoup& soup, bool second_planes, ProgressFn progress,
                                  void* progress_user, BandGrid* io);

/// A voxel the surface overlaps, with the average normal of the triangles overlapping it.
struct SurfaceVoxel {
  std::array<std::int32_t, 3> ijk;
  Vec3f normal;
};

/// Method 1's blur (paper §3.1): the surface normals blurred with the tent kernel of `radius` (1-8) for
/// `rounds` rounds, surface voxels reset after each; every band voxel the blur reaches takes the
/// normalized result as its shading normal, the others keep their exact normal as theirs. Reports stage "normals" after
/// each pass; a false return from `progress` cancels (kCancelled, the band half-updated).
BakeStatus blurNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                       BandGrid* io, ProgressFn progress = nullptr, void* progress_user = nullptr);

/// Method 2 (paper §3.1): occupancy 1 at surface voxels blurred the same way; band voxels' shading
/// normals are the normalized downhill gradient by central differences, oriented into the hemisphere of their exact
/// normal, where the gradient is not flat. Progress and cancel as blurNormals.
BakeStatus potentialNormals(const std::vector<SurfaceVoxel>& surface, std::uint32_t radius, std::uint32_t rounds,
                            BandGrid* io, ProgressFn progress = nullptr, void* progress_user = nullptr);

/// Writes the band as OpenVDB grids, "distance" (a level set: FloatGrid, background = band, active =
/// band voxels), "normal" (Vec3SGrid) and the rest export_vdb.cpp names, in the .dng's world
/// placement, to the file `temp` (a StagedOutputs temporary); `path` is what messages call it.
BakeStatus exportVdb(const BandGrid& band, const std::string& temp, const std::string& path);

/// Refuses, before anything is read, outputs that would destroy something: an output that is an input
/// (kBadOption), the .dng and the export at one path (kBadOption), an existing output that is not a
/// regular file, such as a directory or /dev/null, which a rename would replace (kIo).
BakeStatus checkOutputPaths(const std::vector<std::string>& inputs, const BakeOutputs& outputs);

/// A bake's output files, each written in full to a temporary beside its path, then flushed to disk and
/// put in place together by commit() (renames): a bake that fails before commit leaves every output
/// path as it was, and readers see old files or new ones, never partial ones. Temporaries not
/// committed are removed on destruction. Temporaries get the mode a plain create would (0666 less the
/// umask).
class StagedOutputs {
public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();
  /// A new, empty temporary beside `path`, for a writer that opens files by name (OpenVDB's).
  BakeStatus reserve(const std::string& path, std::string* out_temp);
  /// `bytes` to a new temporary beside `path`.
  BakeStatus write(const std::string& path, const std::vector<std::uint8_t>& bytes);
  /// Flushes every temporary to disk, then renames each over its path in the order they were added. A
  /// rename that fails after an earlier one succeeded leaves that earlier output replaced.
  BakeStatus commit();

private:
  struct Entry {
    std::string temp, path;
  };
  std::vector<Entry> entries_;
};

} // namespace baker
} // namespace dng
