// The batch kernels built for aarch64 Advanced SIMD (NEON), 4 lanes. Every aarch64 CPU has it, so
// instruction_set.cpp needs no detection for this set.
#define DNG_LANES_NEON
#include "step_lanes.h"

namespace dng {

namespace {

void sampleNearest(const View& view, const float* points, std::size_t stride, std::size_t count, Sample* out) {
  if (view.grid().encoding == format::Encoding::kDense)
    lanes::neon::sampleNearestBatch<true>(view, points, stride, count, out);
  else
    lanes::neon::sampleNearestBatch<false>(view, points, stride, count, out);
}

} // namespace

extern const BatchKernels kNeonKernels;
const BatchKernels kNeonKernels = {"neon", &sampleNearest, &lanes::neon::stepLanes};

} // namespace dng
