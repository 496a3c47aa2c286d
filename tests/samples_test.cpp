// The sample programs, run as a user runs them (small, with --particles, and mostly --no-pictures) and
// judged on the JSON lines they print: the physics each figure is about, not just that it ran. These
// are the same programs, scenes and measures that docs/SAMPLES.md describes at full size.
#include "run_program.h"
#include "sample_output.h"
#include "temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

#ifdef DNG_HAVE_BAKER
#include "dng/format/writer.h"
#include "mesh_reference.h"
#include "sample_files.h"
#include "stages.h"
#include "test_meshes.h"

#include <cmath>
#endif

namespace dng {
namespace testing {
namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// DNG_SAMPLES_DIR/dng_PROGRAM ARGS --particles N [--no-pictures], in the shell.
SampleOutput runProgramSmall(const std::string& program, const std::string& args, int particles,
                             bool pictures = false) {
  return runSample(quoted(std::string(DNG_SAMPLES_DIR) + "/dng_" + program) + " " + args + " --particles " +
                   std::to_string(particles) + (pictures ? "" : " --no-pictures"));
}

// Width and height from a PNG's header, or 0 x 0 when the file is not a PNG.
std::pair<std::uint32_t, std::uint32_t> pngSize(const std::string& path) {
  const std::string bytes = readFile(path);
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return {0, 0};
  auto be32 = [&](std::size_t at) {
    return std::uint32_t(std::uint8_t(bytes[at])) << 24 | std::uint32_t(std::uint8_t(bytes[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(bytes[at + 2])) << 8 | std::uint32_t(std::uint8_t(bytes[at + 3]));
  };
  return {be32(16), be32(20)};
}

TEST(SampleOutput, ReadsTheSamplesJsonLines) {
  const auto fields = parseFlatJson(R"({"sample":"fig3a_bouncy","particles":400,"step_seconds":0.0123})");
  EXPECT_EQ(fields.at("sample"), "fig3a_bouncy");
  EXPECT_EQ(fields.at("particles"), "400");
  EXPECT_EQ(fields.at("step_seconds"), "0.0123");
  EXPECT_TRUE(parseFlatJson("dng_demo: no such file").empty());
}

// Fig. 3: bounce heights fall with beta; drag stops sliding.
TEST(Samples, Fig3BounceHeightFallsWithBetaAndDragStopsSliding) {
  TempDir dir("samples_fig3");
  const SampleOutput out = runProgramSmall("fig3_falling", quoted(dir.path().string()), 400);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  for (const char* variant : {"fig3a_bouncy", "fig3b_slippery", "fig3c_drag"}) {
    EXPECT_EQ(out.get(variant, "particles"), 400) << variant;
    EXPECT_EQ(out.get(variant, "inside"), 0) << variant;
  }
  const double bouncy = out.get("fig3a_bouncy", "mean_rebound_height");
  EXPECT_GT(bouncy, 0.5);
  EXPECT_GT(bouncy, 5.0 * out.get("fig3b_slippery", "mean_rebound_height"));
  const double resting = out.get("fig3c_drag", "fraction_resting_on_top");
  EXPECT_GT(resting, 0.6);
  EXPECT_GT(resting, 5.0 * out.get("fig3b_slippery", "fraction_resting_on_top"));
}

// Every picture-making sample writes PREFIX_side.png and PREFIX_top.png, 640 pixels on the long side.
TEST(Samples, Fig3WritesASideAndATopPicturePerVariant) {
  TempDir dir("samples_pictures");
  const SampleOutput out = runProgramSmall("fig3_falling", quoted(dir.path().string()), 50, true);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  for (const char* variant : {"fig3a_bouncy", "fig3b_slippery", "fig3c_drag"}) {
    for (const char* view : {"_side.png", "_top.png"}) {
      const auto [width, height] = pngSize(dir.file(std::string(variant) + view));
      EXPECT_EQ(std::max(width, height), 640u) << variant << view;
      EXPECT_GT(std::min(width, height), 0u) << variant << view;
    }
  }
}

// A picture that cannot be written is exit code 2 (docs/SAMPLES.md), not a success with it missing: here
// a folder stands where the first one goes. Every variant still runs and prints its results.
TEST(Samples, LostPictureIsExitCode2) {
  TempDir dir("samples_lost_picture");
  std::filesystem::create_directory(dir.file("fig3a_bouncy_side.png"));
  const SampleOutput out = runProgramSmall("fig3_falling", quoted(dir.path().string()), 50, true);
  EXPECT_EQ(out.exit_code, 2) << out.text;
  for (const char* variant : {"fig3a_bouncy", "fig3b_slippery", "fig3c_drag"})
    EXPECT_EQ(out.get(variant, "particles"), 50) << variant;
}

// JSON lines that cannot be written (stdout on /dev/full, as on a full disk) are exit code 2 too.
TEST(Samples, LostJsonLinesAreExitCode2) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  TempDir dir("samples_lost_lines");
  const ProgramRun run = runProgram(quoted(std::string(DNG_SAMPLES_DIR) + "/dng_fig8_explosion") + " " +
                                    quoted(dir.path().string()) + " --particles 50 --no-pictures 2>&1 >/dev/full");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("cannot write to standard output"), std::string::npos) << run.output;
}

// Fig. 6: the stream goes around the sphere (ending far off its axis), not through it.
TEST(Samples, Fig6StreamFlowsAroundTheSphere) {
  TempDir dir("samples_fig6");
  const SampleOutput out = runProgramSmall("fig6_sphere_flow", quoted(dir.path().string()), 1200);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  EXPECT_EQ(out.get("fig6a_from_side", "particles"), 1200);
  EXPECT_EQ(out.get("fig6a_from_side", "inside"), 0);
  EXPECT_GT(out.get("fig6a_from_side", "fraction_downstream"), 0.3);
  EXPECT_GT(out.get("fig6a_from_side", "mean_downstream_offset"), 1.0); // the sphere's radius: they passed beside it
  EXPECT_EQ(out.get("fig6b_from_above", "inside"), 0);
  EXPECT_GT(out.get("fig6b_from_above", "fraction_downstream"), 0.9);
  EXPECT_GT(out.get("fig6b_from_above", "mean_downstream_offset"), 1.0);
}

// Fig. 7: around the shaft in every variant; a negative rho_out pulls the stream in behind it.
TEST(Samples, Fig7ShaftFlowDependsOnRhoInAndRhoOut) {
  TempDir dir("samples_fig7");
  const SampleOutput out = runProgramSmall("fig7_shaft_flow", quoted(dir.path().string()), 1200);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  for (const char* variant : {"fig7a_12_3", "fig7b_3_6", "fig7c_3_minus3"}) {
    EXPECT_EQ(out.get(variant, "particles"), 1200) << variant;
    EXPECT_EQ(out.get(variant, "inside"), 0) << variant;
    EXPECT_GT(out.get(variant, "fraction_downstream"), 0.3) << variant;
  }
  const double strong_in = out.get("fig7a_12_3", "mean_downstream_offset");
  EXPECT_GT(strong_in, 0.4); // wider than the shaft
  EXPECT_LT(out.get("fig7c_3_minus3", "mean_downstream_offset"), 0.5 * strong_in);
}

// Fig. 8: nothing ends inside the ground or a building, and the gas gets out between them.
TEST(Samples, Fig8ExplosionFlowsBetweenTheBuildings) {
  TempDir dir("samples_fig8");
  const SampleOutput out = runProgramSmall("fig8_explosion", quoted(dir.path().string()), 1500);
  ASSERT_EQ(out.exit_code, 0) << out.text;
  EXPECT_EQ(out.get("fig8_explosion", "particles"), 1500);
  EXPECT_EQ(out.get("fig8_explosion", "inside"), 0);
  EXPECT_GT(out.get("fig8_explosion", "fraction_beyond_buildings"), 0.3);
  EXPECT_GT(out.get("fig8_explosion", "contacts"), 0);
}

TEST(Samples, RejectAnUnknownOptionWithTheirUsage) {
  const ProgramRun run = runProgram(quoted(std::string(DNG_SAMPLES_DIR) + "/dng_fig8_explosion") + " --bogus 2>&1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("usage:"), std::string::npos) << run.output;
}

#ifdef DNG_HAVE_BAKER
class BakedSamples : public ::testing::Test {
protected:
  // Bakes `mesh` at resolution 48 and returns the .dng file's path.
  std::string bake(const Mesh& mesh, baker::NormalMode mode, const std::string& name) {
    writeObj(mesh, dir_.file(name + ".obj"));
    baker::BakeOptions options;
    options.mode = mode;
    options.resolution = 48;
    baker::BakeReport report;
    EXPECT_TRUE(
        baker::bake(dir_.file(name + ".obj"), {dir_.file(name + ".dng"), {}}, options, nullptr, nullptr, &report).ok());
    return dir_.file(name + ".dng");
  }
  TempDir dir_{"samples_test"};
};

// The paper's one-sided field of a zero-thickness sheet (§3.1: with normal-blur "the DN field will
// only work towards one direction"): its distance, |z|, but every normal +z, so every plane rises
// towards the sheet from below. 48^3 voxels over [-1.5, 1.5]^3, band 4 voxels.
std::vector<std::uint8_t> oneSidedSheet() {
  format::DenseField field;
  format::GridGeometry g;
  g.origin = {-1.5f, -1.5f, -1.5f};
  g.voxel_size = 3.0f / 48.0f;
  g.dims[0] = g.dims[1] = g.dims[2] = 48;
  g.band = 4.0f * g.voxel_size;
  field.reset(g);
  for (std::uint32_t k = 0; k < 48; ++k)
    for (std::uint32_t j = 0; j < 48; ++j)
      for (std::uint32_t i = 0; i < 48; ++i) {
        field.distance[g.index(i, j, k)] = std::min(std::fabs(g.voxelCentre(i, j, k).z), g.band);
        field.normal[g.index(i, j, k)] = {0.0f, 0.0f, 1.0f};
      }
  return format::encodeBricked(field, {}, "").bytes;
}

// A zero-thickness sheet keeps particles from both sides on their side, in potential mode (whose
// normals push away on both sides) and in normal-blur mode (whose blurred normals point one way, but
// whose planes, like every mode's since format 1.3, carry the distance's own normal).
TEST_F(BakedSamples, ThinSheetStopsParticlesFromBothSides) {
  for (baker::NormalMode mode : {baker::NormalMode::kPotential, baker::NormalMode::kNormalBlur}) {
    SCOPED_TRACE(baker::normalModeName(mode));
    const std::string sheet = bake(sheetMesh({0, 0, 0}, 1.0f), mode, std::string("sheet_") + normalModeName(mode));
    const SampleOutput out = runProgramSmall("thin_sheet", quoted(sheet) + " " + quoted(dir_.file("out")), 2000);
    EXPECT_EQ(out.exit_code, 0) << out.text;
    EXPECT_EQ(out.get("thin_sheet", "crossed"), 0);
    EXPECT_GT(out.get("thin_sheet", "contacts"), 1000); // they really were thrown at it
  }
  // The same scene on the one-sided field must show crossings: the measure can fail.
  writeFileBytes(dir_.file("one_sided.dng"), oneSidedSheet());
  const SampleOutput one_sided =
      runProgramSmall("thin_sheet", quoted(dir_.file("one_sided.dng")) + " " + quoted(dir_.file("out")), 2000);
  EXPECT_EQ(one_sided.exit_code, 1) << one_sided.text; // the sample says so in its exit code
  EXPECT_GT(one_sided.get("thin_sheet", "crossed"), 100);
}

TEST_F(BakedSamples, DemoLeavesNoParticleInsideTheMesh) {
  const Mesh mesh = sphereMesh({0, 0, 0}, 0.5f, 32, 16);
  const std::string ball = bake(mesh, baker::NormalMode::kNormalBlur, "ball");
  const std::string positions = dir_.file("positions.txt");
  const SampleOutput out =
      runProgramSmall("demo", quoted(ball) + " " + quoted(dir_.file("out")) + " z " + quoted(positions), 2000);
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_GT(out.get("demo", "contacts"), 0);
  // The throughput the demo prints is a timing, not a test; what it is computed from is checked here.
  EXPECT_EQ(out.get("demo", "particles"), 2000 / 120 * 120); // 120 raining steps of 2000 / 120 each
  EXPECT_EQ(out.get("demo", "steps"), 240);
  // POSITIONS: one "x y z" line per particle, judged on the mesh's own triangles, as setup.sh demo does.
  reference::MeshReference triangles;
  ASSERT_TRUE(triangles.build(mesh.vertices, mesh.triangles));
  std::ifstream in(positions);
  std::size_t lines = 0, inside = 0;
  for (Vec3f p; in >> p.x >> p.y >> p.z;) {
    ++lines;
    inside += triangles.inside(p) ? 1 : 0;
  }
  EXPECT_EQ(lines, std::size_t(2000 / 120 * 120));
  EXPECT_EQ(inside, 0u);
}
#endif

} // namespace
} // namespace testing
} // namespace dng
