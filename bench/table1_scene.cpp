#include "table1_scene.h"

#include "stages.h"

#include <unistd.h>

#include <filesystem>
#include <memory>

namespace dng {
namespace table1 {

namespace {

// Spawn lists are seeded per mesh size so that every method of one row sees the same particles.
constexpr std::uint32_t kSpawnSeed = 1;

// Bakes `path` in-process with the baker's public API and maps the result. The temporary file is
// removed at once: the mapping stays valid.
bool bakeField(const std::string& path, format::Encoding encoding, baker::NormalMode mode, File* out,
               baker::BakeReport* report, std::string* error) {
  baker::BakeOptions options;
  options.resolution = kResolution;
  options.encoding = encoding;
  options.mode = mode;
  // The step never reads the LIFT section (accurate queries do): a game that only steps particles bakes
  // with --no-lift, and the memory column is what the step needs.
  options.lift = false;
  const std::string dng = (std::filesystem::temp_directory_path() /
                           ("dng_table1_" + std::to_string(::getpid()) + "_" + std::to_string(int(encoding)) + "_" +
                            std::to_string(int(mode)) + ".dng"))
                              .string();
  const baker::BakeStatus status = baker::bake(path, {dng, {}}, options, nullptr, nullptr, report);
  if (!status.ok()) {
    *error = path + ": " + status.message;
    return false;
  }
  const Status opened = File::open(dng.c_str(), out);
  std::filesystem::remove(dng);
  if (opened != Status::kOk) {
    *error = path + ": cannot open the baked field: " + statusString(opened);
    return false;
  }
  return true;
}

bool buildScene(const std::string& path, MeshScene* scene, std::string* error) {
  baker::TriangleSoup soup;
  const baker::BakeStatus loaded = baker::loadMesh(path, &soup);
  if (!loaded.ok()) {
    *error = path + ": " + loaded.message;
    return false;
  }
  scene->name = std::filesystem::path(path).stem().string();
  scene->vertices = std::move(soup.vertices);
  scene->triangles = std::move(soup.triangles);
  baker::BakeReport report;
  if (!bakeField(path, format::Encoding::kBricked, baker::BakeOptions{}.mode, &scene->bricked, &report, error))
    return false;
  scene->outward = report.mesh.signed_volume < 0.0 ? -1.0f : 1.0f;
  const GridInfo& grid = scene->bricked.view().grid();
  scene->voxel = grid.voxel_size;
  if (!scene->judge.build(scene->vertices, scene->triangles) ||
      !scene->caster.build(scene->vertices, scene->triangles, scene->voxel)) {
    *error = path + ": Embree could not build the scene";
    return false;
  }
  scene->levelset = meshToNanoLevelSet(scene->vertices, scene->triangles, grid.origin, grid.voxel_size, grid.band);
  return true;
}

} // namespace

const Swarm& MeshScene::spawn(std::size_t count, bool proven) const {
  const std::pair<std::size_t, bool> key{count, proven};
  auto it = spawns_.find(key);
  if (it == spawns_.end()) {
    Body prover; // the field alone decides: a body with the default material and transform
    const bool asks = proven && Body::create(&bricked.view(), Material{}, &prover) == Status::kOk;
    it = spawns_
             .emplace(key, spawnNearSurface(vertices, triangles, judge, voxel, outward, count, kSpawnSeed,
                                            asks ? &prover : nullptr))
             .first;
  }
  return it->second;
}

const MeshScene* meshScene(const std::string& path, Extras extra, std::string* out_error) {
  static std::map<std::string, std::unique_ptr<MeshScene>> scenes;
  auto it = scenes.find(path);
  if (it == scenes.end()) {
    auto scene = std::make_unique<MeshScene>();
    if (!buildScene(path, scene.get(), out_error)) return nullptr;
    it = scenes.emplace(path, std::move(scene)).first;
  }
  MeshScene& scene = *it->second;
  baker::BakeReport report;
  if (extra.dense && !scene.dense.valid() &&
      !bakeField(path, format::Encoding::kDense, baker::BakeOptions{}.mode, &scene.dense, &report, out_error))
    return nullptr;
  if (extra.exact && !scene.exact.valid() &&
      !bakeField(path, format::Encoding::kBricked, baker::NormalMode::kExact, &scene.exact, &report, out_error))
    return nullptr;
  if (extra.embree_avx2 && !scene.caster_avx2.built() &&
      !scene.caster_avx2.build(scene.vertices, scene.triangles, scene.voxel, "max_isa=avx2")) {
    *out_error = path + ": Embree could not build the scene on an AVX2 device";
    return nullptr;
  }
  return &scene;
}

} // namespace table1
} // namespace dng
