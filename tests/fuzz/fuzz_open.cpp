// libFuzzer target for the loader: View::open and then every query, on mutated files.
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
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size); // operator new: 8-byte aligned, as open() needs
  dng::format::resealHashes(bytes);
  dng::View view;
  if (dng::View::open(bytes.data(), bytes.size(), &view) != dng::Status::kOk) return 0;
  (void)view.verifyHashes();
  const dng::GridInfo& g = view.grid();
  for (int n = 0; n < 64; ++n) { // a fixed lattice over the grid and a little beyond
    const float t[3] = {float(n % 4) / 3.0f, float((n / 4) % 4) / 3.0f, float(n / 16) / 3.0f};
    const dng::Vec3f p =
        g.origin +
        dng::Vec3f{t[0] * float(g.dims[0]), t[1] * float(g.dims[1]), t[2] * float(g.dims[2])} * (g.voxel_size * 1.1f);
    for (dng::Interpolation mode :
         {dng::Interpolation::kNearest, dng::Interpolation::kTrilinear, dng::Interpolation::kAccurate}) {
      const dng::Sample s = view.sample(p, mode);
      if (s.status != dng::SampleStatus::kNoField && !std::isfinite(s.distance)) std::abort();
      if (!std::isfinite(s.normal.x) || !std::isfinite(s.normal.y) || !std::isfinite(s.normal.z)) std::abort();
    }
  }
  return 0;
}
