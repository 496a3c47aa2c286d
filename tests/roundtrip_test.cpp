// Round trips: analytic fields written dense and bricked, read back through the runtime, and
// compared at thousands of random points with the exact field and with each other.
#include "analytic_fields.h"
#include "dng/format/writer.h"
#include "dng/view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <thread>
#include <vector>

namespace dng {
namespace {

using analytic::AnalyticField;
using format::BrickOptions;
using format::DenseField;
using format::EncodeResult;

constexpr float kRadiansPerDegree = 0.017453292f;

// An encoded file and the view onto its bytes; the view lives as long as the bytes it points at.
struct Opened {
  EncodeResult file;
  View view;
};

Opened openOrDie(EncodeResult encoded) {
  EXPECT_TRUE(encoded.ok()) << encoded.error;
  Opened out{std::move(encoded), View()};
  Diagnostic diag;
  EXPECT_EQ(View::open(out.file.bytes.data(), out.file.bytes.size(), &out.view, &diag), Status::kOk) << diag.message;
  return out; // moving the vector keeps its buffer, so the view stays valid
}

// Nearest reports "far" when the containing voxel's centre is far, so points used for in-band
// comparisons stay half a voxel diagonal inside the 3-voxel band.
constexpr float kInBandReach = 3.0f - 0.87f;

struct Scene {
  const char* name;
  AnalyticField field;
  float curvature_bound_voxels; // how far nearest+plane refinement may stray from the exact field
};

// A 40^3 grid of unit voxels around the origin with a 3-voxel band.
format::GridGeometry sceneGrid() { return analytic::cubeGrid({-20, -20, -20}, 1.0f, 40, 3.0f); }

std::vector<Vec3f> pointsNearSurface(const AnalyticField& field, float max_distance, std::size_t count) {
  std::vector<Vec3f> out;
  const auto candidates = analytic::randomPoints({-19.5f, -19.5f, -19.5f}, {19.5f, 19.5f, 19.5f}, count * 40, 11);
  for (const Vec3f& p : candidates) {
    if (std::fabs(field(p).distance) < max_distance) out.push_back(p);
    if (out.size() == count) break;
  }
  return out;
}

class RoundTrip : public ::testing::TestWithParam<std::uint32_t> {};

// Dense reproduces smooth fields to within the refinement's curvature error, and bricked reproduces
// dense to within what the encoder says it let through (plus the normal error over half a voxel).
TEST_P(RoundTrip, BrickedMatchesDenseWithinReportedErrorAndDenseMatchesExact) {
  const Scene scenes[] = {
      {"tilted plane", analytic::planeField({0.3f, -0.2f, 1.0f}, 1.5f), 0.001f},
      {"sphere", analytic::sphereField({0.4f, -0.3f, 0.2f}, 12.0f), 0.05f},
      {"box", analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f}), -1.0f}, // edges: not smooth
  };
  BrickOptions options;
  options.brick_size = GetParam();
  for (const Scene& scene : scenes) {
    SCOPED_TRACE(scene.name);
    const DenseField field = analytic::sampleField(sceneGrid(), scene.field);
    const Opened dense = openOrDie(format::encodeDense(field, ""));
    const Opened bricked = openOrDie(format::encodeBricked(field, options, ""));
    const format::EncodeStats& stats = bricked.file.stats;
    EXPECT_LE(stats.max_distance_error_voxels, std::max(options.tolerance_distance, 6.0f / 2046.0f) + 1e-4f);
    EXPECT_LE(stats.max_normal_error_deg, std::max(options.tolerance_normal_deg, 0.1f));
    const float normal_error_rad = stats.max_normal_error_deg * kRadiansPerDegree;
    const float bound = stats.max_distance_error_voxels + 0.87f * normal_error_rad + 1e-4f;

    int compared = 0;
    for (const Vec3f& p : pointsNearSurface(scene.field, kInBandReach, 3000)) {
      const Sample d = dense.view.sample(p);
      const Sample b = bricked.view.sample(p);
      ASSERT_EQ(d.status, SampleStatus::kInBand) << p.x << " " << p.y << " " << p.z;
      ASSERT_EQ(b.status, SampleStatus::kInBand);
      ASSERT_NEAR(b.distance, d.distance, bound);
      ASSERT_LE(analytic::angleDegrees(b.normal, d.normal), stats.max_normal_error_deg + 1e-3f);
      ASSERT_NEAR(length(b.normal), 1.0f, 1e-5f);
      if (scene.curvature_bound_voxels >= 0.0f) {
        ASSERT_NEAR(d.distance, scene.field(p).distance, scene.curvature_bound_voxels);
      }
      ++compared;
    }
    EXPECT_EQ(compared, 3000);
  }
}

TEST_P(RoundTrip, TrilinearBrickedMatchesTrilinearDenseAndTheSphere) {
  const AnalyticField sphere = analytic::sphereField({0.4f, -0.3f, 0.2f}, 12.0f);
  BrickOptions options;
  options.brick_size = GetParam();
  const DenseField field = analytic::sampleField(sceneGrid(), sphere);
  const Opened dense = openOrDie(format::encodeDense(field, ""));
  const Opened bricked = openOrDie(format::encodeBricked(field, options, ""));
  const float bound = bricked.file.stats.max_distance_error_voxels + 1e-4f;
  for (const Vec3f& p : pointsNearSurface(sphere, 2.0f, 3000)) {
    const Sample d = dense.view.sample(p, Interpolation::kTrilinear);
    const Sample b = bricked.view.sample(p, Interpolation::kTrilinear);
    ASSERT_NEAR(b.distance, d.distance, bound);
    ASSERT_NEAR(d.distance, sphere(p).distance, 0.05f);
    ASSERT_LE(analytic::angleDegrees(d.normal, sphere(p).normal), 3.0f);
    ASSERT_LE(analytic::angleDegrees(b.normal, d.normal), 0.2f);
  }
}

INSTANTIATE_TEST_SUITE_P(BrickSizes, RoundTrip, ::testing::Values(4u, 8u, 16u));

TEST(PlaneTiles, PlanarFieldNeedsNoBricksAndQueriesStayExact) {
  const AnalyticField plane = analytic::planeField({0.3f, -0.2f, 1.0f}, 1.5f);
  const Opened opened = openOrDie(format::encodeBricked(analytic::sampleField(sceneGrid(), plane), {}, ""));
  const format::EncodeStats& stats = opened.file.stats;
  EXPECT_EQ(stats.tiles.brick, 0u);
  EXPECT_GT(stats.tiles.plane, 0u);
  EXPECT_GT(stats.tiles.far_outside, 0u);
  EXPECT_GT(stats.tiles.far_inside, 0u);
  // The reader counts with the encoder's type: what was written is what is read.
  const TileCounts& read = opened.view.tileCounts();
  EXPECT_EQ(read.plane, stats.tiles.plane);
  EXPECT_EQ(read.far_outside, stats.tiles.far_outside);
  EXPECT_EQ(read.far_inside, stats.tiles.far_inside);
  EXPECT_EQ(read.total(), stats.tiles.total());
  EXPECT_EQ(opened.view.tileCounts().brick, 0u);
  for (const Vec3f& p : pointsNearSurface(plane, kInBandReach, 2000)) {
    const Sample s = opened.view.sample(p);
    ASSERT_EQ(s.status, SampleStatus::kInBand);
    ASSERT_NEAR(s.distance, plane(p).distance, 0.02f + 1e-3f);
    ASSERT_LT(analytic::angleDegrees(s.normal, plane(p).normal), 0.5f);
  }
}

TEST(PlaneTiles, BoxFacesBecomePlanesAndEdgesBecomeBricks) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  const Opened opened = openOrDie(format::encodeBricked(analytic::sampleField(sceneGrid(), box), {}, ""));
  const View& view = opened.view;
  EXPECT_GT(view.tileCounts().plane, 0u);
  EXPECT_GT(view.tileCounts().brick, 0u);
  EXPECT_GT(view.tileCounts().far_inside, 0u);
  // A point in the middle of the +z face, between the two rows of voxel centres.
  const Sample s = view.sample({0.3f, 0.2f, 10.9f + 0.25f});
  EXPECT_NEAR(s.distance, 0.25f, 0.03f); // the face is at z = 11 - 0.1
  EXPECT_LT(analytic::angleDegrees(s.normal, {0, 0, 1}), 0.5f);
}

TEST(FarTiles, FarSidesReportBandAndNoNormal) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 12.0f);
  const Opened opened = openOrDie(format::encodeBricked(analytic::sampleField(sceneGrid(), sphere), {}, ""));
  const View& view = opened.view;
  const Sample outside = view.sample({19.0f, 19.0f, 19.0f});
  EXPECT_EQ(outside.status, SampleStatus::kFarOutside);
  EXPECT_GE(outside.distance, 3.0f);
  EXPECT_EQ(length(outside.normal), 0.0f);
  const Sample inside = view.sample({0.5f, 0.5f, 0.5f});
  EXPECT_EQ(inside.status, SampleStatus::kFarInside);
  EXPECT_LE(inside.distance, -3.0f);
}

TEST(NoField, OutsideTheGridOrNotFiniteOrEmptyView) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 12.0f);
  const DenseField field = analytic::sampleField(sceneGrid(), sphere);
  const Opened dense = openOrDie(format::encodeDense(field, ""));
  const Opened bricked = openOrDie(format::encodeBricked(field, {}, ""));
  const float inf = INFINITY;
  const Vec3f bad[] = {{20.0f, 0, 0}, {-20.001f, 0, 0}, {0, 1e30f, 0}, {NAN, 0, 0},
                       {0, 0, NAN},   {inf, 0, 0},      {0, -inf, 0}};
  for (const View* view : {&dense.view, &bricked.view}) {
    for (const Vec3f& p : bad) {
      for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear}) {
        const Sample s = view->sample(p, mode);
        EXPECT_EQ(s.status, SampleStatus::kNoField);
        EXPECT_EQ(s.distance, inf);
      }
    }
    // The last voxel is still inside: [origin, origin + dims * voxel_size).
    EXPECT_NE(view->sample({19.99f, 19.99f, 19.99f}).status, SampleStatus::kNoField);
  }
  EXPECT_EQ(View().sample({0, 0, 0}).status, SampleStatus::kNoField);
}

// Every encoding and interpolation the batch dispatches to once gives what single queries give.
TEST(Batch, StridedBatchEqualsSingleQueries) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 12.0f);
  const DenseField field = analytic::sampleField(sceneGrid(), sphere);
  for (const bool dense : {false, true}) {
    SCOPED_TRACE(dense ? "dense" : "bricked");
    const Opened opened = openOrDie(dense ? format::encodeDense(field, "") : format::encodeBricked(field, {}, ""));
    const View& view = opened.view;
    struct Particle {
      float position[3];
      float payload; // makes the stride 16 bytes
    };
    std::vector<Particle> particles;
    for (const Vec3f& p : analytic::randomPoints({-21, -21, -21}, {21, 21, 21}, 5000, 3))
      particles.push_back({{p.x, p.y, p.z}, 1.0f});
    for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear}) {
      std::vector<Sample> out(particles.size());
      view.sampleBatch(particles[0].position, sizeof(Particle), particles.size(), out.data(), mode);
      for (std::size_t n = 0; n < particles.size(); ++n) {
        const Sample one =
            view.sample({particles[n].position[0], particles[n].position[1], particles[n].position[2]}, mode);
        ASSERT_EQ(out[n].status, one.status);
        ASSERT_EQ(out[n].distance, one.distance);
        ASSERT_EQ(out[n].normal.x, one.normal.x);
      }
    }
  }
}

// Queries are const and touch no shared mutable state: concurrent samplers see what one thread sees.
TEST(Threads, ConcurrentQueriesMatchSingleThreaded) {
  const Opened opened = openOrDie(
      format::encodeBricked(analytic::sampleField(sceneGrid(), analytic::sphereField({0, 0, 0}, 12.0f)), {}, ""));
  const auto points = analytic::randomPoints({-20, -20, -20}, {20, 20, 20}, 20000, 8);
  std::vector<Sample> expected(points.size());
  opened.view.sampleBatch(&points[0].x, sizeof(Vec3f), points.size(), expected.data(), Interpolation::kTrilinear);
  std::vector<std::vector<Sample>> results(4, std::vector<Sample>(points.size()));
  std::vector<std::thread> threads;
  for (auto& out : results) {
    threads.emplace_back([&] {
      for (std::size_t n = 0; n < points.size(); ++n)
        out[n] = opened.view.sample(points[n], Interpolation::kTrilinear);
    });
  }
  for (auto& t : threads)
    t.join();
  for (const auto& out : results) {
    for (std::size_t n = 0; n < points.size(); ++n) {
      ASSERT_EQ(out[n].status, expected[n].status);
      ASSERT_EQ(out[n].distance, expected[n].distance);
    }
  }
}

TEST(Writer, SameInputGivesIdenticalBytesAndMetadataSurvives) {
  const DenseField field = analytic::sampleField(sceneGrid(), analytic::sphereField({0, 0, 0}, 9.0f));
  const std::string meta = R"({"tool":"test","mode":"exact"})";
  const EncodeResult a = format::encodeBricked(field, {}, meta);
  const EncodeResult b = format::encodeBricked(field, {}, meta);
  EXPECT_EQ(a.bytes, b.bytes);
  EXPECT_EQ(openOrDie(a).view.metadata(), meta);
  EXPECT_EQ(openOrDie(format::encodeDense(field, "")).view.metadata(), "");
}

TEST(Writer, BrickedIsMuchSmallerThanDenseOnASphere) {
  const DenseField field = analytic::sampleField(analytic::cubeGrid({-32, -32, -32}, 1.0f, 64, 3.0f),
                                                 analytic::sphereField({0, 0, 0}, 25.0f));
  const EncodeResult dense = format::encodeDense(field, "");
  const EncodeResult bricked = format::encodeBricked(field, {}, "");
  const double per_band_voxel = double(bricked.stats.payload_bytes) / double(bricked.stats.band_voxels);
  RecordProperty("bricked_bytes_per_band_voxel", std::to_string(per_band_voxel));
  RecordProperty("dense_over_bricked", std::to_string(double(dense.bytes.size()) / double(bricked.bytes.size())));
  EXPECT_LT(bricked.bytes.size() * 4, dense.bytes.size());
  // The payload is exactly 8 bytes per tile plus 4 bytes per pooled voxel: nothing else hides in it.
  const std::uint64_t tiles = 8 * 8 * 8; // 64^3 voxels in bricks of 8
  EXPECT_EQ(bricked.stats.payload_bytes, 8 * tiles + 4 * 512 * bricked.stats.tiles.brick);
  EXPECT_EQ(bricked.stats.tiles.total(), tiles);
}

TEST(Writer, ReportsProgressAndStopsWhenAsked) {
  const DenseField field =
      analytic::sampleField(analytic::cubeGrid({0, 0, 0}, 1.0f, 32, 2.0f), analytic::sphereField({16, 16, 16}, 8));
  struct Log {
    std::vector<double> fractions;
    double stop_after = 2.0; // never
    static bool report(void* self, double f) {
      auto* log = static_cast<Log*>(self);
      log->fractions.push_back(f);
      return f <= log->stop_after;
    }
  };
  for (bool bricked : {false, true}) {
    SCOPED_TRACE(bricked ? "bricked" : "dense");
    auto encode = [&](Log* log) {
      format::EncodeHooks hooks;
      hooks.progress = {&Log::report, log};
      return bricked ? format::encodeBricked(format::DenseSource(field), {}, "", hooks)
                     : format::encodeDense(format::DenseSource(field), "", hooks);
    };
    Log all;
    ASSERT_TRUE(encode(&all).ok());
    ASSERT_EQ(all.fractions.size(), bricked ? 4u : 32u); // per layer of 8^3 bricks, per z slice
    EXPECT_TRUE(std::is_sorted(all.fractions.begin(), all.fractions.end()));
    EXPECT_EQ(all.fractions.back(), 1.0);
    Log halfway;
    halfway.stop_after = 0.5;
    const EncodeResult stopped = encode(&halfway);
    EXPECT_EQ(stopped.code, format::EncodeError::kCancelled);
    EXPECT_TRUE(stopped.bytes.empty());
    EXPECT_LT(halfway.fractions.size(), all.fractions.size());
  }
}

// Pieces run on several threads, in an order of their own, join into the same bytes.
TEST(Writer, ParallelPiecesGiveTheSameBytes) {
  const DenseField field =
      analytic::sampleField(analytic::cubeGrid({0, 0, 0}, 1.0f, 40, 3.0f), analytic::sphereField({20, 19, 21}, 11));
  format::EncodeHooks threaded;
  threaded.parallel_for = [](std::size_t count, const std::function<void(std::size_t)>& task) {
    std::vector<std::thread> workers;
    for (std::size_t w = 0; w < 3; ++w)
      workers.emplace_back([&, w] {
        for (std::size_t i = count; i-- > 0;) // last piece first
          if (i % 3 == w) task(i);
      });
    for (std::thread& worker : workers)
      worker.join();
  };
  for (std::uint32_t size : {4u, 8u, 16u}) {
    BrickOptions options;
    options.brick_size = size;
    const EncodeResult serial = format::encodeBricked(format::DenseSource(field), options, "{}");
    const EncodeResult parallel = format::encodeBricked(format::DenseSource(field), options, "{}", threaded);
    ASSERT_TRUE(serial.ok() && parallel.ok());
    EXPECT_EQ(serial.bytes, parallel.bytes) << size;
    EXPECT_EQ(serial.stats.tiles.brick, parallel.stats.tiles.brick);
    EXPECT_EQ(serial.stats.max_normal_error_deg, parallel.stats.max_normal_error_deg);
    EXPECT_GT(serial.stats.tiles.brick, 1u); // several layers hold bricks: the pool indices were moved
  }
  EXPECT_EQ(format::encodeDense(format::DenseSource(field), "").bytes,
            format::encodeDense(format::DenseSource(field), "", threaded).bytes);
}

TEST(Writer, RefusesFieldsItCannotWrite) {
  DenseField field =
      analytic::sampleField(analytic::cubeGrid({0, 0, 0}, 1.0f, 8, 2.0f), analytic::sphereField({4, 4, 4}, 2));
  DenseField nan_field = field;
  nan_field.distance[5] = NAN;
  DenseField short_field = field;
  short_field.normal.pop_back();
  DenseField zero_dim = field;
  zero_dim.grid.dims[1] = 0;
  DenseField bad_voxel = field;
  bad_voxel.grid.voxel_size = -1.0f;
  for (const DenseField* f : {&nan_field, &short_field, &zero_dim, &bad_voxel}) {
    const EncodeResult dense = format::encodeDense(*f, "");
    EXPECT_FALSE(dense.ok());
    EXPECT_EQ(dense.code, format::EncodeError::kInvalidField);
    EXPECT_TRUE(dense.bytes.empty());
    EXPECT_FALSE(format::encodeBricked(*f, {}, "").ok());
  }
  BrickOptions odd;
  odd.brick_size = 5;
  const EncodeResult refused = format::encodeBricked(field, odd, "");
  EXPECT_EQ(refused.code, format::EncodeError::kInvalidOptions);
  EXPECT_NE(refused.error.find("brick size"), std::string::npos);
}

} // namespace
} // namespace dng
