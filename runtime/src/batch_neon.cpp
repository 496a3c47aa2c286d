// The batch kernels built for aarch64 Advanced SIMD (NEON), 4 lanes. Every aarch64 CPU has it, so
// instruction_set.cpp needs no detection for this set.
#define DNG_LANES_NEON
#include "span_lanes.h"

namespace dng {

extern const BatchKernels kNeonKernels;
const BatchKernels kNeonKernels = {"neon",
                                   &lanes::neon::sampleNearestBatch,
                                   &lanes::neon::sampleTrilinearBatch,
                                   &lanes::neon::sampleAccurateBatch,
                                   &lanes::neon::stepLanes,
                                   &lanes::neon::neighbourBound};

} // namespace dng
