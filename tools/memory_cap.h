// dngbake's memory limit. A bake's grids grow with the surface's area in voxels, so a fine resolution
// or a wide band can ask for more memory than the machine or its container has; Linux then grants the
// allocations and later kills the process without a word (exit 137), in the middle of any stage. With
// a cap, the allocation that would take the process past it fails instead (std::bad_alloc, which
// dng::baker::bake reports as "out of memory", exit 4), and nothing is written.
//
// The cap is on the process's resident memory, checked against /proc/self/statm whenever another
// 16 MB has been allocated through operator new (every allocation of OpenVDB's grids, of the
// baker's arrays and of OpenMesh's meshes goes through it), and by any single larger allocation. Memory
// taken around operator new (Embree's BVH) is seen at the next check.
#pragma once

#include <cstdint>

namespace dng {
namespace tools {

/// Whether this build can cap its memory: not under AddressSanitizer or ThreadSanitizer, whose own
/// operator new must stay in place.
bool memoryCapSupported();

/// Caps this process's resident memory at `bytes` from now on; 0 lifts the cap. Without
/// memoryCapSupported() it changes nothing.
void setMemoryCap(std::uint64_t bytes);

/// The cap as set (also after it was reached); 0: none.
std::uint64_t memoryCap();

/// Whether an allocation has been refused for the cap. Each refusal also raises the cap by 64 MB, so
/// that unwinding and the error report can allocate.
bool memoryCapReached();

} // namespace tools
} // namespace dng
