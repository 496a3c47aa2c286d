// The batch kernels built for SSE4.1, 4 lanes (compiled with the matching -m flag: runtime/CMakeLists.txt).
// instruction_set.cpp calls them only on CPUs that support the set.
#define DNG_LANES_SSE41
#include "span_lanes.h"

namespace dng {

extern const BatchKernels kSse41Kernels;
const BatchKernels kSse41Kernels = lanes::sse41::kernelTable("sse4.1");

} // namespace dng
