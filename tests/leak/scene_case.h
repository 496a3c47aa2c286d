// Scenes: several baked bodies at once and one swarm among them, every step judged against each body's
// original triangles in that body's own frame (swarm_judge.h). What one body's cases (leak_case.h)
// cannot show happens between bodies: a particle one body stopped where another arrives, a particle
// pushed by one body into another, a gap that closes.
#pragma once

#include "leak_case.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace dng {
namespace leak {

/// One body of a scene, moving with constant velocities.
struct SceneBody {
  SceneBody(const Subject* s, Vec3f at = {}, Vec3f velocity = {}, Vec3f spin = {})
      : subject(s), position(at), linear(velocity), angular(spin) {}

  const Subject* subject;
  Vec3f position; ///< where the mesh's centre is at time 0, world
  Vec3f linear;   ///< world units per second
  Vec3f angular;  ///< radians per second about the mesh's centre
};

struct SceneSpec {
  explicit SceneSpec(std::string scene_name) : name(std::move(scene_name)) {}

  std::string name;
  std::vector<SceneBody> bodies;
  Responses responses = Responses::kImpact;
  bool swept = false; ///< every body's material walks every step whatever its speed
  /// Particles start uniformly in this world box (flat for particles resting on a floor), outside every
  /// body and at least 0.1 of its voxel from its surface, at random directions with speeds up to
  /// `spawn_speed` (world units per second). The box must have room outside the bodies.
  Vec3f spawn_lo, spawn_hi;
  float spawn_speed = 0.0f;
  Vec3f gravity;
  std::size_t particles = 20000;
  int steps = 60; ///< the bodies' paths are laid out for this many steps
  std::uint32_t seed = 1;
};

/// The slowest of the bodies' design speeds (View::guaranteedReach() / kDt), world units per second.
float designSpeed(const std::vector<SceneBody>& bodies);

/// Runs the scene with dng::stepParticles over all its bodies. The counts are summed over the bodies,
/// each judged on its own triangles (a particle inside two bodies at the end counts twice); depths are
/// in voxels of the body crossed. `fast_steps` counts steps begun in a body's grid box faster, relative
/// to its surface, than that body's design speed. Deterministic for a given spec.
CaseResult runScene(const SceneSpec& spec);

/// The standard scenes of docs/LEAKS.md in one normal mode, with the bodies they bake.
class SceneSet {
public:
  /// Boxes made in code (a ground, crates, a wall): crates sliding, pushing particles into a wall and
  /// into a slower crate, closing in, passing each other, coming down and tumbling. Mesh files go to `folder`, which
  /// must exist. Null with *out_error on failure.
  static std::unique_ptr<SceneSet> boxes(baker::NormalMode mode, const std::string& folder, std::string* out_error);
  /// A closed mesh, baked (`mesh`, which must outlive the set), on a ground box baked in its mode: sliding
  /// along the ground it is sunk into, and spinning just above it.
  static std::unique_ptr<SceneSet> aroundMesh(const Subject& mesh, const std::string& folder, std::string* out_error);

  /// `count` random scenes from `seed`: two to four movers (8-unit crates, rods and slabs 2 and 1.5
  /// units thick) over a ground 120 units square, each sliding along it or spinning about a random axis
  /// 0.05 or 1 unit above it, at up to `speed` times the design speed, their paths kept 1 unit apart;
  /// particles resting on the ground or thrown above it; impact, impact + drag + flow or spring.
  static std::unique_ptr<SceneSet> random(baker::NormalMode mode, int count, std::uint32_t seed, float speed,
                                          const std::string& folder, std::string* out_error);

  const std::vector<SceneSpec>& scenes() const { return scenes_; }

private:
  SceneSet() = default;

  std::vector<std::unique_ptr<Subject>> bodies_; ///< the subjects the set baked
  std::vector<SceneSpec> scenes_;
};

} // namespace leak
} // namespace dng
