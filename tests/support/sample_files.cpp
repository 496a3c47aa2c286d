#include "sample_files.h"

#include "analytic_fields.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace dng {
namespace testing {

using namespace analytic;

std::vector<std::uint8_t> smallBrickedBox() { return smallBrickedBox(R"({"test":"small bricked box"})"); }

std::vector<std::uint8_t> smallBrickedBox(std::string_view metadata) {
  const format::GridGeometry grid = cubeGrid({-12, -12, -12}, 1.0f, 24, 2.0f);
  format::BrickOptions options;
  options.brick_size = 4;
  const auto result =
      format::encodeBricked(sampleField(grid, boxField({0, 0, 0}, {6.25f, 6.25f, 6.25f})), options, metadata);
  if (!result.ok()) throw std::runtime_error(result.error);
  return result.bytes;
}

format::DenseField loweredBoxField() {
  const format::GridGeometry grid = cubeGrid({-12, -12, -12}, 1.0f, 24, 2.0f);
  format::DenseField field = sampleField(grid, boxField({0, 0, 0}, {6.25f, 6.25f, 6.25f}));
  field.accurate = field.distance;
  for (std::uint32_t k = 0; k < grid.dims[2]; ++k)
    for (std::uint32_t j = 0; j < grid.dims[1]; ++j)
      for (std::uint32_t i = 0; i < grid.dims[0]; ++i) {
        float& d = field.distance[grid.index(i, j, k)];
        const Vec3f c = grid.voxelCentre(i, j, k);
        const float lowering = (0.3f + 0.25f * std::sin(1.7f * c.x + 0.9f * c.y - 1.3f * c.z)) * grid.voxel_size;
        if (std::fabs(d) < grid.band) d = std::max(d - lowering, std::min(d, -0.98f * grid.band));
      }
  return field;
}

namespace {

// A field encoded as smallBrickedBox is, bricks of 4, with `metadata`.
std::vector<std::uint8_t> encodedAsTheBox(const format::DenseField& field, const char* metadata) {
  format::BrickOptions options;
  options.brick_size = 4;
  const auto result = format::encodeBricked(field, options, metadata);
  if (!result.ok()) throw std::runtime_error(result.error);
  return result.bytes;
}

std::vector<Vec3f> tiltedNormals(const format::DenseField& field) {
  const format::GridGeometry& g = field.grid;
  std::vector<Vec3f> tilted = field.normal;
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        Vec3f& n = tilted[g.index(i, j, k)];
        if (dot(n, n) == 0.0f) continue;
        const Vec3f c = g.voxelCentre(i, j, k) * (1.0f / g.voxel_size);
        const Vec3f tilt{std::sin(0.7f * c.y + 0.3f), std::sin(0.5f * c.z - 0.8f), std::sin(0.6f * c.x + 1.1f)};
        n = normalizeOrZero(n + tilt * 0.3f);
      }
  return tilted;
}

} // namespace

std::vector<std::uint8_t> smallBrickedBoxLifted() {
  return encodedAsTheBox(loweredBoxField(), R"({"test":"small bricked box, lifted"})");
}

void blurNormalsKeepingTheGradient(format::DenseField* field) {
  field->gradient = field->normal;
  field->normal = tiltedNormals(*field);
}

void addTiltedShading(format::DenseField* field) { field->shading = tiltedNormals(*field); }

std::vector<std::uint8_t> smallBrickedBoxShaded() {
  format::DenseField field = loweredBoxField();
  addTiltedShading(&field);
  return encodedAsTheBox(field, R"({"test":"small bricked box, lifted and shaded"})");
}

void addUnloweredSecondPlanes(format::DenseField* field) {
  const format::GridGeometry& g = field->grid;
  field->second_distance.assign(g.voxelCount(), -std::numeric_limits<float>::infinity());
  field->second_normal.assign(g.voxelCount(), Vec3f{});
  field->second_raise.assign(g.voxelCount(), -1.0f);
  for (std::uint32_t k = 0; k < g.dims[2]; ++k)
    for (std::uint32_t j = 0; j < g.dims[1]; ++j)
      for (std::uint32_t i = 0; i < g.dims[0]; ++i) {
        const std::size_t v = g.index(i, j, k);
        if ((i + j + k) % 3 == 0 || !(std::fabs(field->accurate[v]) < g.band)) continue;
        const bool pair = (i + j + k) % 3 == 2;
        field->second_distance[v] = field->accurate[v] + (pair ? 0.25f * g.voxel_size : 0.0f);
        field->second_normal[v] = field->normal[v];
        if (pair) field->second_raise[v] = field->accurate[v] - field->distance[v];
      }
}

std::vector<std::uint8_t> smallBrickedBoxSecondPlanes() {
  format::DenseField field = loweredBoxField();
  addUnloweredSecondPlanes(&field);
  return encodedAsTheBox(field, R"({"test":"small bricked box, lifted, with second planes"})");
}

std::vector<std::uint8_t> smallBrickedBoxGraded() {
  format::DenseField field = loweredBoxField();
  blurNormalsKeepingTheGradient(&field);
  return encodedAsTheBox(field, R"({"test":"small bricked box, lifted and graded"})");
}

std::vector<std::uint8_t> smallDensePlane() {
  format::GridGeometry grid;
  grid.origin = {0.0f, 0.0f, 0.0f};
  grid.voxel_size = 0.5f;
  grid.dims[0] = 6;
  grid.dims[1] = 5;
  grid.dims[2] = 4;
  grid.band = 1.0f;
  const auto result =
      format::encodeDense(sampleField(grid, planeField({0.2f, 0.1f, 1.0f}, 1.0f)), R"({"test":"small dense plane"})");
  if (!result.ok()) throw std::runtime_error(result.error);
  return result.bytes;
}

std::size_t entryOffset(const std::vector<std::uint8_t>& bytes, std::uint32_t tag) {
  const auto header = peek<format::FileHeader>(bytes, 0);
  for (std::uint32_t s = 0; s < header.section_count; ++s) {
    const std::size_t at = header.section_table_offset + s * sizeof(format::SectionEntry);
    if (peek<format::SectionEntry>(bytes, at).tag == tag) return at;
  }
  return 0;
}

format::SectionEntry entryOf(const std::vector<std::uint8_t>& bytes, std::uint32_t tag) {
  const std::size_t at = entryOffset(bytes, tag);
  return at == 0 ? format::SectionEntry{} : peek<format::SectionEntry>(bytes, at);
}

std::string goldenPath(const char* name) { return std::string(DNG_GOLDEN_DIR) + "/" + name; }

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFileBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

} // namespace testing
} // namespace dng
