// Which SIMD instruction set View::sampleBatch (all three modes) and stepParticles use.
//
// The runtime carries its batch kernels for SSE4.1 (4 lanes), AVX2 (16 lanes, two registers of 8) and AVX-512 (32
// lanes, two registers of 16) on x86-64, where it picks the best one the CPU supports the first time it needs one, and
// for NEON (4 lanes) on aarch64. Every kernel gives bit for bit the result of the scalar code, which stays the
// reference and the fallback (other CPUs, and the cases the kernels hand back: docs/RUNTIME.md, "SIMD"). Choosing a set
// is for tests and benchmarks; the results do not depend on it.
#pragma once

#include "dng/status.h"

#include <cstdint>

namespace dng {

enum class InstructionSet : std::uint32_t {
  kScalar = 0, ///< one particle at a time: the reference
  kSse41 = 1,  ///< x86-64 SSE4.1, 4 lanes
  kAvx2 = 2,   ///< x86-64 AVX2, 16 lanes: two registers of 8 side by side
  kNeon = 3,   ///< aarch64 Advanced SIMD, 4 lanes
  kAvx512 = 4, ///< x86-64 AVX-512 (F, DQ, BW, VL), 32 lanes: two registers of 16 side by side
};

/// Every set there is, the scalar path first, the SIMD sets from the narrowest: for tests and tools that
/// try each one (setInstructionSet() tells which this build and CPU can run).
constexpr InstructionSet kInstructionSets[] = {InstructionSet::kScalar, InstructionSet::kSse41, InstructionSet::kNeon,
                                               InstructionSet::kAvx2, InstructionSet::kAvx512};

/// The widest set this build carries and this CPU supports.
InstructionSet bestInstructionSet();

/// The set in use now: bestInstructionSet() until setInstructionSet() chooses another.
InstructionSet activeInstructionSet();

/// Uses `set` for every later call in the process (thread-safe; calls already running finish with the
/// set they started with). Fails with kInvalidArgument, changing nothing, when this build or CPU lacks it.
Status setInstructionSet(InstructionSet set, Diagnostic* out_diag = nullptr);

/// "scalar", "sse4.1", "avx2", "neon" or "avx512".
const char* instructionSetName(InstructionSet set);

} // namespace dng
