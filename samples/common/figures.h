// The paper's figures as runnable scenes (Ilmonen, Takala & Laitinen, Figs. 3, 6, 7, 8), a thin
// sheet, and the README demo. Each returns its statistics and the physical measurements its test
// asserts; with a picture prefix it also writes two views as PNG (prefix_side.png, prefix_top.png).
#pragma once

#include "analytic_fields.h"
#include "scene.h"

#include <memory>
#include <string>
#include <vector>

namespace dng {
namespace samples {

/// A field made from an analytic shape with the std-only writer, kept alive with its bytes.
struct GeneratedField {
  std::vector<std::uint8_t> bytes;
  View view;
};
std::unique_ptr<GeneratedField> generateField(const analytic::AnalyticField& shape, Vec3f lo, Vec3f hi, float voxel,
                                              float band_voxels);

/// Scale and pictures for a run. particles = 0 uses the sample's full size.
struct RunOptions {
  int particles = 0;
  std::string picture_prefix; ///< empty: no pictures
  int picture_pixels = 640;
  /// When set, the scenes that support it (the demo) store where every particle ended, world frame.
  std::vector<Vec3f>* final_positions = nullptr;
};

/// Fig. 3: particles falling on a table-like box. (a) bouncy beta = 0.7, (b) slippery beta = 0,
/// (c) high drag beta = 0, delta = 2, theta = 1 voxel.
struct FallingResult {
  SceneStats stats;
  float mean_rebound_height = 0; ///< highest point after the first contact, above the top face
  float fraction_resting_on_top = 0;
};
FallingResult runFalling(float restitution, float drag, const RunOptions& options);

/// Figs. 6 and 7: a stream flowing past an obstacle with surface flow.
struct StreamResult {
  SceneStats stats;
  float fraction_downstream = 0;    ///< of the particles aimed at the obstacle, those that got past it
  float mean_downstream_offset = 0; ///< their mean distance from the stream's axis afterwards
};
/// Fig. 6: a sphere, the stream coming from the side (from_above = false) or falling on top.
StreamResult runSphereStream(bool from_above, const RunOptions& options);
/// Fig. 7: a vertical shaft, the stream from the right, with rho_in / rho_out / flow distance.
StreamResult runShaftStream(float rho_in, float rho_out, float flow_distance, const RunOptions& options);

/// Fig. 8: an explosion among buildings on a ground plane; one box field shared by every building.
struct ExplosionResult {
  SceneStats stats;
  float fraction_beyond_buildings = 0; ///< particles that ended farther out than the buildings
};
ExplosionResult runExplosion(const RunOptions& options);

/// A thin open sheet baked in potential mode (paper §3.1 method 2): particles fired at it from both
/// sides, from inside its band, must stay on their side.
struct SheetResult {
  SceneStats stats;
  std::size_t crossed = 0; ///< particles that ended behind the surface plane they started facing
};
SheetResult runSheet(const View& sheet_field, const RunOptions& options);

/// The README demo: particles raining on a baked mesh (the Stanford bunny), bouncing, sliding and
/// flowing off it. `up` is the mesh's vertical axis (0 x, 1 y, 2 z; bunny00.off is y-up).
SceneStats runDemo(const View& field, int up, const RunOptions& options);

} // namespace samples
} // namespace dng
