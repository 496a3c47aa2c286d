// Bake time against OpenVDB's meshToLevelSet alone, same mesh, same voxel size, same band, one run
// (issue #4's goal: the Stanford bunny at resolution 128 in <= 1.5 s on 2 cores and <= 2x
// meshToLevelSet; the paper needed one to two minutes for 50^3), and at 512 to show how it scales. The mesh path comes
// from DNG_BENCH_MESH (bench/run.sh fetches Debian's bunny00.off).
#include "bench_main.h"
#include "stages.h"

#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <cstdlib>
#include <filesystem>

namespace {

using namespace dng::baker;

const char* meshPath() {
  const char* path = std::getenv("DNG_BENCH_MESH");
  return path != nullptr ? path : "data/data/meshes/bunny00.off";
}

void BM_Dngbake(benchmark::State& state) {
  BakeOptions options;
  options.mode = NormalMode(state.range(0));
  options.resolution = std::uint32_t(state.range(1));
  const std::string out = (std::filesystem::temp_directory_path() / "dng_bake_bench.dng").string();
  for (auto _ : state) {
    BakeReport report;
    const BakeStatus status = bake(meshPath(), {out, {}}, options, nullptr, nullptr, &report);
    if (!status.ok()) {
      state.SkipWithError(status.message.c_str());
      return;
    }
  }
  state.SetLabel(std::string("dngbake ") + normalModeName(options.mode) + " @" + std::to_string(options.resolution));
}
BENCHMARK(BM_Dngbake)
    ->Args({int(NormalMode::kExact), 128})
    ->Args({int(NormalMode::kNormalBlur), 128})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
// How the sparse store scales: 64x the voxels of @128 (two repetitions only: each takes seconds).
BENCHMARK(BM_Dngbake)
    ->Args({int(NormalMode::kNormalBlur), 512})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1)
    ->Repetitions(2);

// The baseline gets the mesh already loaded and the same grid the baker placed: only the volume build.
void BM_MeshToLevelSet(benchmark::State& state) {
  TriangleSoup soup;
  if (!loadMesh(meshPath(), &soup).ok()) {
    state.SkipWithError("cannot load the mesh");
    return;
  }
  BakeOptions options;
  options.resolution = std::uint32_t(state.range(0));
  dng::format::GridGeometry grid;
  std::vector<std::string> warnings;
  (void)placeGrid(checkMesh(soup), options, &grid, &warnings);
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  for (const dng::Vec3f& v : soup.vertices)
    points.emplace_back(v.x, v.y, v.z);
  std::vector<openvdb::Vec3I> triangles;
  for (const auto& t : soup.triangles)
    triangles.emplace_back(t[0], t[1], t[2]);
  const auto transform = openvdb::math::Transform::createLinearTransform(double(grid.voxel_size));
  for (auto _ : state) {
    auto volume =
        openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, grid.band / grid.voxel_size);
    benchmark::DoNotOptimize(volume.get());
  }
  state.SetLabel("OpenVDB meshToLevelSet @" + std::to_string(options.resolution) + ", same voxel size and band");
}
BENCHMARK(BM_MeshToLevelSet)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_MeshToLevelSet)->Arg(512)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(2);

} // namespace

int main(int argc, char** argv) { return dng::bench::runBenchmarks(argc, argv, "bake_bench"); }
