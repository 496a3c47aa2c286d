// The batch kernels built for aarch64 Advanced SIMD (NEON), 4 lanes. Every aarch64 CPU has it, so
// instruction_set.cpp needs no detection for this set.
#define DNG_LANES_NEON
#include "span_lanes.h"

namespace dng {

extern const BatchKernels kNeonKernels;
const BatchKernels kNeonKernels = lanes::neon::kernelTable("neon");

} // namespace dng
