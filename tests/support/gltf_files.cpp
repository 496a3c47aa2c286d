// Writing glTF test files (gltf_files.h).
#include "gltf_files.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace dng {
namespace testing {

namespace {

void pad4(std::vector<std::uint8_t>* bytes, std::uint8_t fill) {
  while (bytes->size() % 4 != 0)
    bytes->push_back(fill);
}

// Appends raw bytes as a buffer view plus an accessor; returns the accessor's index.
int addAccessor(nlohmann::json& json, std::vector<std::uint8_t>* bin, const void* data, std::size_t bytes,
                std::size_t count, int component_type, const char* type) {
  pad4(bin, 0);
  const std::size_t offset = bin->size();
  bin->resize(offset + bytes);
  std::memcpy(bin->data() + offset, data, bytes);
  json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  json["accessors"].push_back({{"bufferView", json["bufferViews"].size() - 1},
                               {"componentType", component_type},
                               {"count", count},
                               {"type", type}});
  return int(json["accessors"].size() - 1);
}

int addIndices(nlohmann::json& json, std::vector<std::uint8_t>* bin, const GltfPrimitive& p) {
  if (p.index_type == 5121) {
    std::vector<std::uint8_t> v(p.indices.begin(), p.indices.end());
    return addAccessor(json, bin, v.data(), v.size(), v.size(), 5121, "SCALAR");
  }
  if (p.index_type == 5123) {
    std::vector<std::uint16_t> v(p.indices.begin(), p.indices.end());
    return addAccessor(json, bin, v.data(), v.size() * 2, v.size(), 5123, "SCALAR");
  }
  return addAccessor(json, bin, p.indices.data(), p.indices.size() * 4, p.indices.size(), 5125, "SCALAR");
}

nlohmann::json nodeJson(const GltfNode& n) {
  nlohmann::json node = nlohmann::json::object();
  if (!n.name.empty()) node["name"] = n.name;
  if (n.mesh >= 0) node["mesh"] = n.mesh;
  if (!n.children.empty()) node["children"] = n.children;
  if (!n.translation.empty()) node["translation"] = n.translation;
  if (!n.rotation.empty()) node["rotation"] = n.rotation;
  if (!n.scale.empty()) node["scale"] = n.scale;
  if (!n.matrix.empty()) node["matrix"] = n.matrix;
  return node;
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t n = (std::uint32_t(bytes[i]) << 16) | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) |
                            (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

void appendU32(std::vector<std::uint8_t>* out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b)
    out->push_back(std::uint8_t(v >> (8 * b)));
}

} // namespace

GltfFile buildGltf(const GltfScene& scene) {
  GltfFile file;
  nlohmann::json& json = file.json;
  json["asset"] = {{"version", "2.0"}, {"generator", "dngrid tests"}};
  json["bufferViews"] = nlohmann::json::array();
  json["accessors"] = nlohmann::json::array();
  json["meshes"] = nlohmann::json::array();
  for (const std::vector<GltfPrimitive>& mesh : scene.meshes) {
    nlohmann::json primitives = nlohmann::json::array();
    for (const GltfPrimitive& p : mesh) {
      nlohmann::json prim;
      prim["attributes"]["POSITION"] =
          addAccessor(json, &file.bin, p.positions.data(), p.positions.size() * 12, p.positions.size(), 5126, "VEC3");
      if (!p.indices.empty()) prim["indices"] = addIndices(json, &file.bin, p);
      prim["mode"] = p.mode;
      primitives.push_back(prim);
    }
    json["meshes"].push_back({{"primitives", primitives}});
  }
  json["nodes"] = nlohmann::json::array();
  for (const GltfNode& n : scene.nodes)
    json["nodes"].push_back(nodeJson(n));
  json["scenes"] = nlohmann::json::array();
  for (const std::vector<int>& roots : scene.scenes)
    json["scenes"].push_back({{"nodes", roots}});
  json["scene"] = scene.default_scene;
  pad4(&file.bin, 0);
  json["buffers"] = nlohmann::json::array({{{"byteLength", file.bin.size()}}});
  return file;
}

void saveGltf(GltfFile file, const std::string& path, GltfStorage storage) {
  nlohmann::json& buffer = file.json["buffers"][0];
  if (storage == GltfStorage::kExternalBin && !buffer.contains("uri")) {
    const std::filesystem::path bin_path = std::filesystem::path(path).replace_extension(".bin");
    std::ofstream(bin_path, std::ios::binary)
        .write(reinterpret_cast<const char*>(file.bin.data()), std::streamsize(file.bin.size()));
    buffer["uri"] = bin_path.filename().string();
  } else if (storage == GltfStorage::kEmbedded) {
    buffer["uri"] = "data:application/octet-stream;base64," + base64(file.bin);
  }
  std::ofstream out(path, std::ios::binary);
  if (storage != GltfStorage::kBinaryGlb) {
    out << file.json.dump(1);
    return;
  }
  std::vector<std::uint8_t> text;
  const std::string dumped = file.json.dump();
  text.assign(dumped.begin(), dumped.end());
  pad4(&text, ' ');
  std::vector<std::uint8_t> glb;
  appendU32(&glb, 0x46546C67u); // "glTF"
  appendU32(&glb, 2);
  appendU32(&glb, std::uint32_t(12 + 8 + text.size() + 8 + file.bin.size()));
  appendU32(&glb, std::uint32_t(text.size()));
  appendU32(&glb, 0x4E4F534Au); // JSON
  glb.insert(glb.end(), text.begin(), text.end());
  appendU32(&glb, std::uint32_t(file.bin.size()));
  appendU32(&glb, 0x004E4942u); // BIN
  glb.insert(glb.end(), file.bin.begin(), file.bin.end());
  out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
}

void writeOff(const std::vector<Vec3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
              const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  out << "OFF\n" << vertices.size() << ' ' << triangles.size() << " 0\n";
  for (const Vec3f& v : vertices)
    out << v.x << ' ' << v.y << ' ' << v.z << '\n';
  for (const auto& t : triangles)
    out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

} // namespace testing
} // namespace dng
