// Writing .dng files: a generic container builder and the two payload encoders.
//
// Everything here produces bytes in memory; putting them on disk atomically is the caller's job.
// Output is a pure function of the inputs (single-threaded, no clocks, no addresses), so the same
// field and options always give byte-identical files.
#pragma once

#include "dng/format/dense_field.h"
#include "dng/format/field_source.h"
#include "dng/format/layout.h"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace dng {
namespace format {

/// Assembles header, section table and 64-byte aligned sections, in the order they were added.
/// Not thread-safe; cheap to create.
class ContainerBuilder {
public:
  /// Copies `size` bytes as a section with FourCC `tag`; `flags` bit 0 marks it required.
  void addSection(std::uint32_t tag, std::uint32_t flags, const void* data, std::size_t size);

  /// Sets the version numbers written into the header (tests use it to fake newer files).
  void setVersion(std::uint16_t major, std::uint16_t minor) {
    major_ = major;
    minor_ = minor;
  }

  /// The complete file: header, table, sections, every hash filled in.
  std::vector<std::uint8_t> finish() const;

private:
  struct Pending {
    std::uint32_t tag;
    std::uint32_t flags;
    std::vector<std::uint8_t> bytes;
  };
  std::vector<Pending> sections_;
  std::uint16_t major_ = kVersionMajor;
  std::uint16_t minor_ = kVersionMinor;
};

/// Recomputes every section hash whose range lies inside `bytes`, then the table and header hashes.
/// For tools and tests that patch a file on purpose; never needed after finish().
void resealHashes(std::vector<std::uint8_t>& bytes);

/// Bricked-encoder knobs. Tolerances decide when a brick may be replaced by a plane or far tile:
/// only when every voxel it replaces is reproduced within them.
struct BrickOptions {
  std::uint32_t brick_size = 8;      ///< voxels per brick edge: 4, 8 or 16
  float tolerance_distance = 0.02f;  ///< in voxels
  float tolerance_normal_deg = 0.5f; ///< in degrees
};

/// What an encoder wrote and the largest error it let through, measured over in-band voxels
/// (|distance| < band) by decoding what it wrote at each voxel centre.
struct EncodeStats {
  TileCounts tiles; ///< all zero for dense
  std::uint64_t band_voxels = 0;
  float max_distance_error_voxels = 0.0f;
  float max_normal_error_deg = 0.0f;
  /// With a LIFT section: the largest |decoded + lift - accurate| over band voxel centres, in voxels.
  float max_lifted_error_voxels = 0.0f;
  std::uint64_t payload_bytes = 0; ///< bytes of the payload sections (excluding GRID and META)
  /// Bricked, with second bounds: the tiles given a block of them in the PLN2 section, and the voxels
  /// given one.
  std::uint64_t second_plane_blocks = 0;
  std::uint64_t second_planes = 0;
};

/// Why an encode failed.
enum class EncodeError : int {
  kOk = 0,
  kInvalidGeometry, ///< checkGeometry refused the grid
  kInvalidOptions,  ///< brick size or tolerances out of range
  kInvalidField,    ///< array sizes wrong, or a voxel not finite or beyond format::kMaxMagnitude
  kTooLarge,        ///< more bricks than the pool index can address
  kCancelled,       ///< the progress callback asked to stop
};

/// Result of an encode: on success `code` is kOk and `bytes` the file; otherwise `bytes` is empty and
/// `error` says why in a sentence for people (programs compare `code`).
struct EncodeResult {
  std::vector<std::uint8_t> bytes;
  EncodeStats stats;
  EncodeError code = EncodeError::kOk;
  std::string error;
  bool ok() const { return code == EncodeError::kOk; }
  /// Records a failure unless one is recorded already (the first one wins) or `message` is empty
  /// (the checks return an empty message when they pass).
  void fail(EncodeError c, std::string message) {
    if (!ok() || message.empty()) return;
    code = c;
    error = std::move(message);
  }
};

/// Progress of a long encode: the fraction done in [0, 1], one call at a time (from whichever thread
/// finished a piece); a false return stops the encode with EncodeError::kCancelled. Null: no reports.
struct EncodeProgress {
  bool (*report)(void* user, double fraction) = nullptr;
  void* user = nullptr;
  bool operator()(double fraction) const { return report == nullptr || report(user, fraction); }
};

/// Runs task(i) for every i in [0, count), on any threads in any order, and returns when all are done.
/// The encoders hand it independent pieces (z layers of bricks, z slices) and join the results in
/// order, so the bytes never depend on it. The writer itself uses no threads; callers bring their own.
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& task)>;

/// Optional services for the encoders.
struct EncodeHooks {
  EncodeProgress progress;
  /// Empty: the pieces run in order on the calling thread. Set: the source's read() and farHint()
  /// must be safe to call from several threads at once.
  ParallelFor parallel_for;
};

/// Empty when `grid` can be written, otherwise why not (non-finite or out-of-range placement, zero
/// or oversized dimensions, a big-endian host).
std::string checkGeometry(const GridGeometry& grid);

/// Empty when `field` can be written, otherwise why not: checkGeometry, array sizes, non-finite values.
std::string checkField(const DenseField& field);

/// Dense encoding: every voxel's distance and normal as float32. `metadata_json` (UTF-8 JSON, may be
/// empty) goes into an optional META section when not empty. Reads the source one z slice at a time,
/// reporting progress after each; a non-finite voxel fails the encode.
[[nodiscard]] EncodeResult encodeDense(const FieldSource& source, std::string_view metadata_json,
                                       const EncodeHooks& hooks = {});
[[nodiscard]] EncodeResult encodeDense(const DenseField& field, std::string_view metadata_json);

/// Bricked encoding, the paper's compressed plane grid (§3.2). See docs/FORMAT.md. Reads the source
/// one brick at a time, skips the reads of bricks the source hints are far, and reports progress after
/// each z layer of bricks.
[[nodiscard]] EncodeResult encodeBricked(const FieldSource& source, const BrickOptions& options,
                                         std::string_view metadata_json, const EncodeHooks& hooks = {});
[[nodiscard]] EncodeResult encodeBricked(const DenseField& field, const BrickOptions& options,
                                         std::string_view metadata_json);

} // namespace format
} // namespace dng
