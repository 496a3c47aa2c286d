// Scene importers: glTF files written here (gltf_files.h) with a node hierarchy of rotations and
// scales, a mesh instanced twice, a primitive of lines and a binary .glb bake to the same field as the
// same triangles written as OFF with the transforms applied by independent code; --node, --scene,
// several inputs, units, an assimp format, and every kind of bad input with its exit code.
#include "dng/file.h"
#include "gltf_files.h"
#include "run_program.h"
#include "stages.h"
#include "temp_dir.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

namespace dng {
namespace {

using namespace baker;
using testing::GltfFile;
using testing::GltfNode;
using testing::GltfPrimitive;
using testing::GltfScene;
using testing::GltfStorage;

// ---- The expected geometry, by Rodrigues rotations rather than matrices ----

struct Trs {
  Vec3f translation;
  Vec3f axis{0, 0, 1};
  double degrees = 0.0;
  Vec3f scale{1, 1, 1};
};

Vec3f rotate(Vec3f v, Vec3f axis, double degrees) {
  const double a = degrees * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
  const double n = std::sqrt(double(dot(axis, axis)));
  const double k[3] = {axis.x / n, axis.y / n, axis.z / n}, p[3] = {v.x, v.y, v.z};
  const double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
  const double cross[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
  double r[3];
  for (int i = 0; i < 3; ++i)
    r[i] = p[i] * c + cross[i] * s + k[i] * kp * (1 - c);
  return {float(r[0]), float(r[1]), float(r[2])};
}

// Applies the chain innermost first: the node's own TRS, then its parent's, up to the root.
Vec3f place(Vec3f v, const std::vector<Trs>& root_to_node) {
  for (auto it = root_to_node.rbegin(); it != root_to_node.rend(); ++it) {
    v = {v.x * it->scale.x, v.y * it->scale.y, v.z * it->scale.z};
    v = rotate(v, it->axis, it->degrees) + it->translation;
  }
  return v;
}

std::vector<double> quaternion(Vec3f axis, double degrees) { // glTF order: x, y, z, w
  const double half = degrees * M_PI / 360.0, n = std::sqrt(double(dot(axis, axis)));
  return {axis.x / n * std::sin(half), axis.y / n * std::sin(half), axis.z / n * std::sin(half), std::cos(half)};
}

// Column-major matrix of translation * rotation (uniform scale 1), as glTF's "matrix".
std::vector<double> matrixOf(const Trs& t) {
  std::vector<double> m(16, 0.0);
  const Vec3f columns[3] = {rotate({1, 0, 0}, t.axis, t.degrees), rotate({0, 1, 0}, t.axis, t.degrees),
                            rotate({0, 0, 1}, t.axis, t.degrees)};
  for (int c = 0; c < 3; ++c) {
    m[std::size_t(c * 4 + 0)] = columns[c].x;
    m[std::size_t(c * 4 + 1)] = columns[c].y;
    m[std::size_t(c * 4 + 2)] = columns[c].z;
  }
  m[12] = t.translation.x, m[13] = t.translation.y, m[14] = t.translation.z, m[15] = 1.0;
  return m;
}

const Trs kRoot{{0.25f, 0, 0}, {0, 0, 1}, 30.0, {1.5f, 1.5f, 1.5f}};
const Trs kLeft{{-1.2f, 0, 0}, {1, 0, 0}, 45.0, {1.0f, 0.6f, 1.3f}};
const Trs kRight{{1.2f, 0.1f, 0.3f}, {0, 1, 0}, 90.0, {1, 1, 1}};
const Trs kOther{{0, 0, 2}, {1, 1, 0}, 20.0, {0.8f, 0.8f, 0.8f}};

GltfNode trsNode(const std::string& name, int mesh, const Trs& t) {
  GltfNode n;
  n.name = name;
  n.mesh = mesh;
  n.translation = {t.translation.x, t.translation.y, t.translation.z};
  n.rotation = quaternion(t.axis, t.degrees);
  n.scale = {t.scale.x, t.scale.y, t.scale.z};
  return n;
}

// Scene 0: root (T R S) -> left (T R S, non-uniform) and right (a matrix), both instancing mesh 0, a
// cube plus a primitive of lines. Scene 1: one node "other" with the same mesh.
GltfScene twoCubes() {
  const testing::Mesh cube = testing::boxMesh({0, 0, 0}, {0.5f, 0.5f, 0.5f});
  GltfPrimitive triangles{cube.vertices, {}, 5121, 4};
  for (const auto& t : cube.triangles)
    triangles.indices.insert(triangles.indices.end(), t.begin(), t.end());
  const GltfPrimitive lines{{{0, 0, 0}, {5, 5, 5}}, {}, 5123, 1};
  GltfScene scene;
  scene.meshes = {{triangles, lines}};
  GltfNode root = trsNode("root", -1, kRoot);
  root.children = {1, 2};
  GltfNode right;
  right.name = "right";
  right.mesh = 0;
  right.matrix = matrixOf(kRight);
  scene.nodes = {root, trsNode("left", 0, kLeft), right, trsNode("other", 0, kOther)};
  scene.scenes = {{0}, {3}};
  return scene;
}

// The cube's triangles placed by each chain, as one soup.
testing::Mesh placedCubes(const std::vector<std::vector<Trs>>& chains) {
  const testing::Mesh cube = testing::boxMesh({0, 0, 0}, {0.5f, 0.5f, 0.5f});
  testing::Mesh out;
  for (const auto& chain : chains) {
    const auto base = std::uint32_t(out.vertices.size());
    for (const Vec3f& v : cube.vertices)
      out.vertices.push_back(place(v, chain));
    for (const auto& t : cube.triangles)
      out.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  return out;
}

class ImportTest : public ::testing::Test {
protected:
  ImportTest() : dir_(::testing::UnitTest::GetInstance()->current_test_info()->name()) {}
  std::string path(const std::string& name) const { return dir_.file(name); }

  static BakeOptions options() {
    BakeOptions o;
    o.mode = NormalMode::kExact;
    o.resolution = 40;
    o.encoding = format::Encoding::kDense; // bricks round within a tolerance; dense keeps every distance
    return o;
  }

  // Bakes `inputs` to `name`.dng; the file stays open for the test.
  File bakeFiles(BakeInputs inputs, const std::string& name, BakeReport* out_report = nullptr) {
    BakeReport report;
    const BakeStatus status = bake(inputs, {path(name + ".dng"), {}}, options(), nullptr, nullptr, &report);
    EXPECT_TRUE(status.ok()) << status.message;
    if (out_report != nullptr) *out_report = report;
    File file;
    EXPECT_EQ(File::open(path(name + ".dng").c_str(), &file), Status::kOk);
    return file;
  }
  File bakeFile(const std::string& input, const std::string& name, BakeReport* out_report = nullptr) {
    BakeInputs inputs;
    inputs.paths = {input};
    return bakeFiles(inputs, name, out_report);
  }
  File bakeOff(const testing::Mesh& mesh, const std::string& name) {
    testing::writeOff(mesh.vertices, mesh.triangles, path(name + ".off"));
    return bakeFile(path(name + ".off"), name);
  }

  testing::TempDir dir_;
};

// Same grid, and every voxel centre answers the same within a twentieth of a voxel. Exact distances
// agree to float rounding, but the baker's conservative lowering of planes (a few hundredths of a voxel)
// may go one way or the other on vertices one rounding apart; a wrong transform moves the surface by
// whole voxels.
void expectSameField(const View& a, const View& b) {
  const GridInfo& g = a.grid();
  ASSERT_EQ(g.dims[0], b.grid().dims[0]);
  ASSERT_EQ(g.dims[1], b.grid().dims[1]);
  ASSERT_EQ(g.dims[2], b.grid().dims[2]);
  ASSERT_NEAR(g.voxel_size, b.grid().voxel_size, 1e-6f * g.voxel_size);
  ASSERT_NEAR(g.origin.x, b.grid().origin.x, 1e-4f * g.voxel_size);
  std::size_t differing = 0, in_band = 0;
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        const Vec3f p = g.origin + Vec3f{float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f} * g.voxel_size;
        const Sample sa = a.sample(p), sb = b.sample(p);
        in_band += sa.status == SampleStatus::kInBand;
        const bool differ = sa.status != sb.status || std::abs(sa.distance - sb.distance) > 0.05f * g.voxel_size;
        if (differ && differing < 5)
          ADD_FAILURE() << "voxel " << i << ' ' << j << ' ' << k << ": status " << int(sa.status) << " vs "
                        << int(sb.status) << ", distance " << sa.distance << " vs " << sb.distance;
        differing += differ;
      }
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(in_band, 1000u); // the comparison saw the surface
}

TEST_F(ImportTest, HierarchyInstancesAndAllThreeStoragesBakeLikeTheOffFile) {
  const File reference = bakeOff(placedCubes({{kRoot, kLeft}, {kRoot, kRight}}), "reference");
  const GltfFile gltf = testing::buildGltf(twoCubes());
  saveGltf(gltf, path("external.gltf"), GltfStorage::kExternalBin);
  saveGltf(gltf, path("embedded.gltf"), GltfStorage::kEmbedded);
  saveGltf(gltf, path("binary.glb"), GltfStorage::kBinaryGlb);
  for (const char* name : {"external.gltf", "embedded.gltf", "binary.glb"}) {
    SCOPED_TRACE(name);
    BakeReport report;
    const File baked = bakeFile(path(name), std::string(name) + "_out", &report);
    expectSameField(reference.view(), baked.view());
    ASSERT_EQ(report.inputs.size(), 1u);
    const ImportReport& in = report.inputs[0];
    EXPECT_EQ(in.importer, "tinygltf");
    EXPECT_EQ(in.units, LengthUnit::kMetre);
    EXPECT_EQ(in.triangles, 24u);
    EXPECT_EQ(in.skipped_primitives, 2u); // the lines, once per instance
    ASSERT_EQ(in.nodes.size(), 2u);
    EXPECT_EQ(in.nodes[0].name, "left");
    EXPECT_EQ(in.nodes[1].name, "right");
    EXPECT_EQ(in.nodes[1].triangles, 12u);
    EXPECT_NEAR(in.nodes[1].transform[12], 0.25 + 1.5 * (1.2 * std::cos(M_PI / 6) - 0.1 * std::sin(M_PI / 6)), 1e-6);
    ASSERT_FALSE(in.messages.empty());
    EXPECT_NE(in.messages[0].find("lines skipped"), std::string::npos) << in.messages[0];
    const std::string meta(baked.view().metadata());
    EXPECT_NE(meta.find("\"units\":{\"field\":\"m\"}"), std::string::npos) << meta;
    EXPECT_NE(meta.find("\"nodes\":[\"left\",\"right\"]"), std::string::npos) << meta;
  }
}

TEST_F(ImportTest, NodeAndSceneChooseWhatIsBaked) {
  saveGltf(testing::buildGltf(twoCubes()), path("cubes.gltf"), GltfStorage::kExternalBin);
  BakeInputs only_right;
  only_right.paths = {path("cubes.gltf")};
  only_right.import.nodes = {"right"};
  expectSameField(bakeOff(placedCubes({{kRoot, kRight}}), "right_ref").view(), bakeFiles(only_right, "right").view());
  BakeInputs scene1;
  scene1.paths = {path("cubes.gltf")};
  scene1.import.scene = 1;
  expectSameField(bakeOff(placedCubes({{kOther}}), "other_ref").view(), bakeFiles(scene1, "other").view());
}

TEST_F(ImportTest, SeveralInputsBakeTheirUnionAndUnitsConvert) {
  saveGltf(testing::buildGltf(twoCubes()), path("cubes.glb"), GltfStorage::kBinaryGlb);
  // A third cube in an OFF file "in centimetres": --units m converts it, glTF is metres already.
  testing::Mesh third = placedCubes({{Trs{{0, 3, 0}, {0, 0, 1}, 0.0, {1, 1, 1}}}});
  testing::Mesh third_cm = third;
  for (Vec3f& v : third_cm.vertices)
    v = v * 100.0f;
  testing::writeOff(third_cm.vertices, third_cm.triangles, path("third_cm.off"));
  BakeInputs inputs;
  inputs.paths = {path("cubes.glb"), path("third_cm.off")};
  inputs.units.field = LengthUnit::kMetre;
  inputs.units.assumed = LengthUnit::kCentimetre;
  BakeReport report;
  const File both = bakeFiles(inputs, "both", &report);
  testing::Mesh all = placedCubes({{kRoot, kLeft}, {kRoot, kRight}});
  const auto base = std::uint32_t(all.vertices.size());
  all.vertices.insert(all.vertices.end(), third.vertices.begin(), third.vertices.end());
  for (const auto& t : third.triangles)
    all.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  expectSameField(bakeOff(all, "all_ref").view(), both.view());
  ASSERT_EQ(report.inputs.size(), 2u);
  EXPECT_EQ(report.inputs[1].importer, "openmesh");
  EXPECT_DOUBLE_EQ(report.inputs[1].scale, 0.01);
  EXPECT_EQ(report.units, LengthUnit::kMetre);
}

TEST_F(ImportTest, ScaleAndUnitsAreRecordedInTheMetadata) {
  saveGltf(testing::buildGltf(twoCubes()), path("cubes.gltf"), GltfStorage::kEmbedded);
  BakeInputs inputs;
  inputs.paths = {path("cubes.gltf")};
  inputs.units.field = LengthUnit::kCentimetre;
  inputs.units.scale = 2.0;
  BakeReport metres, report;
  bakeFile(path("cubes.gltf"), "m", &metres);
  const File file = bakeFiles(inputs, "cm", &report);
  EXPECT_NEAR(report.mesh.bounds_max.x, 200.0f * metres.mesh.bounds_max.x, 1e-3f); // metres -> cm, x2
  EXPECT_NEAR(report.mesh.bounds_min.z, 200.0f * metres.mesh.bounds_min.z, 1e-3f);
  const std::string meta(file.view().metadata());
  EXPECT_NE(meta.find("\"units\":{\"field\":\"cm\"}"), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"units\":\"m\",\"scale\":200.0"), std::string::npos) << meta;
}

TEST_F(ImportTest, StripsFansIndexTypesAndMirrorsKeepTheWinding) {
  // A unit square as a strip and as a fan, each wound +z; then the same under a mirroring scale, whose
  // determinant is negative: without reversing the winding the mirrored copy would face -z.
  GltfScene scene;
  const GltfPrimitive strip{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {}, 5123, 5};
  const GltfPrimitive fan{{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 2, 3}, 5125, 6};
  scene.meshes = {{strip, fan}};
  GltfNode plain;
  plain.name = "plain";
  plain.mesh = 0;
  GltfNode mirrored = plain;
  mirrored.name = "mirrored";
  mirrored.scale = {-1, 1, 1};
  scene.nodes = {plain, mirrored};
  scene.scenes = {{0, 1}};
  saveGltf(testing::buildGltf(scene), path("flat.gltf"), GltfStorage::kExternalBin);
  TriangleSoup soup;
  std::vector<ImportReport> reports;
  std::vector<std::string> warnings;
  ASSERT_TRUE(importInputs({path("flat.gltf")}, {}, {}, &soup, &reports, &warnings).ok());
  ASSERT_EQ(soup.triangles.size(), 8u);
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    const auto& tri = soup.triangles[t];
    const Vec3f n = cross(soup.vertices[tri[1]] - soup.vertices[tri[0]], soup.vertices[tri[2]] - soup.vertices[tri[0]]);
    EXPECT_GT(n.z, 0.0f) << "triangle " << t; // mirrored in x, flipped back: a mirrored +z face still faces +z
  }
}

// KHR_mesh_quantization: positions as normalized shorts, scaled back by the node (as exporters do).
TEST_F(ImportTest, QuantizedPositionsAreReadAsTheSpecSays) {
  GltfScene scene;
  scene.meshes = {{GltfPrimitive{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, 5123, 4}}};
  GltfNode node;
  node.name = "quantized";
  node.mesh = 0;
  node.scale = {2, 2, 2};
  scene.nodes = {node};
  scene.scenes = {{0}};
  GltfFile file = testing::buildGltf(scene);
  const std::int16_t shorts[12] = {0, 0, 0, 0, 32767, -32767, 0, 0, 16384, 32767, 0, 0}; // xyz + padding
  const std::size_t offset = file.bin.size();
  file.bin.resize(offset + sizeof shorts);
  std::memcpy(file.bin.data() + offset, shorts, sizeof shorts);
  file.json["buffers"][0]["byteLength"] = file.bin.size();
  file.json["bufferViews"].push_back(
      {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", sizeof shorts}, {"byteStride", 8}});
  file.json["accessors"].push_back({{"bufferView", file.json["bufferViews"].size() - 1},
                                    {"componentType", 5122},
                                    {"normalized", true},
                                    {"count", 3},
                                    {"type", "VEC3"}});
  file.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = file.json["accessors"].size() - 1;
  file.json["extensionsUsed"] = {"KHR_mesh_quantization"};
  file.json["extensionsRequired"] = {"KHR_mesh_quantization"};
  saveGltf(file, path("quantized.glb"), GltfStorage::kBinaryGlb);
  TriangleSoup soup;
  std::vector<ImportReport> reports;
  std::vector<std::string> warnings;
  const BakeStatus status = importInputs({path("quantized.glb")}, {}, {}, &soup, &reports, &warnings);
  ASSERT_TRUE(status.ok()) << status.message;
  ASSERT_EQ(soup.vertices.size(), 3u);
  EXPECT_NEAR(soup.vertices[1].x, 2.0f, 1e-6f);  // 32767 -> 1, times the node's 2
  EXPECT_NEAR(soup.vertices[1].y, -2.0f, 1e-6f); // -32767 -> -1
  EXPECT_NEAR(soup.vertices[2].x, 2.0f * 16384.0f / 32767.0f, 1e-6f);
  EXPECT_NEAR(soup.vertices[2].y, 2.0f, 1e-6f);
}

// ---- Bad inputs through the program: exit code, message, no output ----

struct BadCase {
  const char* name;
  int exit_code;
  const char* message;
};

testing::ProgramRun runDngbake(const std::string& args) {
  return testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + args + " 2>&1");
}

TEST_F(ImportTest, BadScenesGetTheirExitCodeAMessageAndNoOutput) {
  const GltfFile good = testing::buildGltf(twoCubes());
  saveGltf(good, path("good.glb"), GltfStorage::kBinaryGlb);
  {
    const std::string glb = testing::readFile(path("good.glb"));
    std::ofstream(path("truncated.glb"), std::ios::binary) << glb.substr(0, glb.size() - 40);
  }
  GltfFile outside = good;
  outside.json["buffers"][0]["uri"] = "../secret.bin";
  std::ofstream(dir_.path().parent_path() / "secret.bin") << std::string(4096, 'x');
  saveGltf(outside, path("outside.gltf"), GltfStorage::kExternalBin);
  GltfFile missing = good;
  missing.json["buffers"][0]["uri"] = "gone.bin";
  saveGltf(missing, path("missing.gltf"), GltfStorage::kExternalBin);
  GltfFile folder = good; // a buffer that is there but no file: a folder, as a FIFO or a device would be
  folder.json["buffers"][0]["uri"] = "folder.bin";
  std::filesystem::create_directory(path("folder.bin"));
  saveGltf(folder, path("folder.gltf"), GltfStorage::kExternalBin);
  GltfFile range = good;
  range.json["accessors"][0]["count"] = 1000;
  saveGltf(range, path("range.gltf"), GltfStorage::kEmbedded);
  GltfFile bad_index = good;
  bad_index.json["accessors"][1]["byteOffset"] = 0;
  bad_index.bin[bad_index.json["bufferViews"][1]["byteOffset"].get<std::size_t>()] = 200;
  saveGltf(bad_index, path("bad_index.gltf"), GltfStorage::kEmbedded);
  GltfScene nan_scene = twoCubes();
  nan_scene.meshes[0][0].positions[3].y = NAN;
  saveGltf(testing::buildGltf(nan_scene), path("nan.gltf"), GltfStorage::kEmbedded);
  GltfScene empty_scene = twoCubes();
  empty_scene.scenes = {{}};
  saveGltf(testing::buildGltf(empty_scene), path("empty.gltf"), GltfStorage::kEmbedded);
  GltfFile draco = good;
  draco.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  draco.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  saveGltf(draco, path("draco.gltf"), GltfStorage::kEmbedded);
  GltfScene cycle = twoCubes();
  cycle.nodes[1].children = {0};
  saveGltf(testing::buildGltf(cycle), path("cycle.gltf"), GltfStorage::kEmbedded);
  testing::writeOff(placedCubes({{kOther}}).vertices, placedCubes({{kOther}}).triangles, path("cube.off"));

  const std::pair<std::string, BadCase> cases[] = {
      {"truncated.glb", {"truncated", 3, "truncated.glb"}},
      {"outside.gltf", {"outside", 3, "outside the file's folder"}},
      {"missing.gltf", {"missing", 2, "does not exist"}},
      {"folder.gltf", {"folder", 2, "a buffer file is not a regular file: '"}},
      {"range.gltf", {"range", 3, "reaches outside its buffer view"}},
      {"bad_index.gltf", {"index", 3, "refers to vertex 200"}},
      {"nan.gltf", {"nan", 3, "NaN"}},
      {"empty.gltf", {"empty", 3, "holds no triangles"}},
      {"draco.gltf", {"draco", 5, "KHR_draco_mesh_compression"}},
      {"cycle.gltf", {"cycle", 3, "not a tree"}},
      {"good.glb --node nowhere", {"node", 1, "--node 'nowhere'"}},
      {"good.glb --scene 7", {"scene", 1, "--scene 7"}},
      {"cube.off --scene 0", {"scene of a mesh", 1, "--scene 0: no input is a scene file"}},
      {"good.glb --units parsecs", {"units", 1, "parsecs"}},
  };
  for (const auto& [args, c] : cases) {
    SCOPED_TRACE(args);
    const testing::ProgramRun run = runDngbake(path(args) + " -o " + path("out.dng"));
    EXPECT_EQ(run.exit_code, c.exit_code) << run.output;
    EXPECT_NE(run.output.find(c.message), std::string::npos) << run.output;
    EXPECT_FALSE(std::filesystem::exists(path("out.dng")));
  }
  std::filesystem::remove(dir_.path().parent_path() / "secret.bin");
}

TEST_F(ImportTest, JsonReportsEveryInputAndNode) {
  saveGltf(testing::buildGltf(twoCubes()), path("cubes.glb"), GltfStorage::kBinaryGlb);
  testing::writeOff(placedCubes({{kOther}}).vertices, placedCubes({{kOther}}).triangles, path("other.off"));
  const testing::ProgramRun run = runDngbake(path("cubes.glb") + " " + path("other.off") + " -o " + path("out.dng") +
                                             " --resolution 24 --json --source-units m");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json j = nlohmann::json::parse(run.output);
  ASSERT_EQ(j["inputs"].size(), 2u);
  EXPECT_EQ(j["units"], "m");
  EXPECT_EQ(j["mesh"]["triangles"], 36);
  const nlohmann::json& glb = j["inputs"][0];
  EXPECT_EQ(glb["format"], "glb");
  EXPECT_EQ(glb["triangles"], 24);
  EXPECT_EQ(glb["skipped_primitives"], 2);
  ASSERT_EQ(glb["nodes"].size(), 2u);
  EXPECT_EQ(glb["nodes"][0]["name"], "left");
  EXPECT_EQ(glb["nodes"][0]["skipped_primitives"], 1);
  EXPECT_EQ(glb["nodes"][0]["transform"].size(), 16u);
  EXPECT_EQ(j["inputs"][1]["importer"], "openmesh");
  EXPECT_EQ(j["inputs"][1]["triangles"], 12);
  // One name per --node: the word after it is an input again.
  const testing::ProgramRun left = runDngbake("--node left " + path("cubes.glb") + " " + path("other.off") + " -o " +
                                              path("left.dng") + " --resolution 24 --json");
  ASSERT_EQ(left.exit_code, 0) << left.output;
  const nlohmann::json l = nlohmann::json::parse(left.output);
  EXPECT_EQ(l["inputs"].size(), 2u);
  EXPECT_EQ(l["mesh"]["triangles"], 24); // the left cube and the OFF file's cube
  // Mesh files are taken whole, --node or not: an empty one fails the bake as it would alone.
  std::ofstream(path("nothing.off")) << "OFF\n0 0 0\n";
  const testing::ProgramRun empty = runDngbake("--node left " + path("cubes.glb") + " " + path("nothing.off") + " -o " +
                                               path("empty.dng") + " --resolution 24");
  EXPECT_EQ(empty.exit_code, 3) << empty.output;
  EXPECT_NE(empty.output.find("nothing.off': the mesh has no faces"), std::string::npos) << empty.output;
  // dngdump shows how the sources' units became the field's.
  const testing::ProgramRun dump = testing::runProgram(testing::shellQuoted(DNG_DNGDUMP_PATH) + " " + path("out.dng"));
  ASSERT_EQ(dump.exit_code, 0) << dump.output;
  EXPECT_NE(dump.output.find("units      m (from glb in m, scale 1; off in unknown, scale 1)"), std::string::npos)
      << dump.output;
}

// Inputs that crashed or leaked in assimp's readers under tests/fuzz/fuzz_assimp.cpp (first byte: the
// extension, as the fuzzer picks it). dngbake must answer each with a documented exit code and a
// message: the crash happens in the importer's child process.
TEST_F(ImportTest, AssimpReaderCrashesBecomeInvalidInput) {
  static const char* const kExtensions[] = {"fbx", "dae", "3ds", "ac", "x", "lwo", "ase", "ms3d", "off", "nff"};
  std::size_t replayed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(DNG_ASSIMP_REGRESSIONS)) {
    const std::string bytes = testing::readFile(entry.path().string());
    ASSERT_FALSE(bytes.empty());
    const std::string input =
        path(entry.path().filename().string() + "." + kExtensions[static_cast<unsigned char>(bytes[0]) % 10]);
    std::ofstream(input, std::ios::binary) << bytes.substr(1);
    const testing::ProgramRun run = runDngbake(input + " -o " + path("out.dng"));
    SCOPED_TRACE(entry.path().filename().string() + ": " + run.output);
    EXPECT_GE(run.exit_code, 0); // -1: dngbake itself died
    EXPECT_LE(run.exit_code, 5);
    if (entry.path().filename() == "ase_misspelt_vertex_count" ||
        entry.path().filename() == "ase_vertex_glued_to_keyword") {
      EXPECT_EQ(run.exit_code, 3);
      EXPECT_NE(run.output.find("assimp crashed reading it"), std::string::npos);
    }
    if (run.exit_code != 0) {
      EXPECT_FALSE(std::filesystem::exists(path("out.dng")));
    }
    std::filesystem::remove(path("out.dng"));
    ++replayed;
  }
  EXPECT_GE(replayed, 3u);
}

// AC3D, a text format only assimp reads here: an object with a name and a location.
TEST_F(ImportTest, AssimpScenesBakeWithTheirNodeTransforms) {
  const testing::Mesh cube = testing::boxMesh({0, 0, 0}, {0.5f, 0.5f, 0.5f});
  {
    std::ofstream ac(path("cube.ac"));
    ac << "AC3Db\nMATERIAL \"\" rgb 1 1 1  amb 0.2 0.2 0.2  emis 0 0 0  spec 0.5 0.5 0.5  shi 10  trans 0\n"
       << "OBJECT world\nkids 1\nOBJECT poly\nname \"box\"\nloc 1 2 3\nnumvert 8\n";
    for (const Vec3f& v : cube.vertices)
      ac << v.x << ' ' << v.y << ' ' << v.z << '\n';
    ac << "numsurf " << cube.triangles.size() << '\n';
    for (const auto& t : cube.triangles)
      ac << "SURF 0x10\nmat 0\nrefs 3\n" << t[0] << " 0 0\n" << t[1] << " 0 0\n" << t[2] << " 0 0\n";
    ac << "kids 0\n";
  }
  BakeReport report;
  const File baked = bakeFile(path("cube.ac"), "ac", &report);
  expectSameField(bakeOff(placedCubes({{Trs{{1, 2, 3}, {0, 0, 1}, 0.0, {1, 1, 1}}}}), "ac_ref").view(), baked.view());
  ASSERT_EQ(report.inputs.size(), 1u);
  EXPECT_EQ(report.inputs[0].importer, "assimp");
  EXPECT_EQ(report.inputs[0].triangles, 12u);
  ASSERT_FALSE(report.inputs[0].nodes.empty());
  EXPECT_EQ(report.inputs[0].nodes[0].name, "box");
}

} // namespace
} // namespace dng
