// The physical set-up of a leak case: the body's motion and material, gravity, and where the particles
// start. Speeds are in design speeds: View::guaranteedReach() x body scale / dt.
#pragma once

#include "dng/body.h"
#include "leak_case.h"
#include "swarm.h"

namespace dng {
namespace leak {

struct CaseSetup {
  float scale = 1.0f;
  float design_speed = 0.0f; ///< world units per second
  Vec3f position;            ///< where the mesh's centre is at time 0, world
  Vec3f linear;              ///< body velocity, world
  Vec3f angular;             ///< rad/s about the body origin (the mesh centre)
  Material material;
  Vec3f gravity;
  float spawn_speed = 0.0f; ///< largest world speed a particle starts with
  float speed_limit = 0.0f; ///< the largest relative speed the case means to test
};

CaseSetup makeSetup(const Subject& subject, const CaseSpec& spec);

/// Places `body` (made on the subject's view) at its pose at time t (from `position`, turning about the
/// mesh's centre), moving with the set-up's velocity.
void placeBody(const CaseSetup& setup, float t, Body* body);

/// The case's particles in the world at time 0 (body at its starting pose `body`), from spec.seed.
testing::Swarm spawnParticles(const Subject& subject, const CaseSpec& spec, const CaseSetup& setup, const Body& body);

} // namespace leak
} // namespace dng
