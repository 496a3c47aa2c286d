// Query cost per point on a 128^3 sphere field: dense vs bricked, nearest vs trilinear, coherent vs
// random point order. Baselines measured in the same run on the same points: a bare array of float4
// (the paper's plain "normal grid": one load, no refinement, no checks) and, when installed, NanoVDB's
// ReadAccessor (distance + 3 forward differences for the normal, as a level-set user would).
//
// Every benchmark reports per_query (seconds); bench/run.sh turns them into ratios in docs/PERFORMANCE.md.
#include "bench_main.h"
#include "dng/instruction_set.h"
#include "sphere_scene.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

#ifdef DNG_HAVE_NANOVDB
#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridBuilder.h>
#endif

namespace {

using namespace dng;

using bench::kBandVoxels;
using bench::kGridSize;

struct Data {
  const format::DenseField& field = bench::sphereScene().field;
  const View& dense = bench::sphereScene().dense;
  const View& bricked = bench::sphereScene().bricked;
  // The same field with LIFT and SHAD sections, as dngbake writes a blurred mode's bake (format 1.3):
  // what the accurate query reads (LIFT), and the shading normals the nearest and trilinear queries read
  // (here the lifts are zero and the shading normals the normals; the reads are real).
  std::vector<std::uint8_t> dense_extra_bytes, bricked_extra_bytes;
  View dense_extra, bricked_extra;
  std::vector<Vec3f> coherent, random;
  std::vector<float> raw; // float4 per voxel
#ifdef DNG_HAVE_NANOVDB
  nanovdb::GridHandle<nanovdb::HostBuffer> nano;
#endif
};

// Near-surface points: one jittered point per in-band voxel, in scan order (coherent), and the same
// points shuffled (random).
void makePoints(Data& d) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
  const format::GridGeometry& g = d.field.grid;
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        if (std::fabs(d.field.distance[g.index(i, j, k)]) >= 2.0f) continue;
        d.coherent.push_back(g.origin + Vec3f{float(i) + jitter(rng), float(j) + jitter(rng), float(k) + jitter(rng)} *
                                            g.voxel_size);
      }
  d.random = d.coherent;
  std::shuffle(d.random.begin(), d.random.end(), rng);
}

const Data& data() {
  static const Data* instance = [] {
    auto* d = new Data;
    format::DenseField extra = d->field;
    extra.accurate = extra.distance;
    extra.shading = extra.normal;
    d->dense_extra_bytes = format::encodeDense(extra, "").bytes;
    d->bricked_extra_bytes = format::encodeBricked(extra, {}, "").bytes;
    View::open(d->dense_extra_bytes.data(), d->dense_extra_bytes.size(), &d->dense_extra);
    View::open(d->bricked_extra_bytes.data(), d->bricked_extra_bytes.size(), &d->bricked_extra);
    for (std::size_t v = 0; v < d->field.distance.size(); ++v) {
      const Vec3f n = d->field.normal[v];
      d->raw.insert(d->raw.end(), {d->field.distance[v], n.x, n.y, n.z});
    }
#ifdef DNG_HAVE_NANOVDB
    nanovdb::GridBuilder<float> builder(kBandVoxels, nanovdb::GridClass::LevelSet);
    auto acc = builder.getAccessor();
    const format::GridGeometry& g = d->field.grid;
    for (std::uint32_t k = 0; k < g.dims[2]; ++k)
      for (std::uint32_t j = 0; j < g.dims[1]; ++j)
        for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
          const float dist = d->field.distance[g.index(i, j, k)];
          if (std::fabs(dist) < kBandVoxels) acc.setValue(nanovdb::Coord(int(i), int(j), int(k)), dist);
        }
    d->nano = builder.getHandle<>(1.0, nanovdb::Vec3d(g.origin.x, g.origin.y, g.origin.z));
#endif
    makePoints(*d);
    return d;
  }();
  return *instance;
}

void reportPerQuery(benchmark::State& state, std::size_t count) {
  // Seconds per query (the console prints it with an SI prefix, e.g. "8.9n").
  state.counters["per_query"] =
      benchmark::Counter(double(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Arguments: encoding (0 dense, 1 bricked), query (0 nearest, 1 trilinear; on the field with LIFT and SHAD
// sections: 2 accurate, 3 nearest, 4 trilinear), order (0 coherent, 1 random),
// path (0 the best SIMD kernels of this CPU, 1 the scalar reference, whose samples are bit for bit the same).
void BM_Sample(benchmark::State& state) {
  const Data& d = data();
  const InstructionSet before = activeInstructionSet();
  setInstructionSet(state.range(3) == 0 ? bestInstructionSet() : InstructionSet::kScalar);
  const auto query = int(state.range(1));
  const bool extra = query >= 2;
  const auto mode = Interpolation(query >= 3 ? query - 3 : query);
  const View& view = state.range(0) == 0 ? (extra ? d.dense_extra : d.dense) : (extra ? d.bricked_extra : d.bricked);
  const std::vector<Vec3f>& points = state.range(2) == 0 ? d.coherent : d.random;
  std::vector<Sample> out(points.size());
  for (auto _ : state) {
    view.sampleBatch(&points[0].x, sizeof(Vec3f), points.size(), out.data(), mode);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  setInstructionSet(before);
  static const char* const kModes[] = {" nearest", " trilinear", " accurate", " nearest+SHAD", " trilinear+SHAD"};
  state.SetLabel(std::string(state.range(0) ? "bricked" : "dense") + kModes[state.range(1)] +
                 (state.range(2) ? " random" : " coherent") + (state.range(3) ? " scalar" : " simd"));
  reportPerQuery(state, points.size());
}
BENCHMARK(BM_Sample)->ArgsProduct({{0, 1}, {0, 1, 2, 3, 4}, {0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);

// Baseline: the voxel's float4 from a bare array, bounds-checked, no refinement.
void BM_RawArray(benchmark::State& state) {
  const Data& d = data();
  const std::vector<Vec3f>& points = state.range(0) == 0 ? d.coherent : d.random;
  const format::GridGeometry& g = d.field.grid;
  std::vector<Sample> out(points.size());
  for (auto _ : state) {
    for (std::size_t n = 0; n < points.size(); ++n) {
      const Vec3f u = (points[n] - g.origin) * (1.0f / g.voxel_size);
      if (!(u.x >= 0 && u.y >= 0 && u.z >= 0 && u.x < kGridSize && u.y < kGridSize && u.z < kGridSize)) {
        out[n] = Sample{};
        continue;
      }
      const float* v = &d.raw[4 * g.index(std::uint32_t(u.x), std::uint32_t(u.y), std::uint32_t(u.z))];
      out[n] = {v[0], {v[1], v[2], v[3]}, SampleStatus::kInBand};
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(state.range(0) ? "raw array random" : "raw array coherent");
  reportPerQuery(state, points.size());
}
BENCHMARK(BM_RawArray)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

#ifdef DNG_HAVE_NANOVDB
// Baseline: NanoVDB level set, distance plus a forward-difference gradient for the normal.
void BM_NanoVdb(benchmark::State& state) {
  const Data& d = data();
  const std::vector<Vec3f>& points = state.range(0) == 0 ? d.coherent : d.random;
  const auto* grid = d.nano.grid<float>();
  std::vector<Sample> out(points.size());
  for (auto _ : state) {
    auto acc = grid->getAccessor(); // one accessor per batch, as a particle loop would
    for (std::size_t n = 0; n < points.size(); ++n) {
      const auto ijk = grid->worldToIndexF(nanovdb::Vec3f(points[n].x, points[n].y, points[n].z)).floor();
      const float v = acc.getValue(ijk);
      const float gx = acc.getValue(ijk.offsetBy(1, 0, 0)) - v;
      const float gy = acc.getValue(ijk.offsetBy(0, 1, 0)) - v;
      const float gz = acc.getValue(ijk.offsetBy(0, 0, 1)) - v;
      const float inv = 1.0f / std::sqrt(gx * gx + gy * gy + gz * gz + 1e-20f);
      out[n] = {v, {gx * inv, gy * inv, gz * inv}, SampleStatus::kInBand};
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(state.range(0) ? "nanovdb random" : "nanovdb coherent");
  reportPerQuery(state, points.size());
}
BENCHMARK(BM_NanoVdb)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
#endif

} // namespace

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "field_query_bench"); }
