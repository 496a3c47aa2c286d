// libFuzzer target for the loader: View::open and then every query, one at a time and batched (the
// SIMD kernels, which must give the same bits), on mutated files.
//
// Hashes are resealed after each mutation (as a file damaged after writing but before hashing would
// look), so the fuzzer gets past the header and table hashes into every validation rule (V7-V16) and
// into the queries on whatever opens. Seed corpus: tests/golden/*.dng. Any crash, ASan or UBSan
// report is a bug: open() must refuse bad files cleanly and queries must be total on good ones.
#include "dng/format/writer.h"
#include "dng/view.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size); // operator new: 8-byte aligned, as open() needs
  dng::format::resealHashes(bytes);
  dng::View view;
  if (dng::View::open(bytes.data(), bytes.size(), &view) != dng::Status::kOk) return 0;
  (void)view.verifyHashes();
  const dng::GridInfo& g = view.grid();
  constexpr int kPoints = 64;
  std::vector<dng::Vec3f> points;
  for (int n = 0; n < kPoints; ++n) { // a fixed lattice over the grid and a little beyond
    const float t[3] = {float(n % 4) / 3.0f, float((n / 4) % 4) / 3.0f, float(n / 16) / 3.0f};
    points.push_back(g.origin + dng::Vec3f{t[0] * float(g.dims[0]), t[1] * float(g.dims[1]), t[2] * float(g.dims[2])} *
                                    (g.voxel_size * 1.1f));
  }
  for (dng::Interpolation mode :
       {dng::Interpolation::kNearest, dng::Interpolation::kTrilinear, dng::Interpolation::kAccurate}) {
    // The batch runs the SIMD kernels where the CPU has them: the same bits as one query at a time.
    std::vector<dng::Sample> batch(kPoints);
    view.sampleBatch(&points[0].x, sizeof(dng::Vec3f), kPoints, batch.data(), mode);
    for (int n = 0; n < kPoints; ++n) {
      const dng::Sample s = view.sample(points[std::size_t(n)], mode);
      if (s.status != dng::SampleStatus::kNoField && !std::isfinite(s.distance)) std::abort();
      if (!std::isfinite(s.normal.x) || !std::isfinite(s.normal.y) || !std::isfinite(s.normal.z)) std::abort();
      const dng::Sample& b = batch[std::size_t(n)];
      if (b.status != s.status || std::memcmp(&b.distance, &s.distance, sizeof s.distance) != 0 ||
          std::memcmp(&b.normal, &s.normal, sizeof s.normal) != 0)
        std::abort();
    }
  }
  return 0;
}
