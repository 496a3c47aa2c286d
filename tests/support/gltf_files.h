// glTF 2.0 files written by the tests themselves: a small scene description becomes JSON plus one
// binary buffer, saved as .gltf with an external .bin, as .gltf with the buffer embedded as a data URI,
// or as a binary .glb. Tests may edit the JSON in between to make broken files.
#pragma once

#include "dng/format/vec3.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dng {
namespace testing {

struct GltfPrimitive {
  std::vector<Vec3f> positions;
  std::vector<std::uint32_t> indices; ///< empty: not indexed
  int index_type = 5123;              ///< 5121 unsigned byte, 5123 unsigned short, 5125 unsigned int
  int mode = 4;                       ///< 0 points, 1 lines, 4 triangles, 5 strip, 6 fan
};

struct GltfNode {
  std::string name;
  int mesh = -1;
  std::vector<int> children;
  std::vector<double> translation, rotation, scale, matrix; ///< empty: absent
};

struct GltfScene {
  std::vector<std::vector<GltfPrimitive>> meshes;
  std::vector<GltfNode> nodes;
  std::vector<std::vector<int>> scenes; ///< root nodes of each scene
  int default_scene = 0;
};

struct GltfFile {
  nlohmann::json json;
  std::vector<std::uint8_t> bin;
};

enum class GltfStorage { kExternalBin, kEmbedded, kBinaryGlb };

/// The scene as glTF JSON (asset, scenes, nodes, meshes, accessors, buffer views, one buffer) and the
/// buffer's bytes. Positions are float VEC3, indices of each primitive's index_type.
GltfFile buildGltf(const GltfScene& scene);

/// Writes `file` to `path`. kExternalBin also writes the buffer beside it as "<stem>.bin" and points
/// the buffer's uri there (unless the JSON already has a uri); kEmbedded uses a base64 data URI.
void saveGltf(GltfFile file, const std::string& path, GltfStorage storage);

/// A mesh as ASCII OFF with round-trip float precision.
void writeOff(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
              const std::string& path);

} // namespace testing
} // namespace dng
