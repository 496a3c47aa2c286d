// A broadphase for scenes of many bodies: a uniform grid over the bodies' world boxes, so a particle
// tests only the bodies whose boxes it is in instead of every body (docs/RUNTIME.md, "Many bodies").
#pragma once

#include "dng/body.h"
#include "dng/particles.h"
#include "dng/status.h"

#include <cstddef>
#include <cstdint>
#include <memory>

namespace dng {

/// Which bodies are near which places, for one set of bodies and one time step. Caller-owned: build it
/// once per frame, after the bodies are placed and before stepping, then share it read-only between
/// any number of threads stepping with those bodies (docs/INTEGRATION.md, "Threads").
///
/// Each body is entered with its world box grown by how far the box moves in dt, the same box
/// stepParticles culls with, so stepping with the index gives bit for bit the results of stepping
/// without it. Move-only.
class BodyIndex {
public:
  BodyIndex();
  ~BodyIndex();
  BodyIndex(BodyIndex&&) noexcept;
  BodyIndex& operator=(BodyIndex&&) noexcept;
  BodyIndex(const BodyIndex&) = delete;
  BodyIndex& operator=(const BodyIndex&) = delete;

  /// Builds the index for stepping `bodies[0, count)` by `dt`: their poses now, their velocities, their
  /// end-of-step poses. O(count + grid cells). Allocates, reusing the memory of the previous build
  /// when it is enough; never throws. Call it again whenever a body moves, turns, changes velocity or
  /// field, or the set of bodies or dt changes (materials may change freely); calling it every frame
  /// is fine: when the count, dt and every body (field, transform, velocities, box) are bit for bit
  /// what the last successful rebuild saw, it keeps the index after an O(count) comparison, and only
  /// finds again which bodies share a material if one changed; when some changed, it computes again
  /// the numbers of those alone, then the grid. Fails, leaving the index
  /// empty (built() false): kInvalidArgument when dt is not finite and > 0, bodies is null with count
  /// > 0, a body is not valid or its velocities give no finite motion
  /// over dt, or count >= 2^31; kOutOfMemory.
  Status rebuild(const Body* bodies, std::size_t count, float dt, Diagnostic* out_diag = nullptr);

  /// Whether the last rebuild succeeded.
  bool built() const;
  /// The count and dt of the last successful rebuild (0 when not built).
  std::size_t bodyCount() const;
  float dt() const;
  /// Grid cells per axis (all 0 when not built), for tests and tuning.
  void cellDims(std::uint32_t out_dims[3]) const;

  /// The bodies a move within the world box [lo, hi] is walked through: those whose grown box overlaps
  /// it, in increasing index order (compared as the step compares, so a NaN coordinate rejects nothing
  /// along its axis). Writes at most `capacity` of them to `out` (which may be null when capacity is 0)
  /// and returns how many there are. Thread-safe; no allocation. 0 when not built.
  std::size_t bodiesNear(Vec3f lo, Vec3f hi, std::uint32_t* out, std::size_t capacity) const;

  struct Impl; ///< internal (runtime/src/broadphase.h)

private:
  friend Status stepParticles(const ParticleSpan&, float, const Body*, std::size_t, const BodyIndex&, Diagnostic*);
  std::unique_ptr<Impl> impl_;
};

/// stepParticles (dng/particles.h) with a broadphase: the same results, bit for bit, but each particle
/// tests only the bodies the index lists near it. `index` must have been rebuilt from these bodies, in
/// this state, with this count and dt: each call checks that in O(count) and fails with
/// kInvalidArgument, touching no particle, when the index is not built or is stale (a body moved or
/// its velocity changed since). No allocation; any number of threads may step disjoint spans with
/// one index at once.
Status stepParticles(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
                     const BodyIndex& index, Diagnostic* out_diag = nullptr);

} // namespace dng
