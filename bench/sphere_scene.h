// The benchmarks' shared scene: a 128^3 sphere field (radius 48 voxels, band 3 voxels) in both
// encodings, built once per process.
#pragma once

#include "analytic_fields.h"
#include "dng/format/writer.h"
#include "dng/view.h"

namespace dng {
namespace bench {

constexpr std::uint32_t kGridSize = 128;
constexpr float kBandVoxels = 3.0f;
constexpr float kRadius = kGridSize / 2.0f * 0.75f;

struct SphereScene {
  format::DenseField field;
  std::vector<std::uint8_t> dense_bytes, bricked_bytes;
  View dense, bricked;
};

inline const SphereScene& sphereScene() {
  static const SphereScene* scene = [] {
    auto* s = new SphereScene;
    const float half = kGridSize / 2.0f;
    s->field = analytic::sampleField(analytic::cubeGrid({-half, -half, -half}, 1.0f, kGridSize, kBandVoxels),
                                     analytic::sphereField({0.3f, 0.2f, 0.1f}, kRadius));
    s->dense_bytes = format::encodeDense(s->field, "").bytes;
    s->bricked_bytes = format::encodeBricked(s->field, {}, "").bytes;
    View::open(s->dense_bytes.data(), s->dense_bytes.size(), &s->dense);
    View::open(s->bricked_bytes.data(), s->bricked_bytes.size(), &s->bricked);
    return s;
  }();
  return *scene;
}

} // namespace bench
} // namespace dng
