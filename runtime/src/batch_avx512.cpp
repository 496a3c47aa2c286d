// The batch kernels built for AVX-512 (F, DQ, BW, VL), 32 lanes in two registers (compiled with the matching -m flags:
// runtime/CMakeLists.txt). instruction_set.cpp calls them only on CPUs that support the set.
#define DNG_LANES_AVX512
#include "span_lanes.h"

namespace dng {

extern const BatchKernels kAvx512Kernels;
const BatchKernels kAvx512Kernels = lanes::avx512::kernelTable("avx512");

} // namespace dng
