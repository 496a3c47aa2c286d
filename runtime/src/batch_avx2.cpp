// The batch kernels built for AVX2, 8 lanes (compiled with the matching -m flag: runtime/CMakeLists.txt).
// instruction_set.cpp calls them only on CPUs that support the set.
#define DNG_LANES_AVX2
#include "step_lanes.h"

namespace dng {

namespace {

void sampleNearest(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    lanes::avx2::sampleNearestBatch<true>(view, points, stride, count, out);
  else
    lanes::avx2::sampleNearestBatch<false>(view, points, stride, count, out);
}

} // namespace

extern const BatchKernels kAvx2Kernels;
const BatchKernels kAvx2Kernels = {"avx2", &sampleNearest, &lanes::avx2::stepLanes};

} // namespace dng
