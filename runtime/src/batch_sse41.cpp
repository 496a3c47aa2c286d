// The batch kernels built for SSE4.1, 4 lanes (compiled with the matching -m flag: runtime/CMakeLists.txt).
// instruction_set.cpp calls them only on CPUs that support the set.
#define DNG_LANES_SSE41
#include "step_lanes.h"

namespace dng {

namespace {

void sampleNearest(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    lanes::sse41::sampleNearestBatch<true>(view, points, stride, count, out);
  else
    lanes::sse41::sampleNearestBatch<false>(view, points, stride, count, out);
}

} // namespace

extern const BatchKernels kSse41Kernels;
const BatchKernels kSse41Kernels = {"sse4.1", &sampleNearest, &lanes::sse41::stepLanes};

} // namespace dng
