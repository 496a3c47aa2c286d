// Internal: the C ABI's handle types and message helpers, shared by c_api.cpp (versions and fields)
// and c_api_scene.cpp (scenes).
#pragma once

#include "dng/body_index.h"
#include "dng/dng.h"
#include "dng/file.h"
#include "dng/particles.h"

#include <cstddef>
#include <cstdint>
#include <vector>

struct dng_field {
  dng::File file; // owner when opened from a path
  dng::View view; // what queries use (points into file, or into caller memory)
};

// Bodies by index, plus the enabled ones packed in index order for stepParticles, which takes one
// contiguous array. `active` is rebuilt when the set of enabled bodies changes and patched in place
// when one body changes, so moving every body each frame stays O(bodies). `index` is the broadphase
// over `active`, built by dng_scene_prepare_step; any change to a body makes it stale until the next
// prepare, and a stale index is simply not used (dng_scene_step never writes to the scene, so that
// threads may step one scene at once).
struct dng_scene {
  std::vector<dng::Body> bodies;
  std::vector<std::uint8_t> enabled;      // per index
  std::vector<std::int32_t> active_slot;  // per index: position in `active`, -1 when disabled
  std::vector<dng::Body> active;          // enabled bodies, in index order
  std::vector<std::uint32_t> active_body; // per position in `active`: the body's index
  dng::BodyIndex index;
  bool index_fresh = false; // built from `active` as it is now
};

namespace dng {
namespace c_api {

/// Writes the diagnostic (or the status's description) into the caller's buffer; returns the status.
dng_status report(Status status, const Diagnostic& diag, char* out, std::size_t capacity);
/// Same with a fixed sentence.
dng_status fail(Status status, const char* text, char* out, std::size_t capacity);

} // namespace c_api
} // namespace dng
