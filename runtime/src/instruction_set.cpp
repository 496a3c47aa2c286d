// Choosing the batch kernels (dng/instruction_set.h): CPU detection once, then an atomic choice that
// tests and benchmarks may change.
#include "dng/instruction_set.h"
#include "diagnostic.h"
#include "step_batch.h"

#include <atomic>

namespace dng {

#if DNG_HAVE_X86_KERNELS
extern const BatchKernels kSse41Kernels;
extern const BatchKernels kAvx2Kernels;
extern const BatchKernels kAvx512Kernels;
#endif
#if DNG_HAVE_NEON_KERNELS
extern const BatchKernels kNeonKernels;
#endif

namespace {

bool supported(InstructionSet set) {
  switch (set) {
  case InstructionSet::kScalar: return true;
#if DNG_HAVE_X86_KERNELS
  case InstructionSet::kSse41: return __builtin_cpu_supports("sse4.1");
  case InstructionSet::kAvx2: return __builtin_cpu_supports("avx2");
  case InstructionSet::kAvx512: // the kernels' build flags; libgcc also checks that the OS saves the registers
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
#endif
#if DNG_HAVE_NEON_KERNELS
  case InstructionSet::kNeon: return true;
#endif
  default: return false;
  }
}

// -1 until the first call picks the best set.
std::atomic<int> g_active{-1};

} // namespace

InstructionSet bestInstructionSet() {
  for (InstructionSet set :
       {InstructionSet::kAvx512, InstructionSet::kAvx2, InstructionSet::kSse41, InstructionSet::kNeon}) {
    if (supported(set)) return set;
  }
  return InstructionSet::kScalar;
}

InstructionSet activeInstructionSet() {
  int active = g_active.load(std::memory_order_relaxed);
  if (active < 0) {
    active = int(bestInstructionSet());
    g_active.store(active, std::memory_order_relaxed);
  }
  return InstructionSet(active);
}

Status setInstructionSet(InstructionSet set, Diagnostic* out_diag) {
  if (!supported(set))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "instruction set %u is not available here",
                           unsigned(set));
  g_active.store(int(set), std::memory_order_relaxed);
  return Status::kOk;
}

const char* instructionSetName(InstructionSet set) {
  switch (set) {
  case InstructionSet::kScalar: return "scalar";
  case InstructionSet::kSse41: return "sse4.1";
  case InstructionSet::kAvx2: return "avx2";
  case InstructionSet::kNeon: return "neon";
  case InstructionSet::kAvx512: return "avx512";
  }
  return "unknown";
}

const BatchKernels* activeBatchKernels() {
  switch (activeInstructionSet()) {
#if DNG_HAVE_X86_KERNELS
  case InstructionSet::kSse41: return &kSse41Kernels;
  case InstructionSet::kAvx2: return &kAvx2Kernels;
  case InstructionSet::kAvx512: return &kAvx512Kernels;
#endif
#if DNG_HAVE_NEON_KERNELS
  case InstructionSet::kNeon: return &kNeonKernels;
#endif
  default: return nullptr;
  }
}

} // namespace dng
