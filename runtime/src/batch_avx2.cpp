// The batch kernels built for AVX2, 16 lanes in two registers (compiled with the matching -m flag:
// runtime/CMakeLists.txt). instruction_set.cpp calls them only on CPUs that support the set.
#define DNG_LANES_AVX2
#include "span_lanes.h"

namespace dng {

extern const BatchKernels kAvx2Kernels;
const BatchKernels kAvx2Kernels = lanes::avx2x2::kernelTable("avx2");

} // namespace dng
