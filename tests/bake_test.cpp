// The baker end to end: procedural meshes baked, read back through the runtime, compared with an
// independent brute-force reference; bad input through the real dngbake program.
#include "analytic_fields.h"
#include "dng/body.h"
#include "dng/file.h"
#include "dng/format/xxhash64.h"
#include "dng/particles.h"
#include "stages.h"
#include "test_meshes.h"

#include "run_program.h"
#include "sanitized_build.h" // tools/
#include "temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include <sys/stat.h>

namespace dng {
namespace baker {
namespace {

namespace fs = std::filesystem;
using testing::Mesh;

class BakeTest : public ::testing::Test {
protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Bakes `mesh` and maps the result; fails the test when either step fails.
  File bakeMesh(const Mesh& mesh, const std::string& name, BakeOptions options, BakeReport* out_report = nullptr) {
    testing::writeObj(mesh, path(name + ".obj"));
    BakeReport report;
    const BakeStatus status = bake(path(name + ".obj"), {path(name + ".dng"), {}}, options, nullptr, nullptr, &report);
    EXPECT_TRUE(status.ok()) << status.message;
    File file;
    Diagnostic diag;
    EXPECT_EQ(File::open(path(name + ".dng").c_str(), &file, &diag), Status::kOk) << diag.message;
    if (out_report) *out_report = report;
    return file;
  }
  testing::TempDir temp_{"bake_test"};
  const fs::path& dir_ = temp_.path();
};

BakeOptions exactOptions() {
  BakeOptions o;
  o.mode = NormalMode::kExact;
  o.resolution = 48;
  o.band_voxels = 3.0f;
  return o;
}

struct Shape {
  const char* name;
  Mesh mesh;
  Vec3f inside = {0, 0, 0}; // a point well inside, to check the test mesh faces outwards
};

std::vector<Shape> closedShapes() {
  return {{"box", testing::boxMesh({0.1f, -0.2f, 0.05f}, {1.0f, 0.7f, 0.5f}), {0.1f, -0.2f, 0.05f}},
          {"sphere", testing::sphereMesh({0, 0, 0}, 1.0f, 32, 16)},
          {"cylinder", testing::cylinderMesh({0, 0, 0}, 0.6f, 1.0f, 32)},
          {"torus", testing::torusMesh({0, 0, 0}, 1.0f, 0.35f, 32, 16), {1.0f, 0, 0}}};
}

// Band voxel centres, chosen at random: what the baker computed, read back through the runtime.
std::vector<Vec3f> bandCentres(const View& view, std::size_t count, std::uint32_t seed) {
  const GridInfo& g = view.grid();
  std::mt19937 rng(seed);
  std::vector<Vec3f> out;
  for (int tries = 0; tries < 200000 && out.size() < count; ++tries) {
    const auto i = std::uint32_t(rng() % g.dims[0]), j = std::uint32_t(rng() % g.dims[1]),
               k = std::uint32_t(rng() % g.dims[2]);
    const Vec3f c = g.origin + Vec3f{float(i) + 0.5f, float(j) + 0.5f, float(k) + 0.5f} * g.voxel_size;
    if (view.sample(c).status == SampleStatus::kInBand) out.push_back(c);
  }
  return out;
}

class BakeSign : public BakeTest, public ::testing::WithParamInterface<SignMode> {};

TEST_P(BakeSign, ExactModeDistancesAndSignsMatchBruteForce) {
  for (const Shape& shape : closedShapes()) {
    SCOPED_TRACE(shape.name);
    BakeOptions options = exactOptions();
    options.sign = GetParam();
    ASSERT_NEAR(testing::bruteWinding(shape.mesh, shape.inside), 1.0, 1e-3) << "test mesh faces inwards";
    BakeReport report;
    const File file = bakeMesh(shape.mesh, shape.name, options, &report);
    const View& view = file.view();
    const float h = view.grid().voxel_size;
    EXPECT_TRUE(report.mesh.closed());
    const auto centres = bandCentres(view, 1500, 3);
    ASSERT_GT(centres.size(), 1000u);
    for (const Vec3f& c : centres) {
      const Sample s = view.sample(c);
      const bool inside = testing::bruteWinding(shape.mesh, c) > 0.5;
      const float truth = testing::bruteDistance(shape.mesh, c) * (inside ? -1.0f : 1.0f);
      // Planes are lowered to bound the distance from below over their cells (never raised): by a few
      // hundredths of a voxel on flat and convex parts, by up to a fifth between the faceted torus's
      // concave facets. Inside, values only have to stay negative and are rounded to the nearest code.
      ASSERT_LE(s.distance, std::max(truth, 0.0f) + 1e-5f * h) << c.x << " " << c.y << " " << c.z;
      ASSERT_NEAR(s.distance, truth, 0.25f * h) << c.x << " " << c.y << " " << c.z;
      // The LIFT section gives the accurate query the distance from before the lowering: at a voxel
      // centre that is the exact one, up to the plane tiles' tolerance (0.02 voxel).
      ASSERT_NEAR(view.sample(c, Interpolation::kAccurate).distance, truth, 0.03f * h) << c.x << " " << c.y;
      if (inside) {
        ASSERT_LT(s.distance, 0.0f);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(WindingAndPseudonormal, BakeSign,
                         ::testing::Values(SignMode::kWinding, SignMode::kPseudonormal, SignMode::kAuto));

// Every option's bad values are refused by checkBakeOptions before bake() touches the input: the input
// here does not exist, so any later check would have reported kIo instead.
TEST_F(BakeTest, EveryBadOptionIsRefusedBeforeAnyWork) {
  struct Case {
    const char* names;
    void (*spoil)(BakeOptions&);
  };
  const Case cases[] = {
      {"--voxel-size", [](BakeOptions& o) { o.voxel_size = -1.0f; }},
      {"--voxel-size", [](BakeOptions& o) { o.voxel_size = NAN; }},
      {"--voxel-size", [](BakeOptions& o) { o.voxel_size = INFINITY; }},
      {"--resolution", [](BakeOptions& o) { o.resolution = kMinResolution - 1; }},
      {"--resolution", [](BakeOptions& o) { o.resolution = kMaxBakeAxisVoxels + 1; }},
      {"--band", [](BakeOptions& o) { o.band_voxels = 0.5f; }},
      {"--band", [](BakeOptions& o) { o.band_voxels = NAN; }},
      {"--band", [](BakeOptions& o) { o.band_voxels = INFINITY; }},
      {"--max-speed and --dt", [](BakeOptions& o) { o.max_speed = 3.0f; }},
      {"--max-speed and --dt", [](BakeOptions& o) { o.dt = 0.1f; }},
      {"--max-speed and --dt", [](BakeOptions& o) { o.max_speed = -1.0f, o.dt = 0.1f; }},
      {"--max-speed and --dt", [](BakeOptions& o) { o.max_speed = INFINITY, o.dt = 0.1f; }},
      {"--max-speed and --dt", [](BakeOptions& o) { o.max_speed = 1.0f, o.dt = NAN; }},
      {"--mode", [](BakeOptions& o) { o.mode = NormalMode(7); }},
      {"--blur-radius", [](BakeOptions& o) { o.blur_radius = 0; }},
      {"--blur-radius", [](BakeOptions& o) { o.blur_radius = kMaxBlurRadius + 1; }},
      {"--blur-rounds", [](BakeOptions& o) { o.blur_rounds = kMaxBlurRounds + 1; }},
      {"--sign", [](BakeOptions& o) { o.sign = SignMode(9); }},
      {"--encoding", [](BakeOptions& o) { o.encoding = format::Encoding(2); }},
      {"--brick-size", [](BakeOptions& o) { o.brick.brick_size = 5; }},
      {"--brick-size", [](BakeOptions& o) { o.brick.brick_size = 32; }},
      {"--tolerance", [](BakeOptions& o) { o.brick.tolerance_distance = -1.0f; }},
      {"--tolerance", [](BakeOptions& o) { o.brick.tolerance_distance = NAN; }},
      {"--tolerance", [](BakeOptions& o) { o.brick.tolerance_distance = INFINITY; }},
      {"normal tolerance", [](BakeOptions& o) { o.brick.tolerance_normal_deg = -1.0f; }},
      {"normal tolerance", [](BakeOptions& o) { o.brick.tolerance_normal_deg = 181.0f; }},
  };
  for (const Case& c : cases) {
    BakeOptions options;
    c.spoil(options);
    SCOPED_TRACE(c.names);
    EXPECT_EQ(checkBakeOptions(options).code, BakeError::kBadOption);
    BakeReport report;
    const BakeStatus status = bake(path("absent.obj"), {path("out.dng"), {}}, options, nullptr, nullptr, &report);
    EXPECT_EQ(status.code, BakeError::kBadOption) << status.message;
    EXPECT_NE(status.message.find(c.names), std::string::npos) << status.message;
    EXPECT_TRUE(report.stage_seconds.empty()) << "a stage ran";
  }
  EXPECT_TRUE(checkBakeOptions(BakeOptions()).ok());
  BakeOptions exact; // the blur options do not matter when nothing is blurred
  exact.mode = NormalMode::kExact;
  exact.blur_radius = 0;
  EXPECT_TRUE(checkBakeOptions(exact).ok());
}

TEST_F(BakeTest, PseudonormalSignRefusesOpenMeshes) {
  testing::writeObj(testing::withoutFace(testing::boxMesh({0, 0, 0}, {1, 1, 1}), 2), path("open.obj"));
  BakeOptions options = exactOptions();
  options.sign = SignMode::kPseudonormal;
  BakeReport report;
  const BakeStatus status = bake(path("open.obj"), {path("open.dng"), {}}, options, nullptr, nullptr, &report);
  EXPECT_EQ(status.code, BakeError::kInvalidInput);
  EXPECT_NE(status.message.find("closed manifold"), std::string::npos) << status.message;
  EXPECT_FALSE(fs::exists(path("open.dng")));
}

TEST_F(BakeTest, FarRegionsTakeTheRightSide) {
  const Mesh box = testing::boxMesh({0, 0, 0}, {1.0f, 1.0f, 1.0f});
  const File file = bakeMesh(box, "far", exactOptions());
  EXPECT_EQ(file.view().sample({0, 0, 0}).status, SampleStatus::kFarInside);
  const GridInfo& g = file.view().grid();
  EXPECT_EQ(file.view().sample(g.origin + Vec3f{0.5f, 0.5f, 0.5f} * g.voxel_size).status, SampleStatus::kFarOutside);
}

// A hollow ball (an outer sphere facing out, an inner one facing in): the flood fill must leave the
// cavity outside and the shell inside, far from any band voxel, with either sign method.
TEST_F(BakeTest, HollowBallCavityIsOutsideAndShellInside) {
  Mesh hollow = testing::sphereMesh({0, 0, 0}, 1.0f, 48, 24);
  const Mesh inner = testing::sphereMesh({0, 0, 0}, 0.5f, 32, 16);
  const auto first = std::uint32_t(hollow.vertices.size());
  hollow.vertices.insert(hollow.vertices.end(), inner.vertices.begin(), inner.vertices.end());
  for (const auto& t : inner.triangles)
    hollow.triangles.push_back({t[0] + first, t[2] + first, t[1] + first}); // reversed: faces the cavity
  for (SignMode sign : {SignMode::kAuto, SignMode::kWinding}) {
    BakeOptions options = exactOptions();
    options.resolution = 64;
    options.sign = sign;
    BakeReport report;
    const File file = bakeMesh(hollow, "hollow", options, &report);
    SCOPED_TRACE(report.sign);
    const View& view = file.view();
    EXPECT_EQ(view.sample({0, 0, 0}).status, SampleStatus::kFarOutside); // the cavity's centre
    for (const Vec3f& p : {Vec3f{0.75f, 0, 0}, Vec3f{0, -0.75f, 0}, Vec3f{0, 0, 0.75f}, Vec3f{-0.53f, 0.53f, 0}})
      EXPECT_EQ(view.sample(p).status, SampleStatus::kFarInside) << p.x << " " << p.y << " " << p.z;
    const Vec3f corner = view.grid().origin + Vec3f{0.5f, 0.5f, 0.5f} * view.grid().voxel_size;
    EXPECT_EQ(view.sample(corner).status, SampleStatus::kFarOutside);
  }
}

// Voxels whose closest point lies well inside one face of the box: their normal is that face's.
TEST_F(BakeTest, FlatFaceNormalsInExactAndNormalBlurModes) {
  const Mesh box = testing::boxMesh({0, 0, 0}, {1.0f, 1.0f, 1.0f});
  for (NormalMode mode : {NormalMode::kExact, NormalMode::kNormalBlur}) {
    BakeOptions options = exactOptions();
    options.mode = mode;
    const File file = bakeMesh(box, normalModeName(mode), options);
    const View& view = file.view();
    const float h = view.grid().voxel_size;
    int checked = 0;
    for (const Vec3f& c : bandCentres(view, 4000, 5)) {
      // On the +z face, away from its edges; normal-blur promises the face normal at surface voxels.
      if (std::fabs(c.x) > 1.0f - 2 * h || std::fabs(c.y) > 1.0f - 2 * h) continue;
      const float height = c.z - 1.0f;
      // Surface voxels (those the face overlaps) have centres within half a voxel of it.
      if (mode == NormalMode::kExact ? std::fabs(height) > 2.5f * h : std::fabs(height) > 0.501f * h) continue;
      const Sample s = view.sample(c);
      ASSERT_LT(angleDegrees(s.normal, {0, 0, 1}), 1.0) << normalModeName(mode) << " at z " << c.z;
      ++checked;
    }
    EXPECT_GT(checked, 10) << normalModeName(mode);
  }
}

// The promise the runtime's walk rests on (docs/FORMAT.md §5): anywhere in a voxel's cell, not only at
// its centre, a field value >= 0 is at most the true signed distance, up to the hundredth of a voxel
// the runtime's walk keeps as a margin (so it proves the point outside and a ball of that radius clear). Checked at
// random points against brute force over the triangles, on shapes with concave creases, thin parts and curvature, in
// every normal mode.
TEST_F(BakeTest, PlanesBoundTheTrueDistanceAnywhereInTheirCells) {
  const std::vector<Shape> shapes = {
      {"notch", testing::lBlockMesh({-1.0f, -1.0f, -0.4f}, 1.0f, 0.8f)},
      {"plate", testing::boxMesh({0, 0, 0}, {1.0f, 0.8f, 0.012f})}, // a quarter of a voxel thick
      {"torus", testing::torusMesh({0, 0, 0}, 1.0f, 0.35f, 32, 16), {1.0f, 0, 0}}};
  for (const Shape& shape : shapes) {
    for (NormalMode mode : {NormalMode::kExact, NormalMode::kNormalBlur, NormalMode::kPotential}) {
      SCOPED_TRACE(std::string(shape.name) + " " + normalModeName(mode));
      BakeOptions options = exactOptions();
      options.mode = mode;
      const File file = bakeMesh(shape.mesh, shape.name, options);
      const View& view = file.view();
      ASSERT_TRUE(view.conservativePlanes());
      EXPECT_NE(std::string(view.metadata()).find("\"planes_checked_on_triangles\":true"), std::string::npos);
      const GridInfo& g = view.grid();
      std::mt19937 rng(11);
      std::uniform_real_distribution<float> unit(0.0f, 1.0f);
      int checked = 0, seconds = 0;
      for (int tries = 0; tries < 200000 && checked < 2000; ++tries) {
        const Vec3f p =
            g.origin + Vec3f{unit(rng) * float(g.dims[0]), unit(rng) * float(g.dims[1]), unit(rng) * float(g.dims[2])} *
                           g.voxel_size;
        const Sample s = view.sample(p);
        if (s.status != SampleStatus::kInBand) continue;
        ++checked;
        const float truth =
            testing::bruteDistance(shape.mesh, p) * (testing::bruteWinding(shape.mesh, p) > 0.5 ? -1.0f : 1.0f);
        // The runtime never takes more than the guaranteed reach from a sample (FORMAT.md §5.1). The second
        // planes (§5.5) keep the same promise: the walk reads the higher of the two.
        const float value = std::min(s.distance, view.guaranteedReach());
        if (value >= 0.0f) {
          ASSERT_LE(value, truth + 0.01f * g.voxel_size) << p.x << " " << p.y << " " << p.z;
        }
        const Sample bound = view.lowerBound(p);
        seconds += bound.distance > s.distance ? 1 : 0;
        if (std::min(bound.distance, view.guaranteedReach()) >= 0.0f) {
          ASSERT_LE(std::min(bound.distance, view.guaranteedReach()), truth + 0.01f * g.voxel_size)
              << "second plane at " << p.x << " " << p.y << " " << p.z;
        }
      }
      EXPECT_EQ(checked, 2000);
      EXPECT_TRUE(view.hasSecondPlanes());
      EXPECT_GT(seconds, 0) << "no sample's second plane read higher: the promise above was not tested on them";
    }
  }
}

// Beside a box's convex edges, points a tenth of a voxel to half a voxel out: a voxel whose centre is
// nearest one face carries that face's plane, which reads below zero just outside the other face, so
// the walk could not prove many of them outside. The second planes (docs/FORMAT.md §5.5) prove more of
// them, and never one the triangles say is nearer than it reads. In every mode: the blurred ones keep
// the distance's planes (their normals are shading normals).
// Of up to 1,000 points `draw` gives (false: none this try) that lie 0.1 to 0.5 voxel outside `mesh`
// (brute force), how many each file's lowerBound proves outside. On the way it checks that the second
// bounds (in `with`) only add to what the planes alone (in `without`) prove, and never rise above the
// true distance.
struct ProvenNear {
  int near = 0, with = 0, without = 0;
};
template <class Draw> ProvenNear provenNear(const Mesh& mesh, const File& with, const File& without, Draw draw) {
  const float h = with.view().grid().voxel_size, proof = 0.01f * h;
  ProvenNear count;
  for (int tries = 0; tries < 400000 && count.near < 1000; ++tries) {
    Vec3f p;
    if (!draw(&p)) continue;
    const float truth = testing::bruteDistance(mesh, p);
    if (truth < 0.1f * h || truth > 0.5f * h || testing::bruteWinding(mesh, p) > 0.5) continue;
    ++count.near;
    const float a = with.view().lowerBound(p).distance, b = without.view().lowerBound(p).distance;
    EXPECT_GE(a, b);
    EXPECT_LE(std::min(a, with.view().guaranteedReach()), truth + 0.01f * h);
    count.with += a >= proof ? 1 : 0;
    count.without += b >= proof ? 1 : 0;
  }
  return count;
}

// In an L-block's notch, points a tenth of a voxel to half a voxel out near its concave crease: a
// voxel's plane there came down for the other face's sake, so it reads below zero a little outside its
// own face. The second bounds' pairs (the own plane raised back, and the other face's) prove them.
TEST_F(BakeTest, SecondBoundsProveMorePointsInAConcaveCrease) {
  const Vec3f origin{-1.0f, -1.0f, -0.4f};
  const float size = 1.0f, depth = 0.8f;
  const Mesh notch = testing::lBlockMesh(origin, size, depth); // crease along x = y = 0, z in [-0.4, 0.4]
  BakeOptions options = exactOptions();
  const File with = bakeMesh(notch, "crease_with", options);
  options.second_planes = false;
  const File without = bakeMesh(notch, "crease_without", options);
  const float h = with.view().grid().voxel_size;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const ProvenNear count = provenNear(notch, with, without, [&](Vec3f* out) {
    // Within a voxel and a half of the crease, in the notch's open quarter (x > 0, y > 0).
    *out = Vec3f{unit(rng) * 1.5f * h, unit(rng) * 1.5f * h, origin.z + 0.1f + unit(rng) * (depth - 0.2f)};
    return true;
  });
  EXPECT_EQ(count.near, 1000);
  std::printf("crease: of %d points 0.1 to 0.5 voxel out, %d proven by the planes alone, %d with second bounds\n",
              count.near, count.without, count.with);
  // Measured: 772 of 1,000 left unproven by the planes alone, none with the second bounds.
  EXPECT_LT(count.near - count.with, (count.near - count.without) / 2);
}

TEST_F(BakeTest, SecondPlanesProveMorePointsBesideEdges) {
  const Vec3f half{1.0f, 0.8f, 0.6f};
  // Turned, so its edges cross the grid's cells every which way.
  const float c = std::cos(0.45f), s = std::sin(0.45f), c2 = std::cos(0.3f), s2 = std::sin(0.3f);
  const auto turn = [&](Vec3f v) { // about z, then about x
    const Vec3f z{c * v.x - s * v.y, s * v.x + c * v.y, v.z};
    return Vec3f{z.x, c2 * z.y - s2 * z.z, s2 * z.y + c2 * z.z};
  };
  const auto unturn = [&](Vec3f v) {
    const Vec3f x{v.x, c2 * v.y + s2 * v.z, -s2 * v.y + c2 * v.z};
    return Vec3f{c * x.x + s * x.y, -s * x.x + c * x.y, x.z};
  };
  Shape shape{"box", testing::boxMesh({0, 0, 0}, half)};
  for (Vec3f& v : shape.mesh.vertices)
    v = turn(v);
  for (NormalMode mode : {NormalMode::kExact, NormalMode::kNormalBlur}) {
    SCOPED_TRACE(normalModeName(mode));
    BakeOptions options = exactOptions();
    options.mode = mode;
    const File with = bakeMesh(shape.mesh, "edges_with", options);
    options.second_planes = false;
    const File without = bakeMesh(shape.mesh, "edges_without", options);
    ASSERT_TRUE(with.view().hasSecondPlanes());
    ASSERT_FALSE(without.view().hasSecondPlanes());
    const GridInfo& g = with.view().grid();
    const float h = g.voxel_size;
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const ProvenNear count = provenNear(shape.mesh, with, without, [&](Vec3f* out) {
      *out = g.origin +
             Vec3f{unit(rng) * float(g.dims[0]), unit(rng) * float(g.dims[1]), unit(rng) * float(g.dims[2])} * h;
      // Within a voxel of an edge: two coordinates within a voxel of the box's faces, in its frame.
      const Vec3f q = unturn(*out);
      return int(std::fabs(std::fabs(q.x) - half.x) < h) + int(std::fabs(std::fabs(q.y) - half.y) < h) +
                 int(std::fabs(std::fabs(q.z) - half.z) < h) >=
             2;
    });
    EXPECT_EQ(count.near, 1000);
    // Measured: 29 of 1,000 left unproven by the planes alone, 3 with the second planes.
    EXPECT_LT(count.near - count.with, (count.near - count.without) / 2);
    std::printf("%s: of %d points 0.1 to 0.5 voxel out beside edges, %d proven by the planes alone, %d with "
                "second planes\n",
                normalModeName(mode), count.near, count.without, count.with);
  }
}

// Beside a convex edge a blurred field's own planes read below zero just outside the face (the blur
// tilts them towards the other face), so the walk proves the way with its neighbours' planes: their
// balls, and their planes slid along with the particle (walk.cpp slideEnd). A particle skimming the
// face along the edge, 0.4 to 1.5 voxels above it, must keep going with its whole move each step, and
// none may end inside the box (judged on the triangles). Closer than about 0.3 voxel to the face and
// within a voxel of the edge the lowered planes prove nothing and particles stop (docs/RUNTIME.md,
// "Limits"); that is not what this checks.
TEST_F(BakeTest, ParticlesSkimmingAFaceBesideAConvexEdgeSlideAlongIt) {
  const Mesh box = testing::boxMesh({0, 0, 0}, {1.0f, 1.0f, 1.0f});
  BakeOptions options = exactOptions();
  options.mode = NormalMode::kNormalBlur;
  const File file = bakeMesh(box, "edge", options);
  const float h = file.view().grid().voxel_size;
  Material material; // impact, beta 0.5: nothing here approaches the face, so only the walk acts
  material.collision_distance = 0.05f * h;
  Body body;
  ASSERT_EQ(Body::create(&file.view(), material, &body), Status::kOk);
  constexpr float kDt = 1.0f / 60.0f;
  const float speed = 0.9f * h / kDt; // just under a voxel per step, along the edge (+y)
  std::vector<float> px, py, pz, vx, vy, vz;
  for (float in : {0.1f, 0.2f, 0.3f, 0.5f})
    for (float up : {0.4f, 0.6f, 1.0f, 1.5f})
      for (int k = 0; k < 8; ++k)
        px.push_back(1.0f - in * h), pz.push_back(1.0f + up * h), py.push_back(-0.9f + 0.11f * float(k) + 0.013f * in);
  const std::size_t n = px.size();
  const std::vector<float> start_y = py;
  vx.assign(n, 0.0f), vy.assign(n, speed), vz.assign(n, 0.0f);
  ParticleSpan span{px.data(), py.data(), pz.data(), sizeof(float), vx.data(), vy.data(), vz.data(), sizeof(float), n};
  constexpr int kSteps = 10;
  for (int step = 0; step < kSteps; ++step)
    ASSERT_EQ(stepParticles(span, kDt, &body, 1), Status::kOk);
  for (std::size_t i = 0; i < n; ++i) {
    SCOPED_TRACE("particle " + std::to_string(i));
    EXPECT_NEAR(vy[i], speed, 1e-4f * speed);
    EXPECT_NEAR(py[i] - start_y[i], float(kSteps) * speed * kDt, 1e-4f);
    EXPECT_GT(testing::bruteWinding(box, {px[i], py[i], pz[i]}), -0.5);
    EXPECT_LT(testing::bruteWinding(box, {px[i], py[i], pz[i]}), 0.5) << "inside the box";
  }
}

// Blurred modes keep the exact distances but for the conservative lowering, which their tilted normals
// make larger (up to about half a voxel here, by the tilt between a blurred normal and the distance's
// gradient), and every normal near the surface points away from it.
TEST_F(BakeTest, BlurredModesKeepDistancesAndOutwardNormals) {
  const Mesh sphere = testing::sphereMesh({0, 0, 0}, 1.0f, 32, 16);
  for (NormalMode mode : {NormalMode::kNormalBlur, NormalMode::kPotential}) {
    BakeOptions options = exactOptions();
    options.mode = mode;
    const File file = bakeMesh(sphere, normalModeName(mode), options);
    const float h = file.view().grid().voxel_size;
    for (const Vec3f& c : bandCentres(file.view(), 800, 7)) {
      const Sample s = file.view().sample(c);
      const bool inside = testing::bruteWinding(sphere, c) > 0.5;
      const float truth = testing::bruteDistance(sphere, c) * (inside ? -1.0f : 1.0f);
      ASSERT_LE(s.distance, std::max(truth, 0.0f) + 1e-5f * h);
      ASSERT_NEAR(s.distance, truth, 0.75f * h);
      ASSERT_GT(dot(s.normal, normalizeOrZero(c)), 0.5f) << normalModeName(mode) << " at " << c.x << " " << c.y << " "
                                                         << c.z << " d " << s.distance << " r " << length(c);
    }
  }
}

TEST_F(BakeTest, OpenBoxAndTriangleSoupGetSensibleSigns) {
  const Mesh box = testing::boxMesh({0, 0, 0}, {1.0f, 1.0f, 1.0f});
  for (const Shape& shape : {Shape{"open_box", testing::withoutFace(box, 2)}, Shape{"soup", testing::toSoup(box)}}) {
    SCOPED_TRACE(shape.name);
    BakeReport report;
    const File file = bakeMesh(shape.mesh, shape.name, exactOptions(), &report);
    const bool open_box = shape.name == std::string("open_box");
    if (open_box) {
      EXPECT_FALSE(report.mesh.closed());
    }
    // The open box has a hole and encloses space; the soup's triangles only repeat their corners.
    EXPECT_EQ(report.mesh.hole_edges, open_box ? 4u : 0u);
    const auto holes = std::count_if(report.warnings.begin(), report.warnings.end(), [](const std::string& w) {
      return w.find("has holes (4 open edges) yet encloses space") != std::string::npos;
    });
    EXPECT_EQ(holes, open_box ? 1 : 0);
    const float h = file.view().grid().voxel_size;
    EXPECT_LT(file.view().sample({0, 0, -1.0f + 1.5f * h}).distance, 0.0f); // inside, near the bottom
    EXPECT_GT(file.view().sample({0, 0, -1.0f - 1.5f * h}).distance, 0.0f); // outside, below
    EXPECT_GT(file.view().sample({1.0f + 1.5f * h, 0, 0}).distance, 0.0f);
    EXPECT_LT(file.view().sample({1.0f - 1.5f * h, 0, 0}).distance, 0.0f);
  }
}

// Paper §3.1: "If the object has near-zero thickness ... this method [normal-blur] does not work at
// all"; the potential method repels from both sides.
TEST_F(BakeTest, ThinSheetInPotentialModeRepelsFromBothSides) {
  BakeOptions options = exactOptions();
  options.mode = NormalMode::kPotential;
  BakeReport report;
  const File file = bakeMesh(testing::sheetMesh({0, 0, 0}, 1.0f), "sheet", options, &report);
  // A sheet's edges are holes, but it encloses nothing: no warning about particles getting in.
  EXPECT_GT(report.mesh.hole_edges, 0u);
  for (const std::string& w : report.warnings)
    EXPECT_EQ(w.find("has holes"), std::string::npos) << w;
  const float h = file.view().grid().voxel_size;
  int checked = 0;
  for (float x = -0.6f; x <= 0.6f; x += 0.2f) {
    for (float side : {1.0f, -1.0f}) {
      const Sample s = file.view().sample({x, 0.1f, side * 1.5f * h});
      ASSERT_EQ(s.status, SampleStatus::kInBand);
      EXPECT_GT(s.normal.z * side, 0.9f) << "x " << x << " side " << side;
      EXPECT_GT(s.distance, 0.0f);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 14);
}

TEST_F(BakeTest, SameBytesWhateverTheThreadCount) {
  const Mesh torus = testing::torusMesh({0, 0, 0}, 1.0f, 0.35f, 32, 16);
  testing::writeObj(torus, path("torus.obj"));
  std::vector<std::string> outputs;
  for (std::uint32_t threads : {1u, 2u}) {
    BakeOptions options = exactOptions();
    options.mode = NormalMode::kNormalBlur;
    options.threads = threads;
    BakeReport report;
    const std::string out = path("torus_" + std::to_string(threads) + ".dng");
    ASSERT_TRUE(bake(path("torus.obj"), {out, {}}, options, nullptr, nullptr, &report).ok());
    outputs.push_back(testing::readFile(out));
  }
  EXPECT_EQ(outputs[0], outputs[1]);
}

// --no-lift leaves the LIFT section out and changes nothing else the runtime reads: every query but
// the accurate one gives the same bits, and the accurate one then reads the lowered values.
TEST_F(BakeTest, WithoutTheLiftOnlyTheAccurateQueryChanges) {
  const Mesh torus = testing::torusMesh({0, 0, 0}, 1.0f, 0.35f, 32, 16);
  BakeOptions options = exactOptions();
  const File lifted = bakeMesh(torus, "lifted", options);
  options.lift = false;
  const File plain = bakeMesh(torus, "plain", options);
  EXPECT_TRUE(lifted.view().hasLift());
  EXPECT_FALSE(plain.view().hasLift());
  EXPECT_LT(plain.view().sizeBytes(), lifted.view().sizeBytes());
  std::size_t raised = 0;
  for (const Vec3f& p : analytic::randomPoints({-1.5f, -1.5f, -0.5f}, {1.5f, 1.5f, 0.5f}, 3000, 4)) {
    for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear}) {
      const Sample a = lifted.view().sample(p, mode), b = plain.view().sample(p, mode);
      ASSERT_EQ(a.distance, b.distance);
      ASSERT_EQ(a.status, b.status);
    }
    const float a = lifted.view().sample(p, Interpolation::kAccurate).distance;
    const float b = plain.view().sample(p, Interpolation::kAccurate).distance;
    // Lifts raise, but for half a 10-bit step where inside values were rounded to the nearest code.
    ASSERT_GE(a, b - 0.005f * lifted.view().grid().voxel_size);
    raised += a > b ? 1 : 0;
  }
  EXPECT_GT(raised, 1000u);
}

// The blurred modes store the exact mode's planes and their own normals beside them (SHAD, format
// 1.3): their distances are the exact bake's, their queries' normals are not, and their accurate query
// is as close to the triangles as the exact mode's. Exact files have no SHAD; --no-lift keeps it.
TEST_F(BakeTest, BlurredModesKeepTheExactPlanesAndShadeWithTheirNormals) {
  const Mesh torus = testing::torusMesh({0, 0, 0}, 1.0f, 0.35f, 32, 16);
  const File exact = bakeMesh(torus, "exact", exactOptions());
  EXPECT_FALSE(exact.view().hasShading());
  const float h = exact.view().grid().voxel_size;
  const std::vector<Vec3f> points = [&] {
    std::vector<Vec3f> near;
    for (const Vec3f& p : analytic::randomPoints({-1.5f, -1.5f, -0.5f}, {1.5f, 1.5f, 0.5f}, 6000, 9))
      if (exact.view().sample(p).status == SampleStatus::kInBand && near.size() < 1500) near.push_back(p);
    return near;
  }();
  ASSERT_GT(points.size(), 1000u);
  // The accurate query's worst distance error against the triangles, in voxels.
  const auto worst = [&](const View& view) {
    float out = 0.0f;
    for (const Vec3f& p : points) {
      const bool inside = testing::bruteWinding(torus, p) > 0.5;
      const float truth = testing::bruteDistance(torus, p) * (inside ? -1.0f : 1.0f);
      out = std::max(out, std::fabs(view.sample(p, Interpolation::kAccurate).distance - truth) / h);
    }
    return out;
  };
  const float exact_error = worst(exact.view());
  for (const NormalMode mode : {NormalMode::kNormalBlur, NormalMode::kPotential}) {
    SCOPED_TRACE(normalModeName(mode));
    BakeOptions options = exactOptions();
    options.mode = mode;
    const File blurred = bakeMesh(torus, normalModeName(mode), options);
    EXPECT_TRUE(blurred.view().hasShading());
    EXPECT_FALSE(blurred.view().hasGradient()); // the planes' normals are the gradient
    // The same as the exact mode's: measured 0.0743 voxel against 0.0741. Through the blurred normals
    // it was 0.064 (normal-blur) and 0.140 (potential).
    EXPECT_NEAR(worst(blurred.view()), exact_error, 0.003f);
    int tilted = 0;
    for (const Vec3f& p : points) {
      const Sample a = blurred.view().sample(p), b = exact.view().sample(p);
      ASSERT_EQ(a.status, b.status);
      // Plane tiles may differ (a blurred one must fit the shading normals too), within the tolerance.
      ASSERT_NEAR(a.distance, b.distance, 0.03f * h);
      tilted += analytic::angleDegrees(a.normal, b.normal) > 2.0f ? 1 : 0;
    }
    EXPECT_GT(tilted, int(points.size()) / 10) << "the blurred normals are what the queries answer";
    options.lift = false;
    const File plain = bakeMesh(torus, "plain", options);
    EXPECT_TRUE(plain.view().hasShading());
    EXPECT_FALSE(plain.view().hasLift());
  }
}

// Progress comes during the long stages, not only at their ends, and returning false stops the bake
// there with nothing written.
TEST_F(BakeTest, ProgressReportsWithinStagesAndCancelStopsTheBake) {
  testing::writeObj(testing::sphereMesh({0, 0, 0}, 1.0f, 32, 16), path("sphere.obj"));
  struct Recorder {
    std::vector<std::pair<std::string, double>> calls;
    std::string cancel_in; // stage to cancel in, once past a third of it
    static bool record(void* self, const char* stage, double fraction) {
      auto* r = static_cast<Recorder*>(self);
      r->calls.emplace_back(stage, fraction);
      return !(r->cancel_in == stage && fraction > 0.3);
    }
    int count(const std::string& stage) const {
      return int(std::count_if(calls.begin(), calls.end(), [&](const auto& c) { return c.first == stage; }));
    }
  };
  BakeOptions options = exactOptions();
  options.mode = NormalMode::kNormalBlur;
  options.threads = 1; // every distance block reports
  Recorder full;
  BakeReport report;
  ASSERT_TRUE(bake(path("sphere.obj"), {path("full.dng"), {}}, options, &Recorder::record, &full, &report).ok());
  EXPECT_GT(full.count("distance"), 10);
  EXPECT_GE(full.count("normals"), int(3 * options.blur_rounds)); // after every blur pass
  EXPECT_GT(full.count("encode"), 3);                             // after every layer of bricks
  for (const char* stage : {"distance", "normals", "encode"}) {
    SCOPED_TRACE(stage);
    Recorder cancelling;
    cancelling.cancel_in = stage;
    const BakeStatus status =
        bake(path("sphere.obj"), {path("cut.dng"), {}}, options, &Recorder::record, &cancelling, &report);
    EXPECT_EQ(status.code, BakeError::kCancelled);
    EXPECT_LT(cancelling.count(stage), full.count(stage));
    EXPECT_FALSE(fs::exists(path("cut.dng")));
  }
}

// The source hash is read in 1 MB chunks: a mesh file of several MB checks the chunks join up.
TEST_F(BakeTest, SourceHashIsTheXxh64OfTheWholeInputFile) {
  testing::writeObj(testing::sphereMesh({0, 0, 0}, 1.0f, 300, 150), path("fine.obj"));
  const std::string bytes = testing::readFile(path("fine.obj"));
  ASSERT_GT(bytes.size(), std::size_t(2) << 20);
  char expected[17];
  std::snprintf(expected, sizeof expected, "%016llx", (unsigned long long)format::xxhash64(bytes.data(), bytes.size()));
  BakeOptions options = exactOptions();
  options.resolution = 16;
  options.band_voxels = 2.0f;
  BakeReport report;
  ASSERT_TRUE(bake(path("fine.obj"), {path("fine.dng"), {}}, options, nullptr, nullptr, &report).ok());
  EXPECT_EQ(report.source_hash, expected);
  File file;
  ASSERT_EQ(File::open(path("fine.dng").c_str(), &file), Status::kOk);
  EXPECT_NE(std::string(file.view().metadata()).find(expected), std::string::npos);
}

TEST_F(BakeTest, BandFromMaxSpeedCoversTheTravelPerStep) {
  BakeOptions options = exactOptions();
  options.max_speed = 6.0f;
  options.dt = 1.0f / 60.0f; // 0.1 units per step
  const File file = bakeMesh(testing::sphereMesh({0, 0, 0}, 1.0f, 32, 16), "speed", options);
  EXPECT_GE(file.view().guaranteedReach(), 0.1f);
  EXPECT_LT(file.view().guaranteedReach(), 0.1f + 2.0f * file.view().grid().voxel_size);
}

// ---- The program: exit codes, messages, and nothing written on failure ----

using testing::ProgramRun;

ProgramRun runDngbake(const std::string& args) {
  return testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + args + " 2>&1");
}

// A binary STL of one facet (normal, three vertices) that declares `declared` facets.
void writeBinaryStl(const std::string& file, const char* header_text, std::uint32_t declared, const float facet[12]) {
  std::ofstream stl(file, std::ios::binary);
  char header[80] = {};
  std::strncpy(header, header_text, sizeof header - 1);
  const std::uint16_t attributes = 0;
  stl.write(header, sizeof header);
  stl.write(reinterpret_cast<const char*>(&declared), 4);
  stl.write(reinterpret_cast<const char*>(facet), 12 * sizeof(float));
  stl.write(reinterpret_cast<const char*>(&attributes), 2);
}

TEST_F(BakeTest, BadInputGetsAClearMessageItsExitCodeAndNoOutput) {
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("good.obj"));
  std::ofstream(path("empty.obj")) << "";
  // OpenMesh's OBJ reader cannot even parse "nan" (the vertex is dropped, and later face indices name
  // the wrong vertices); binary STL carries raw floats. The guards read the coordinates first.
  std::ofstream(path("nan_text.obj")) << "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n";
  std::ofstream(path("words.off")) << "these are not the vertices you are looking for\n";
  fs::create_directory(path("folder.obj"));
  const float zero_facet[12] = {};
  writeBinaryStl(path("cut.stl"), "binary STL, truncated", 2, zero_facet); // lost its last facet
  // Upper-case ASCII STL (OpenMesh reads it), and a binary one cut short whose header says "solid".
  std::ofstream(path("upper.stl")) << "SOLID s\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\n"
                                      "VERTEX 0 nan 0\nENDLOOP\nENDFACET\nENDSOLID s\n";
  writeBinaryStl(path("solid_cut.stl"), "solid exported as binary", 3, zero_facet);
  std::ofstream(path("huge.off")) << "OFF\n3 1 0\n0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n";
  std::ofstream(path("nan_text.stl")) << "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                         "vertex 0 nan 0\nendloop\nendfacet\nendsolid s\n";
  std::ofstream(path("nan.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n";
  std::ofstream(path("cut_text.stl")) << "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n";
  const float nan_facet[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, NAN, 1, 0};
  writeBinaryStl(path("nan.stl"), "binary STL with a NaN", 1, nan_facet);
  std::ofstream(path("flat.obj")) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  // OpenMesh's OBJ reader asserts (and aborts) on a face vertex without its index: found by fuzzing.
  std::ofstream(path("no_index.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n";
  // OpenMesh's PLY reader crashed on a property before any element (a misspelt keyword): fuzzing.
  std::ofstream(path("misspelt.ply")) << "ply\nformat ascii 1.0\neLement vertex 3\nproperty float x\nend_header\n";
  // OpenMesh's OFF reader took a negative face count as a huge one and kept reading: fuzzing.
  std::ofstream(path("negative.off")) << "OFF\n 0  -1 2\n";
  // OpenMesh reads the counts after the keyword's line: here from the vertex line, 3 * 10^11 vertices
  // (it read for ever; fuzzing).
  std::ofstream(path("keyword_line.off")) << "OFF 1 0\n300999999990 0\n1 0 01 , ";
  std::ofstream(path("mesh.xyzw")) << "nope";
  std::ofstream(path("mesh.om")) << "OMTB"; // OpenMesh's own format: its reader needs an OpenMesh mesh
  // A binary OFF with big-endian counts: OpenMesh read them as 3 * 2^24 faces and read on for ever.
  std::ofstream(path("big_endian.off")) << std::string("OFF BINARY\n\0\0\0\3\0\0\0\1\0\0\0\0", 23);
  std::ofstream(path("mesh.fbx")) << "nope"; // assimp reads FBX: a broken one is invalid input
  std::ofstream(path("keep.dng")) << "previous contents";
  struct Case {
    std::string args;
    int exit_code;
    const char* says;
  };
  const Case cases[] = {
      {path("empty.obj"), 3, "no faces"},
      {path("absent.obj"), 2, "no such file"},
      {path("mesh.xyzw"), 5, "unknown mesh format"},
      {path("mesh.om"), 5, "native .om format is not supported"},
      {path("big_endian.off"), 3, "OFF binary header declares 50331648 vertices of 12 bytes"},
      {path("mesh.fbx"), 3, "assimp could not read it"},
      {path("nan.stl"), 3, "facet 0 has a NaN or infinite vertex coordinate"},
      {path("nan_text.stl"), 3, "line 6: vertex has coordinate 'nan', not a finite number"},
      {path("nan_text.obj"), 3, "line 3: vertex has coordinate 'nan', not a finite number"},
      {path("huge.off"), 3, "OFF vertex 1 has coordinate '1e39', not a finite number"},
      {path("words.off"), 3, "OFF file has no OFF keyword"},
      {path("upper.stl"), 3, "line 6: vertex has coordinate 'nan', not a finite number"},
      {path("solid_cut.stl"), 3, "binary STL declares 3 facets, 234 bytes, but has 134: truncated"},
      {path("cut.stl"), 3, "binary STL declares 2 facets, 184 bytes, but has 134: truncated"},
      {path("nan.ply"), 3, "PLY vertex 2 has coordinate 'nan', not a finite number"},
      {path("cut_text.stl"), 3, "line 2: facet has no 'endfacet': the file is truncated"},
      {path("folder.obj"), 2, "folder.obj' is a directory, not a mesh file"},
      // One bad or empty input among several: the union used to hide it (a NaN vertex in a second OFF
      // baked 84 million garbage triangles).
      {path("good.obj") + " " + path("huge.off"), 3, "not a finite number"},
      {path("good.obj") + " " + path("empty.obj"), 3, "empty.obj': the mesh has no faces"},
      {path("flat.obj"), 3, "degenerate"},
      {path("no_index.obj"), 3, "line 4: face vertex '/1' has no vertex index"},
      {path("misspelt.ply"), 3, "line 3 'eLement vertex 3' has an unknown keyword"},
      {path("negative.off"), 3, "count '-1' is not a number"},
      {path("keyword_line.off"), 3, "has its counts on the keyword's line: OpenMesh reads them from the next line"},
      {path("good.obj") + " --mode sideways", 1, "sideways"},
      {path("good.obj") + " --resolution 4", 1, "resolution"},
      {path("good.obj") + " --resolution 2000 --encoding dense", 1, "at most 134,217,728"},
      {path("good.obj") + " --voxel-size 0.0001", 1, "at most 2048"},
      {path("good.obj") + " --band 2 --max-speed 3 --dt 0.1", 1, "excludes"},
      // Option values are checked before the mesh is read: these once failed late or with exit 4.
      {path("absent.obj") + " --tolerance -1", 1, "--tolerance"},
      {path("absent.obj") + " --blur-radius 0", 1, "--blur-radius"},
      {path("absent.obj") + " --blur-rounds 1000", 1, "--blur-rounds"},
      {path("absent.obj") + " --band 0.5", 1, "--band"},
      {path("absent.obj") + " --voxel-size -2", 1, "--voxel-size"},
      {path("absent.obj") + " --brick-size 5", 1, "--brick-size"},
      {path("absent.obj") + " --band 1e30", 1, "--band must be between 1 and 2048"},
      {path("absent.obj") + " --voxel-size 1e-7", 1, "--voxel-size must be at least 1.5e-05"},
      // Said in a line, before the mesh is read (a NaN scale had failed as a mesh with NaN vertices, a
      // zero one printed the whole range of a double).
      {path("absent.obj") + " --scale nan", 1, "--scale: must be a finite number > 0, got 'nan'"},
      {path("absent.obj") + " --scale 0", 1, "--scale: must be a finite number > 0, got '0'"},
      {path("absent.obj") + " --scene -1", 1, "--scene: must be a whole number >= 0, got '-1'"},
      {path("absent.obj") + " --voxel-size 0", 1, "--voxel-size: must be a finite number > 0"},
      {path("absent.obj") + " --voxel-size 1e-46", 1, "--voxel-size: must be a finite number > 0"}, // 0 as a float
      {path("absent.obj") + " --memory-limit 0", 1, "--memory-limit: must be auto, none or a size"},
      {path("absent.obj") + " --memory-limit -5G", 1, "--memory-limit: must be auto, none or a size"},
      {path("absent.obj") + " --memory-limit 6Q", 1, "--memory-limit: must be auto, none or a size"},
      {path("absent.obj") + " --memory-limit 1.5G", 1, "--memory-limit: must be auto, none or a size"},
      // Grids the format or OpenVDB cannot hold: refused when placed, not after the whole bake (exit 4).
      {path("good.obj") + " --scale 1e-6", 1, "below OpenVDB's smallest (1.5e-05)"},
      {path("good.obj") + " --scale 2e18", 1, "beyond +-1e18, the format's range"},
      {path("good.obj") + " --max-speed 1e30 --dt 1", 1, "more than a grid of 2048 holds"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const ProgramRun run = runDngbake(c.args + " -o " + path("out.dng"));
    EXPECT_EQ(run.exit_code, c.exit_code) << run.output;
    EXPECT_NE(run.output.find(c.says), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(path("out.dng")));
    // A failed bake leaves an existing output untouched.
    const ProgramRun kept = runDngbake(c.args + " -o " + path("keep.dng"));
    EXPECT_EQ(testing::readFile(path("keep.dng")), "previous contents");
  }
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "leftover " << entry.path();
}

// Nothing an output path names is ever lost: not an input, not the other output, not a device or a
// pipe (a rename over /dev/null replaced the device), not a previous export when the .dng cannot be
// written (both outputs are written in full before either replaces a file).
TEST_F(BakeTest, OutputsThatWouldDestroySomethingAreRefused) {
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("box.obj"));
  const std::string mesh = testing::readFile(path("box.obj"));
  ProgramRun run = runDngbake(path("box.obj") + " -o " + dir_.string() + "/./box.obj");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("is the input"), std::string::npos) << run.output;
  EXPECT_EQ(testing::readFile(path("box.obj")), mesh);
  run = runDngbake(path("box.obj") + " -o " + path("both") + " --export-vdb " + path("both"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_FALSE(fs::exists(path("both")));
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
  run = runDngbake(path("box.obj") + " -o " + path("pipe"));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("not a regular file"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::is_fifo(path("pipe")));
  std::ofstream(path("old.vdb")) << "previous export";
  run = runDngbake(path("box.obj") + " --resolution 16 -o " + path("missing/out.dng") + " --export-vdb " +
                   path("old.vdb"));
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_EQ(testing::readFile(path("old.vdb")), "previous export");
  run = runDngbake(path("box.obj") + " --resolution 16 -o " + path("out.dng") + " --export-vdb " + path("old.vdb"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(testing::readFile(path("old.vdb")), "previous export");
  for (const char* name : {"out.dng", "old.vdb"}) // readable by others, as a plain create makes them
    EXPECT_EQ(fs::status(path(name)).permissions() & fs::perms::others_read, fs::perms::others_read) << name;
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "leftover " << entry.path();
}

// Memory running out inside OpenVDB, TBB or Embree is an error with its exit code, not an abort, and
// the previous output survives. The address-space limit would break the sanitizers' own mappings.
TEST_F(BakeTest, RunningOutOfMemoryIsAnErrorNotACrash) {
#ifdef DNG_SANITIZED_BUILD
  GTEST_SKIP() << "an address-space limit and a sanitizer runtime do not mix";
#endif
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("big.obj"));
  std::ofstream(path("kept.dng")) << "previous contents";
  // A box at 2000 voxels needs gigabytes of band; 600 MB of address space is enough to start.
  const ProgramRun run =
      testing::runProgram("ulimit -v 600000; " + testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + path("big.obj") +
                          " --resolution 2000 --memory-limit none -o " + path("kept.dng") + " 2>&1");
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("out of memory"), std::string::npos) << run.output;
  EXPECT_EQ(testing::readFile(path("kept.dng")), "previous contents");
}

// A bake that would outgrow its memory limit stops with exit 4 and says which limit, instead of being
// killed by the kernel (exit 137, no message) where the machine or its container runs out. The limit
// holds: the peak stays near it. Nothing is written; the previous output survives.
TEST_F(BakeTest, MemoryLimitStopsABakeThatWouldOutgrowIt) {
#ifdef DNG_SANITIZED_BUILD
  GTEST_SKIP() << "the memory limit replaces operator new, which a sanitizer runtime owns";
#endif
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("big.obj"));
  std::ofstream(path("kept.dng")) << "previous contents";
  // The box at 2000 voxels needs gigabytes; 300 MiB is enough to load it and start.
  const std::uint64_t limit = std::uint64_t(300) << 20;
  const ProgramRun run = testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + path("big.obj") +
                                             " --resolution 2000 --memory-limit 300M --threads 2 --json -o " +
                                             path("kept.dng") + " 2>" + path("stderr.txt"));
  EXPECT_EQ(run.exit_code, 4) << run.output;
  const std::string said = testing::readFile(path("stderr.txt"));
  EXPECT_NE(said.find("out of memory while baking"), std::string::npos) << said;
  EXPECT_NE(said.find("reached its memory limit, 315 MB: --memory-limit"), std::string::npos) << said;
  const nlohmann::json report = nlohmann::json::parse(run.output, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << run.output;
  EXPECT_EQ(report["error"]["exit_code"], 4);
  EXPECT_EQ(report["working_store"]["memory_limit_bytes"].get<std::uint64_t>(), limit);
  const auto peak = report["working_store"]["peak_memory_bytes"].get<std::uint64_t>();
  EXPECT_GT(peak, limit / 2) << "the bake stopped long before the limit";
  EXPECT_LT(peak, limit + (std::uint64_t(64) << 20)) << "the limit did not hold";
  EXPECT_EQ(testing::readFile(path("kept.dng")), "previous contents");
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "leftover " << entry.path();
}

// Memory that runs out while a reader holds it (OpenMesh's, here) is out of memory too, exit 4, not an
// unreadable file (exit 2): the readers' own error handling lets std::bad_alloc through.
TEST_F(BakeTest, MemoryRunningOutWhileLoadingIsNotAnUnreadableFile) {
#ifdef DNG_SANITIZED_BUILD
  GTEST_SKIP() << "the memory limit replaces operator new, which a sanitizer runtime owns";
#endif
  // A binary STL: its guard reads facets into a fixed buffer, so the first 16 MB allocated, where the
  // limit is first checked, are OpenMesh's (welding a million triangles' corners takes several times
  // that), and the limit is below what the process holds once its libraries are loaded.
  const testing::Mesh sphere = testing::sphereMesh({0, 0, 0}, 1.0f, 1024, 512);
  {
    std::ofstream stl(path("fine.stl"), std::ios::binary);
    const char header[80] = "binary STL of a fine sphere";
    const auto count = std::uint32_t(sphere.triangles.size());
    stl.write(header, sizeof header);
    stl.write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : sphere.triangles) {
      float facet[12] = {};
      for (int corner = 0; corner < 3; ++corner)
        std::memcpy(facet + 3 + 3 * corner, &sphere.vertices[t[corner]], 3 * sizeof(float));
      const std::uint16_t attributes = 0;
      stl.write(reinterpret_cast<const char*>(facet), sizeof facet);
      stl.write(reinterpret_cast<const char*>(&attributes), 2);
    }
  }
  const ProgramRun run = runDngbake(path("fine.stl") + " --memory-limit 8M -o " + path("fine.dng"));
  EXPECT_EQ(run.exit_code, 4) << run.output;
  EXPECT_NE(run.output.find("out of memory while baking"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("could not read"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("fine.dng")));
}

// The kilobytes after `key` in /proc/meminfo; 0 when it is not there.
std::uint64_t meminfoKilobytes(const std::string& key) {
  std::istringstream lines(testing::readFile("/proc/meminfo"));
  std::string name;
  std::uint64_t value = 0;
  while (lines >> name >> value) {
    if (name == key + ":") return value;
    lines.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return 0;
}

// By default the limit is what the bake holds at the start and most of what the machine (or container)
// has free then: some, never more than its memory and swap. `none` lifts it; a size is taken in bytes,
// k = 1024, its digits decimal.
TEST_F(BakeTest, MemoryLimitDefaultsToTheMachinesFreeMemory) {
#ifdef DNG_SANITIZED_BUILD
  GTEST_SKIP() << "the memory limit replaces operator new, which a sanitizer runtime owns";
#endif
  const std::uint64_t total = (meminfoKilobytes("MemTotal") + meminfoKilobytes("SwapTotal")) * 1024;
  if (total == 0) GTEST_SKIP() << "no /proc/meminfo here";
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("box.obj"));
  const auto limitOf = [&](const std::string& option) {
    const ProgramRun run = runDngbake(path("box.obj") + " --resolution 16 --json -o " + path("box.dng") + option);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    const nlohmann::json report = nlohmann::json::parse(run.output, nullptr, false);
    return report.is_discarded() ? nlohmann::json() : report["working_store"]["memory_limit_bytes"];
  };
  const nlohmann::json automatic = limitOf("");
  ASSERT_TRUE(automatic.is_number_unsigned()) << automatic;
  EXPECT_GT(automatic.get<std::uint64_t>(), std::uint64_t(1) << 20);
  EXPECT_LE(automatic.get<std::uint64_t>(), total);
  EXPECT_TRUE(limitOf(" --memory-limit auto").is_number_unsigned());
  EXPECT_TRUE(limitOf(" --memory-limit none").is_null());
  EXPECT_EQ(limitOf(" --memory-limit 6G").get<std::uint64_t>(), std::uint64_t(6) << 30);
  EXPECT_EQ(limitOf(" --memory-limit 2048mb").get<std::uint64_t>(), std::uint64_t(2) << 30);
  EXPECT_EQ(limitOf(" --memory-limit 010G").get<std::uint64_t>(), std::uint64_t(10) << 30); // not octal
}

// Shell lines that start dngbake in the background as $pid and wait until it has installed its SIGINT
// handler (bit 2 of SigCgt in /proc): a signal before that would kill it the default way.
std::string startDngbake(const std::string& args) {
  return testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + args + " & pid=$!; " +
         "until m=$(grep ^SigCgt /proc/$pid/status 2>/dev/null | cut -f2) && [ -n \"$m\" ] && (( 0x$m & 2 )); do "
         "kill -0 $pid 2>/dev/null || break; done; ";
}

// Ctrl-C before the writes stops the bake at its next progress report: exit 130, the message and the
// JSON report agree that nothing was written, and the previous output is still there.
TEST_F(BakeTest, InterruptBeforeTheWritesStopsTheBakeAndKeepsThePreviousOutput) {
  testing::writeObj(testing::sphereMesh({0, 0, 0}, 1.0f, 64, 32), path("slow.obj"));
  std::ofstream(path("slow.dng")) << "previous contents";
  // The signal lands while the mesh loads or soon after: the first progress report ends the bake.
  const ProgramRun run = testing::runProgram(
      "bash -c '" +
      startDngbake(path("slow.obj") + " -o " + path("slow.dng") + " --resolution 400 --json 2>" + path("stderr.txt")) +
      "kill -INT $pid; wait $pid; echo \"status $?\"'");
  EXPECT_NE(run.output.find("status 130"), std::string::npos) << run.output;
  const std::string json = run.output.substr(0, run.output.rfind("status"));
  const nlohmann::json report = nlohmann::json::parse(json, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << run.output;
  EXPECT_EQ(report["ok"], false);
  EXPECT_EQ(report["error"]["exit_code"], 130);
  EXPECT_NE(testing::readFile(path("stderr.txt")).find("interrupted; " + path("slow.dng") + " was not written"),
            std::string::npos);
  EXPECT_EQ(testing::readFile(path("slow.dng")), "previous contents");
}

// A signal that arrives once the writes have begun (here during --export-vdb, which comes first) does
// not stop them: the bake finishes and says so. Exit 0, "ok": true, no "interrupted", both files whole.
TEST_F(BakeTest, InterruptDuringTheWritesFinishesAndReportsSuccess) {
  testing::writeObj(testing::sphereMesh({0, 0, 0}, 1.0f, 64, 32), path("late.obj"));
  int landed = 0;
  for (int attempt = 0; attempt < 5 && landed == 0; ++attempt) {
    fs::remove(path("late.dng"));
    fs::remove(path("late.vdb"));
    // Wait for the .vdb's temporary file, then interrupt; "sent" only if the process was still running.
    const ProgramRun run = testing::runProgram(
        "bash -c '" +
        startDngbake(path("late.obj") + " -o " + path("late.dng") + " --export-vdb " + path("late.vdb") +
                     " --resolution 160 --json 2>" + path("stderr.txt")) +
        "until compgen -G \"" + path(".late.vdb") +
        ".tmp.*\" >/dev/null; do kill -0 $pid 2>/dev/null || break; done; " +
        "kill -INT $pid 2>/dev/null && echo sent >&2; wait $pid; echo \"status $?\"' 2>" + path("sent.txt"));
    if (testing::readFile(path("sent.txt")).find("sent") == std::string::npos) continue; // too late: again
    ++landed;
    EXPECT_NE(run.output.find("status 0"), std::string::npos) << run.output;
    const nlohmann::json report =
        nlohmann::json::parse(run.output.substr(0, run.output.rfind("status")), nullptr, false);
    ASSERT_FALSE(report.is_discarded()) << run.output;
    EXPECT_EQ(report["ok"], true);
    EXPECT_EQ(testing::readFile(path("stderr.txt")).find("interrupted"), std::string::npos);
    File file;
    ASSERT_EQ(File::open(path("late.dng").c_str(), &file), Status::kOk);
    EXPECT_EQ(file.view().verifyHashes(), Status::kOk);
    EXPECT_TRUE(fs::exists(path("late.vdb")));
  }
  EXPECT_EQ(landed, 1) << "the signal never arrived during the writes in 5 attempts";
}

// SIGKILL cannot be handled: the output path must still hold the previous good file or nothing, never
// a partial one, whenever the kill lands. Bakes killed at a spread of moments, repeatedly.
TEST_F(BakeTest, KillingTheBakeNeverLeavesAPartialOutput) {
  testing::writeObj(testing::sphereMesh({0, 0, 0}, 1.0f, 48, 24), path("kill.obj"));
  const std::string bake_args = path("kill.obj") + " -o " + path("kill.dng") + " --resolution 64 --quiet";
  ASSERT_EQ(testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + bake_args).exit_code, 0);
  std::mt19937 random(11);
  int killed = 0;
  for (int round = 0; round < 12; ++round) {
    // Busy-loop steps before the kill, spread from "while loading" to about a second (past the write
    // on an idle machine), with jitter: ~5 us a step.
    const int spin = round * 16000 + std::uniform_int_distribution<int>(0, 16000)(random);
    const ProgramRun run = testing::runProgram("bash -c '" + testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + bake_args +
                                               " --tolerance 0.0" + std::to_string(round % 5) +
                                               " & pid=$!; for ((i = 0; i < " + std::to_string(spin) +
                                               "; i++)); do :; done; kill -KILL $pid 2>/dev/null && echo killed; "
                                               "wait $pid; true'");
    killed += run.output.find("killed") != std::string::npos ? 1 : 0;
    File file;
    ASSERT_EQ(File::open(path("kill.dng").c_str(), &file), Status::kOk) << "round " << round;
    ASSERT_EQ(file.view().verifyHashes(), Status::kOk) << "round " << round;
  }
  EXPECT_GT(killed, 0) << "no bake was killed while running";
}

TEST_F(BakeTest, ProgramReportsJsonAndVersion) {
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("box.obj"));
  const ProgramRun run = runDngbake(path("box.obj") + " -o " + path("box.dng") + " --resolution 96 --json");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json report = nlohmann::json::parse(run.output);
  EXPECT_EQ(report["format"], "dngbake-report");
  EXPECT_EQ(report["version"], 1);
  EXPECT_EQ(report["mesh"]["triangles"], 12);
  EXPECT_EQ(report["mesh"]["closed"], true);
  EXPECT_GT(report["encoder"]["band_voxels"].get<std::uint64_t>(), 1000u);
  for (const char* stage : {"load", "check", "distance", "normals", "encode", "write"})
    EXPECT_TRUE(report["seconds"].contains(stage)) << stage;
  // The band's leaves: some, but far fewer than the grid's 8^3 cells.
  const auto blocks = report["working_store"]["blocks"].get<std::uint64_t>();
  const auto dims = report["grid"]["dims"];
  EXPECT_GT(blocks, 0u);
  EXPECT_LT(blocks * 512u, dims[0].get<std::uint64_t>() * dims[1].get<std::uint64_t>() * dims[2].get<std::uint64_t>());
  EXPECT_GT(report["working_store"]["peak_memory_bytes"].get<std::uint64_t>(), std::uint64_t(1) << 20);
  EXPECT_TRUE(fs::exists(path("box.dng")));
  const ProgramRun version = runDngbake("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find(DNG_TOOL_VERSION), std::string::npos);
  EXPECT_EQ(runDngbake("--help").exit_code, 0);
}

// A report that could not be written (here /dev/full, as on a full disk) is an I/O error, not a
// success a script would read an empty report after. The .dng itself is whole: only the report is lost.
TEST_F(BakeTest, LostJsonReportIsAnIoError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  testing::writeObj(testing::boxMesh({0, 0, 0}, {1, 1, 1}), path("box.obj"));
  const ProgramRun run = testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + path("box.obj") + " -o " +
                                             path("box.dng") + " --resolution 16 --json 2>&1 >/dev/full");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("dngbake: error: cannot write to standard output"), std::string::npos) << run.output;
  File file;
  ASSERT_EQ(File::open(path("box.dng").c_str(), &file), Status::kOk);
  EXPECT_EQ(file.view().verifyHashes(), Status::kOk);
  for (const char* option : {"--help", "--version"}) { // they print there too
    const ProgramRun lost =
        testing::runProgram(testing::shellQuoted(DNG_DNGBAKE_PATH) + " " + option + " 2>&1 >/dev/full");
    EXPECT_EQ(lost.exit_code, 2) << option << ": " << lost.output;
  }
}

} // namespace
} // namespace baker
} // namespace dng
