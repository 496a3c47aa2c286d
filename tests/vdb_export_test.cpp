// --export-vdb: the grids OpenVDB reads back hold the same field, at the same world positions, as
// the .dng written by the same bake: the accurate distance, the conservative one and the normals.
#include "dng/file.h"
#include "stages.h"
#include "temp_dir.h"
#include "test_meshes.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <unistd.h>

namespace dng {
namespace baker {
namespace {

TEST(VdbExport, GridsMatchTheDngAtTheSameWorldPositions) {
  const testing::TempDir temp("vdb_export_test");
  const std::string dir = temp.path().string();
  testing::writeObj(testing::sphereMesh({0.2f, 0, 0}, 1.0f, 24, 12), dir + "/sphere.obj");
  BakeOptions options;
  options.mode = NormalMode::kExact;
  options.resolution = 40;
  BakeReport report;
  ASSERT_TRUE(
      bake(dir + "/sphere.obj", {dir + "/sphere.dng", dir + "/sphere.vdb"}, options, nullptr, nullptr, &report).ok());

  openvdb::initialize();
  openvdb::io::File file(dir + "/sphere.vdb");
  file.open();
  auto distance = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("distance"));
  auto normal = openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid("normal"));
  auto lowered = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("conservative_distance"));
  file.close();
  ASSERT_TRUE(distance && normal && lowered);
  EXPECT_EQ(distance->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(distance->voxelSize()[0], report.grid.voxel_size, 1e-7);
  EXPECT_EQ(distance->activeVoxelCount(), report.encode.band_voxels);

  File dng;
  ASSERT_EQ(File::open((dir + "/sphere.dng").c_str(), &dng), Status::kOk);
  const float h = report.grid.voxel_size;
  int compared = 0;
  for (auto it = distance->cbeginValueOn(); it; ++it) {
    const openvdb::Vec3d world = distance->indexToWorld(it.getCoord());
    const Vec3f p{float(world.x()), float(world.y()), float(world.z())};
    const Sample s = dng.view().sample(p);
    ASSERT_EQ(s.status, SampleStatus::kInBand);
    // "distance" is the accurate one (plane tiles keep up to their 0.02-voxel tolerance), and
    // "conservative_distance" what the nearest query reads.
    ASSERT_NEAR(*it, dng.view().sample(p, Interpolation::kAccurate).distance, 0.025f * h);
    ASSERT_NEAR(lowered->tree().getValue(it.getCoord()), s.distance, 0.01f * h);
    ASSERT_GE(*it, lowered->tree().getValue(it.getCoord()));
    const openvdb::Vec3s n = normal->tree().getValue(it.getCoord());
    ASSERT_LT(angleDegrees({n.x(), n.y(), n.z()}, s.normal), 0.5);
    ++compared;
  }
  EXPECT_GT(compared, 1000);
}

// A blurred bake exports its planes' normals, the exact bake's voxel for voxel (both come from the same
// distance stage), and its blurred ones beside them as "shading".
TEST(VdbExport, BlurredBakesAddTheShadingGrid) {
  const testing::TempDir temp("vdb_export_gradient_test");
  const std::string dir = temp.path().string();
  testing::writeObj(testing::boxMesh({0, 0, 0}, {0.8f, 0.5f, 0.3f}), dir + "/box.obj");
  const auto exported = [&](NormalMode mode, const char* grid_name) {
    BakeOptions options;
    options.mode = mode;
    options.resolution = 32;
    const std::string stem = dir + "/" + normalModeName(mode);
    EXPECT_TRUE(bake(dir + "/box.obj", {stem + ".dng", stem + ".vdb"}, options, nullptr, nullptr, nullptr).ok());
    openvdb::initialize();
    openvdb::io::File file(stem + ".vdb");
    file.open();
    auto grid = file.hasGrid(grid_name) ? openvdb::gridPtrCast<openvdb::Vec3SGrid>(file.readGrid(grid_name)) : nullptr;
    file.close();
    return grid;
  };
  EXPECT_EQ(exported(NormalMode::kExact, "shading"), nullptr);
  const auto exact = exported(NormalMode::kExact, "normal");
  const auto gradient = exported(NormalMode::kNormalBlur, "normal");
  const auto blurred = exported(NormalMode::kNormalBlur, "shading");
  ASSERT_TRUE(exact && gradient && blurred);
  int compared = 0, tilted = 0;
  for (auto it = exact->cbeginValueOn(); it; ++it) {
    const openvdb::Vec3s g = gradient->tree().getValue(it.getCoord());
    const openvdb::Vec3s b = blurred->tree().getValue(it.getCoord());
    ASSERT_EQ(g, *it);
    tilted += angleDegrees({b.x(), b.y(), b.z()}, {g.x(), g.y(), g.z()}) > 1.0 ? 1 : 0;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(tilted, 100) << "the blur tilts normals at the box's edges";
}

} // namespace
} // namespace baker
} // namespace dng
