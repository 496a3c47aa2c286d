// The control stepper: what an exact collider does with the same particles. Each step's path, in the
// body's frame from its pose before the step to its pose after, is cast at the original triangles;
// a particle that hits stops a hair short of the first hit, on the side it came from (or, where that
// is not clear of every face, stays where it was on the body), and its velocity relative to the
// surface reflects with restitution. Its paths meet no surface by construction, so the
// judge must report 0 crossings for it: a check of the harness, not of dngrid.
#pragma once

#include "dng/body.h"
#include "mesh_reference.h"
#include "swarm.h"

#include <cstdint>

namespace dng {
namespace leak {

/// One step of dt for every particle of `swarm` (velocities already carry gravity). `before` and
/// `after` are the body at its poses at the start and at the end of the step. Returns the hits.
/// Parallel over particles (TBB).
std::uint64_t rayCastStep(const reference::MeshReference& mesh, float voxel, float restitution, float dt,
                          const Body& before, const Body& after, testing::Swarm* swarm);

} // namespace leak
} // namespace dng
