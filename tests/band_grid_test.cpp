// The baker's sparse working store (band_grid.h): it holds exactly the band, signs everything else
// by flood fill, never hints a brick wrongly, and its blur gives what blurring the whole grid gives.
#include "mesh_soup.h"
#include "stages.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace dng {
namespace baker {
namespace {

using testing::soupOf;

// Signed distance to the axis-aligned box [-half, half]^3, exact.
float boxDistance(Vec3f p, float half) {
  const Vec3f q{std::fabs(p.x) - half, std::fabs(p.y) - half, std::fabs(p.z) - half};
  const Vec3f outside{std::max(q.x, 0.0f), std::max(q.y, 0.0f), std::max(q.z, 0.0f)};
  return length(outside) + std::min(std::max({q.x, q.y, q.z}), 0.0f);
}

// Every voxel of the grid, read through the FieldSource interface one z slice at a time.
format::DenseField readAll(const BandGrid& band) {
  const format::GridGeometry& g = band.grid();
  format::DenseField field;
  field.reset(g);
  format::VoxelBox slice;
  slice.hi[0] = g.dims[0];
  slice.hi[1] = g.dims[1];
  const std::size_t per_slice = std::size_t(g.dims[0]) * g.dims[1];
  if (band.hasShading()) field.shading.resize(field.normal.size());
  for (std::uint32_t k = 0; k < g.dims[2]; ++k) {
    slice.lo[2] = k;
    slice.hi[2] = k + 1;
    band.read(slice, &field.distance[k * per_slice], &field.normal[k * per_slice]);
    if (band.hasShading()) band.readShading(slice, &field.shading[k * per_slice]);
  }
  return field;
}

class BoxBand : public ::testing::Test {
protected:
  void SetUp() override {
    soup_ = soupOf(testing::boxMesh({0, 0, 0}, {1, 1, 1}));
    BakeOptions options;
    options.resolution = 96;
    options.band_voxels = 2.5f;
    std::vector<std::string> warnings;
    ASSERT_TRUE(placeGrid(checkMesh(soup_), options, &grid_, &warnings).ok());
    band_ = std::make_unique<BandGrid>(grid_);
    ASSERT_TRUE(computeDistanceField(soup_, nullptr, nullptr, nullptr, band_.get()).ok());
  }
  TriangleSoup soup_;
  format::GridGeometry grid_;
  std::unique_ptr<BandGrid> band_;
};

TEST_F(BoxBand, HoldsExactlyTheVoxelsWithinTheBandAndSignsTheRest) {
  const format::DenseField field = readAll(*band_);
  const float h = grid_.voxel_size, band = grid_.band;
  std::uint64_t in_band = 0, far_inside = 0;
  for (std::uint32_t k = 0; k < grid_.dims[2]; ++k)
    for (std::uint32_t j = 0; j < grid_.dims[1]; ++j)
      for (std::uint32_t i = 0; i < grid_.dims[0]; ++i) {
        const float exact = boxDistance(grid_.voxelCentre(i, j, k), 1.0f);
        const float stored = field.distance[grid_.index(i, j, k)];
        in_band += std::fabs(stored) < band ? 1 : 0;
        // Voxels within a rounding error of the band's edge may fall either way.
        if (std::fabs(exact) < band - 1e-3f * h) {
          ASSERT_NEAR(stored, exact, 1e-3f * h) << i << " " << j << " " << k;
        } else if (std::fabs(exact) > band + 1e-3f * h) {
          ASSERT_EQ(stored, exact < 0.0f ? -band : band) << i << " " << j << " " << k;
          far_inside += exact < 0.0f ? 1 : 0;
        }
      }
  EXPECT_EQ(band_->bandVoxels(), in_band);
  EXPECT_GT(far_inside, 100000u); // the flood fill reached the box's interior
  // Sparse: the blocks cover well under half of the grid.
  EXPECT_LT(band_->blockCount() * VoxelBlock::kVoxels, grid_.voxelCount() / 2);
}

TEST_F(BoxBand, FarHintsNeverContradictTheVoxels) {
  const format::DenseField field = readAll(*band_);
  for (std::uint32_t size : {4u, 8u, 16u}) {
    std::uint64_t hinted = 0;
    for (std::uint32_t z = 0; z < grid_.dims[2]; z += size)
      for (std::uint32_t y = 0; y < grid_.dims[1]; y += size)
        for (std::uint32_t x = 0; x < grid_.dims[0]; x += size) {
          format::VoxelBox box;
          box.lo[0] = x, box.lo[1] = y, box.lo[2] = z;
          for (int a = 0; a < 3; ++a)
            box.hi[a] = std::min(box.lo[a] + size, grid_.dims[a]);
          const format::FarHint hint = band_->farHint(box);
          if (hint == format::FarHint::kUnknown) continue;
          ++hinted;
          const float expected = hint == format::FarHint::kFarInside ? -grid_.band : grid_.band;
          for (std::uint32_t k = box.lo[2]; k < box.hi[2]; ++k)
            for (std::uint32_t j = box.lo[1]; j < box.hi[1]; ++j)
              for (std::uint32_t i = box.lo[0]; i < box.hi[0]; ++i)
                ASSERT_EQ(field.distance[grid_.index(i, j, k)], expected) << size << ": " << i << " " << j << " " << k;
        }
    EXPECT_GT(hinted, 0u) << size;
  }
}

TEST_F(BoxBand, EncodesToTheSameBytesAsItsDenseCopy) {
  const format::DenseField field = readAll(*band_);
  for (std::uint32_t size : {4u, 8u, 16u}) {
    format::BrickOptions options;
    options.brick_size = size;
    const format::EncodeResult sparse = format::encodeBricked(*band_, options, "{}");
    const format::EncodeResult dense = format::encodeBricked(field, options, "{}");
    ASSERT_TRUE(sparse.ok() && dense.ok()) << sparse.error << dense.error;
    EXPECT_EQ(sparse.bytes, dense.bytes) << size;
    EXPECT_EQ(sparse.stats.band_voxels, band_->bandVoxels());
  }
  EXPECT_EQ(format::encodeDense(*band_, "").bytes, format::encodeDense(field, "").bytes);
}

// ---- The blur: sparse against a straightforward dense reference ----

constexpr std::uint32_t kDim = 20;

// A grid whose every voxel is in the band, outside, with the exact normal +z.
std::unique_ptr<BandGrid> allBand() {
  format::GridGeometry g;
  g.voxel_size = 1.0f;
  g.band = 100.0f;
  g.dims[0] = g.dims[1] = g.dims[2] = kDim;
  auto band = std::make_unique<BandGrid>(g);
  std::vector<BlockKey> keys;
  for (int z = 0; z * 8 < int(kDim); ++z)
    for (int y = 0; y * 8 < int(kDim); ++y)
      for (int x = 0; x * 8 < int(kDim); ++x)
        keys.push_back({x, y, z});
  band->addBlocks(keys);
  for (const VoxelBlock& block : band->blocks())
    for (int n = 0; n < VoxelBlock::kVoxels; ++n) {
      block.distance[n] = 1.0f;
      block.setNormal(n, {0, 0, 1});
    }
  band->finishBand();
  return band;
}

// The tent blur of the paper's method, written the obvious way over every voxel of a dense grid.
template <class T>
std::vector<T> denseBlur(const std::vector<SurfaceVoxel>& surface, std::vector<T> values, std::uint32_t radius,
                         std::uint32_t rounds) {
  auto index = [](int i, int j, int k) { return (std::size_t(k) * kDim + j) * kDim + i; };
  const std::vector<T> start = values;
  for (std::uint32_t round = 0; round < rounds; ++round) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<T> next(values.size());
      for (int k = 0; k < int(kDim); ++k)
        for (int j = 0; j < int(kDim); ++j)
          for (int i = 0; i < int(kDim); ++i) {
            T sum{};
            float weights = 0.0f;
            for (int o = -int(radius); o <= int(radius); ++o) {
              int at[3] = {i, j, k};
              at[axis] += o;
              if (at[axis] < 0 || at[axis] >= int(kDim)) continue;
              const float w = 1.0f - float(std::abs(o)) / float(radius + 1);
              sum = sum + values[index(at[0], at[1], at[2])] * w;
              weights += w;
            }
            next[index(i, j, k)] = sum * (1.0f / weights);
          }
      values.swap(next);
    }
    for (const SurfaceVoxel& s : surface) {
      const std::size_t v = index(s.ijk[0], s.ijk[1], s.ijk[2]);
      values[v] = start[v];
    }
  }
  return values;
}

// Surface voxels with random unit normals, some on the grid's faces so edge weights matter.
std::vector<SurfaceVoxel> randomSurface(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coordinate(0, int(kDim) - 1);
  std::normal_distribution<float> gauss;
  std::vector<SurfaceVoxel> surface;
  for (int n = 0; n < 12; ++n) {
    SurfaceVoxel s{{coordinate(rng), coordinate(rng), n < 3 ? 0 : coordinate(rng)}, {}};
    s.normal = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)});
    const bool repeated =
        std::any_of(surface.begin(), surface.end(), [&](const SurfaceVoxel& t) { return t.ijk == s.ijk; });
    if (!repeated) surface.push_back(s);
  }
  return surface;
}

TEST(SparseBlur, NormalBlurEqualsBlurringTheWholeGrid) {
  const std::vector<SurfaceVoxel> surface = randomSurface(3);
  auto band = allBand();
  ASSERT_TRUE(blurNormals(surface, 2, 2, band.get()).ok());
  std::vector<Vec3f> start(kDim * kDim * kDim);
  for (const SurfaceVoxel& s : surface)
    start[(std::size_t(s.ijk[2]) * kDim + s.ijk[1]) * kDim + s.ijk[0]] = s.normal;
  const std::vector<Vec3f> expected = denseBlur(surface, start, 2, 2);
  const format::DenseField field = readAll(*band);
  int blurred = 0;
  for (std::size_t v = 0; v < expected.size(); ++v) {
    const Vec3f n = normalizeOrZero(expected[v]);
    const bool reached = dot(n, n) > 0.0f;
    const Vec3f want = reached ? n : Vec3f{0, 0, 1}; // beyond the blur the exact normal stays
    ASSERT_NEAR(field.shading[v].x, want.x, 1e-5f) << v;
    ASSERT_NEAR(field.shading[v].y, want.y, 1e-5f) << v;
    ASSERT_NEAR(field.shading[v].z, want.z, 1e-5f) << v;
    ASSERT_EQ(field.normal[v].z, 1.0f) << v; // the planes keep the exact normal
    blurred += reached ? 1 : 0;
  }
  EXPECT_GT(blurred, 1000); // 2 rounds of radius 2 reach 4 voxels around each of 12
}

TEST(SparseBlur, PotentialGradientEqualsTheDenseOne) {
  const std::vector<SurfaceVoxel> surface = randomSurface(5);
  auto band = allBand();
  ASSERT_TRUE(potentialNormals(surface, 3, 2, band.get()).ok());
  std::vector<float> start(kDim * kDim * kDim, 0.0f);
  auto index = [](int i, int j, int k) { return (std::size_t(k) * kDim + j) * kDim + i; };
  for (const SurfaceVoxel& s : surface)
    start[index(s.ijk[0], s.ijk[1], s.ijk[2])] = 1.0f;
  const std::vector<float> p = denseBlur(surface, start, 3, 2);
  const format::DenseField field = readAll(*band);
  int oriented = 0;
  for (int k = 1; k + 1 < int(kDim); ++k)
    for (int j = 1; j + 1 < int(kDim); ++j)
      for (int i = 1; i + 1 < int(kDim); ++i) {
        const Vec3f downhill{p[index(i - 1, j, k)] - p[index(i + 1, j, k)],
                             p[index(i, j - 1, k)] - p[index(i, j + 1, k)],
                             p[index(i, j, k - 1)] - p[index(i, j, k + 1)]};
        Vec3f want{0, 0, 1};
        if (length(downhill) > 1e-4f) {
          want = normalizeOrZero(downhill);
          if (want.z < 0.0f) want = want * -1.0f; // into the exact normal's (+z) hemisphere
          ++oriented;
        }
        const Vec3f got = field.shading[index(i, j, k)];
        ASSERT_LT(angleDegrees(got, want), 1e-3) << i << " " << j << " " << k;
        ASSERT_EQ(field.normal[index(i, j, k)].z, 1.0f); // the planes keep the exact normal
      }
  EXPECT_GT(oriented, 1000);
}

TEST(GridLimits, OnlyDenseFilesAreCappedInVoxels) {
  MeshReport mesh;
  mesh.bounds_min = {0, 0, 0};
  mesh.bounds_max = {1, 1, 1};
  BakeOptions options;
  options.resolution = 1024; // about 10^9 voxels: fine sparse, far too big dense
  format::GridGeometry grid;
  std::vector<std::string> warnings;
  EXPECT_TRUE(placeGrid(mesh, options, &grid, &warnings).ok());
  EXPECT_GT(grid.voxelCount(), std::size_t(1) << 27);
  options.encoding = format::Encoding::kDense;
  const BakeStatus dense = placeGrid(mesh, options, &grid, &warnings);
  EXPECT_EQ(dense.code, BakeError::kBadOption);
  EXPECT_NE(dense.message.find("dense"), std::string::npos) << dense.message;
}

// A grid far from the origin for its voxel size has few float positions per voxel: the bake says so
// (a unit box at 10^5 baked at resolution 128 has floats 0.9 voxel apart); near the origin it does not.
TEST(GridLimits, AGridFarFromTheOriginForItsVoxelIsWarnedAbout) {
  MeshReport mesh;
  BakeOptions options;
  format::GridGeometry grid;
  for (const float at : {0.0f, 1e3f, 1e5f}) {
    mesh.bounds_min = {at, at, at};
    mesh.bounds_max = {at + 1, at + 1, at + 1};
    std::vector<std::string> warnings;
    ASSERT_TRUE(placeGrid(mesh, options, &grid, &warnings).ok());
    const bool warned = std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
      return w.find("far from the origin for its voxel size") != std::string::npos;
    });
    EXPECT_EQ(warned, at == 1e5f) << "at " << at;
  }
}

} // namespace
} // namespace baker
} // namespace dng
