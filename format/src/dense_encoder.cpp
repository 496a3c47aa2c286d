// Field checks shared by both encoders, the GRID section, and the dense encoding.
#include "dng/format/writer.h"
#include "grid_section.h"

#include <cmath>

namespace dng {
namespace format {

std::string checkField(const DenseField& field) {
  const GridGeometry& g = field.grid;
  if (!isLittleEndianHost()) return "this host is big-endian; .dng files are little-endian only";
  if (!std::isfinite(g.origin.x) || !std::isfinite(g.origin.y) || !std::isfinite(g.origin.z))
    return "grid origin is not finite";
  if (!(g.voxel_size > 0.0f) || !std::isfinite(g.voxel_size)) return "voxel size must be finite and > 0";
  if (!(g.band > 0.0f) || !std::isfinite(g.band)) return "band must be finite and > 0";
  for (std::uint32_t d : g.dims) {
    if (d == 0) return "every grid dimension must be at least 1";
  }
  const float limit = 1e18f; // readers refuse larger magnitudes (docs/FORMAT.md, V12)
  if (std::fabs(g.origin.x) > limit || std::fabs(g.origin.y) > limit || std::fabs(g.origin.z) > limit ||
      g.voxel_size > limit || g.voxel_size < 1.0f / limit || g.band > limit)
    return "grid origin, voxel size or band is outside [1e-18, 1e18]";
  for (std::uint32_t d : g.dims) {
    if (d > (1u << 24)) return "a grid dimension exceeds 2^24 voxels";
  }
  if (field.distance.size() != g.voxelCount() || field.normal.size() != g.voxelCount())
    return "distance and normal arrays must hold one entry per voxel";
  for (std::size_t v = 0; v < field.distance.size(); ++v) {
    const Vec3f n = field.normal[v];
    if (!(std::fabs(field.distance[v]) <= limit) || !std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      return "voxel " + std::to_string(v) + " holds a non-finite distance or normal";
  }
  return {};
}

GridSection makeGridSection(const GridGeometry& g, Encoding encoding) {
  GridSection s{};
  s.origin[0] = g.origin.x;
  s.origin[1] = g.origin.y;
  s.origin[2] = g.origin.z;
  s.voxel_size = g.voxel_size;
  for (int a = 0; a < 3; ++a)
    s.dims[a] = g.dims[a];
  s.band = g.band;
  s.encoding = std::uint32_t(encoding);
  return s;
}

void addCommonSections(ContainerBuilder& builder, const GridSection& grid, std::string_view metadata_json) {
  builder.addSection(kTagGrid, kSectionRequired, &grid, sizeof grid);
  if (!metadata_json.empty()) builder.addSection(kTagMetadata, 0, metadata_json.data(), metadata_json.size());
}

EncodeResult encodeDense(const DenseField& field, std::string_view metadata_json) {
  EncodeResult result;
  result.error = checkField(field);
  if (!result.ok()) return result;

  std::vector<DenseVoxel> voxels(field.distance.size());
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    const Vec3f n = normalizeOrZero(field.normal[v]); // readers rely on unit-or-zero normals
    voxels[v] = {field.distance[v], {n.x, n.y, n.z}};
    if (std::fabs(field.distance[v]) < field.grid.band) ++result.stats.band_voxels;
  }
  ContainerBuilder builder;
  addCommonSections(builder, makeGridSection(field.grid, Encoding::kDense), metadata_json);
  builder.addSection(kTagDense, kSectionRequired, voxels.data(), voxels.size() * sizeof(DenseVoxel));
  result.stats.payload_bytes = voxels.size() * sizeof(DenseVoxel);
  result.bytes = builder.finish();
  return result;
}

} // namespace format
} // namespace dng
