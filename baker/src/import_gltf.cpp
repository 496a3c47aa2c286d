// glTF 2.0 (.gltf with external or embedded buffers, .glb) through Debian's tinygltf: the chosen scene's
// mesh nodes with their transforms composed, every triangle primitive (lists, strips, fans; indexed or
// not), other modes reported and skipped. glTF lengths are metres.
#include "dng/baker/import.h"
#include "gltf_accessor.h"

#include <new>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

namespace dng {
namespace baker {

namespace {

namespace fs = std::filesystem;
using Matrix = std::array<double, 16>; // column-major, as glTF writes them

constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k)
        m[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return m;
}

// The node's local matrix: `matrix` when given, else T * R * S (glTF 2.0 §5.25).
Matrix localMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    Matrix m;
    std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
    return m;
  }
  const double x = node.rotation.size() == 4 ? node.rotation[0] : 0.0;
  const double y = node.rotation.size() == 4 ? node.rotation[1] : 0.0;
  const double z = node.rotation.size() == 4 ? node.rotation[2] : 0.0;
  const double w = node.rotation.size() == 4 ? node.rotation[3] : 1.0;
  const double s[3] = {node.scale.size() == 3 ? node.scale[0] : 1.0, node.scale.size() == 3 ? node.scale[1] : 1.0,
                       node.scale.size() == 3 ? node.scale[2] : 1.0};
  const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w), // column 0
                       2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w), // column 1
                       2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
  Matrix m = kIdentity;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row)
      m[c * 4 + row] = r[c * 3 + row] * s[c];
  for (int row = 0; row < 3 && node.translation.size() == 3; ++row)
    m[12 + row] = node.translation[std::size_t(row)];
  return m;
}

double determinant3(const Matrix& m) {
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) + m[8] * (m[1] * m[6] - m[5] * m[2]);
}

Vec3f transformPoint(const Matrix& m, Vec3f p) {
  const double x = p.x, y = p.y, z = p.z;
  return {float(m[0] * x + m[4] * y + m[8] * z + m[12]), float(m[1] * x + m[5] * y + m[9] * z + m[13]),
          float(m[2] * x + m[6] * y + m[10] * z + m[14])};
}

// External files must be regular files inside the glTF's own folder: a buffer URI is data, and data
// must not reach "../../etc/passwd" or another project's assets. tinygltf asks through these callbacks;
// what they refused is remembered so the error can say why.
struct ExternalFiles {
  fs::path folder;             // canonical folder of the .gltf
  std::string outside;         // first URI refused for leaving the folder
  std::string missing;         // first URI that is not a regular file there
  bool missing_exists = false; // it is there, but a folder, device, FIFO or socket
  static bool exists(const std::string& path, void* self) {
    auto* files = static_cast<ExternalFiles*>(self);
    // tinygltf tries the file's folder (absolute: loadModel passes an absolute path), then "./": the
    // working directory is no place to look for a file's data.
    if (fs::path(path).is_relative()) return false;
    std::error_code error;
    const fs::path resolved = fs::weakly_canonical(fs::path(path), error);
    const auto [end, unused] =
        std::mismatch(files->folder.begin(), files->folder.end(), resolved.begin(), resolved.end());
    (void)unused;
    if (error || end != files->folder.end()) {
      if (files->outside.empty()) files->outside = path;
      return false;
    }
    if (!fs::is_regular_file(resolved, error)) {
      if (files->missing.empty()) files->missing = path, files->missing_exists = fs::exists(resolved, error);
      return false;
    }
    return true;
  }
  static std::string expand(const std::string& path, void*) { return path; }
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self) {
    return exists(path, self) && tinygltf::ReadWholeFile(out, err, path, nullptr);
  }
  static bool write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err != nullptr) *err = "dngbake never writes through tinygltf";
    return false;
  }
};

// Images are never decoded: the baker needs geometry only.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

BakeStatus loadModel(const std::string& path, bool binary, tinygltf::Model* out_model, ImportReport* report) {
  std::error_code error;
  const std::string absolute = fs::absolute(path, error).string();
  ExternalFiles files{fs::weakly_canonical(fs::path(absolute).parent_path(), error), {}, {}, false};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(
      {&ExternalFiles::exists, &ExternalFiles::expand, &ExternalFiles::read, &ExternalFiles::write, &files});
  loader.SetImageLoader(&skipImage, nullptr);
  std::string err, warn;
  bool loaded = false;
  try { // tinygltf reports through strings, but its JSON parser and containers may still throw
    loaded = binary ? loader.LoadBinaryFromFile(out_model, &err, &warn, absolute)
                    : loader.LoadASCIIFromFile(out_model, &err, &warn, absolute);
  } catch (const std::bad_alloc&) {
    throw; // out of memory, not a broken file
  } catch (const std::exception& e) {
    err = e.what();
  }
  std::istringstream warnings(warn);
  for (std::string line; std::getline(warnings, line);)
    if (!line.empty()) report->messages.push_back(line);
  if (loaded) return BakeStatus::success();
  while (!err.empty() && (err.back() == '\n' || err.back() == ' '))
    err.pop_back();
  if (!files.outside.empty())
    return BakeStatus::failure(BakeError::kInvalidInput,
                               "a buffer URI points outside the file's folder: '" + files.outside + "'");
  if (!files.missing.empty())
    return BakeStatus::failure(BakeError::kIo,
                               std::string(files.missing_exists ? "a buffer file is not a regular file: '"
                                                                : "a buffer file does not exist: '") +
                                   files.missing + "'");
  return BakeStatus::failure(BakeError::kInvalidInput, "tinygltf could not read it: " + err);
}

// Required extensions that change only how things look are harmless to a baker; one that changes
// geometry and is not handled here must stop the bake rather than bake something else.
BakeStatus checkRequiredExtensions(const tinygltf::Model& model) {
  static const char* const kHarmless[] = {"KHR_mesh_quantization", "KHR_materials_", "KHR_texture_",
                                          "KHR_lights_punctual", "EXT_texture_"};
  for (const std::string& name : model.extensionsRequired) {
    const bool harmless = std::any_of(std::begin(kHarmless), std::end(kHarmless), [&](const char* prefix) {
      return name.compare(0, std::strlen(prefix), prefix) == 0;
    });
    if (!harmless)
      return BakeStatus::failure(
          BakeError::kUnsupported,
          "required glTF extension " + name + " is not supported" +
              (name == "KHR_draco_mesh_compression" ? " (Draco-compressed meshes: export without Draco)" : ""));
  }
  return BakeStatus::success();
}

std::string nameOr(const std::string& name, const char* prefix, int index) {
  return name.empty() ? prefix + std::to_string(index) : name;
}

// Triangle k of a primitive's vertex sequence, as the spec defines lists, strips and fans.
void appendTriangles(int mode, const std::vector<std::uint32_t>& order, std::uint32_t base, bool flip,
                     TriangleSoup* soup, std::uint64_t* io_count) {
  const std::size_t n = order.size();
  const std::size_t count = mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : n >= 3 ? n - 2 : 0;
  for (std::size_t k = 0; k < count; ++k) {
    std::uint32_t a, b, c;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      a = order[3 * k], b = order[3 * k + 1], c = order[3 * k + 2];
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      a = order[k], b = order[k + 1 + k % 2], c = order[k + 2 - k % 2];
    } else { // fan
      a = order[k + 1], b = order[k + 2], c = order[0];
    }
    if (flip) std::swap(b, c); // a mirroring transform reverses the winding (glTF 2.0 §3.7.4)
    soup->triangles.push_back({base + a, base + b, base + c});
  }
  *io_count += count;
}

class SceneWalker {
public:
  SceneWalker(const tinygltf::Model& model, const ImportOptions& options, TriangleSoup* soup, ImportReport* report)
      : model_(model), options_(options), soup_(soup), report_(report) {}

  BakeStatus walk(int node_index, const Matrix& parent, bool selected, int depth) {
    if (node_index < 0 || std::size_t(node_index) >= model_.nodes.size())
      return BakeStatus::failure(BakeError::kInvalidInput, "node " + std::to_string(node_index) + " does not exist");
    if (!on_path_.insert(node_index).second || depth > 1000)
      return BakeStatus::failure(BakeError::kInvalidInput,
                                 "the node hierarchy is not a tree (node " + std::to_string(node_index) + " recurs)");
    const tinygltf::Node& node = model_.nodes[std::size_t(node_index)];
    const Matrix world = multiply(parent, localMatrix(node));
    if (!selected && !node.name.empty() &&
        std::find(options_.nodes.begin(), options_.nodes.end(), node.name) != options_.nodes.end()) {
      selected = true;
      report_->matched_nodes.push_back(node.name);
    }
    BakeStatus status;
    if (selected && node.mesh >= 0) status = addMesh(node_index, node, world);
    for (std::size_t c = 0; c < node.children.size() && status.ok(); ++c)
      status = walk(node.children[c], world, selected, depth + 1);
    on_path_.erase(node_index);
    return status;
  }

private:
  BakeStatus addMesh(int node_index, const tinygltf::Node& node, const Matrix& world) {
    if (std::size_t(node.mesh) >= model_.meshes.size())
      return BakeStatus::failure(BakeError::kInvalidInput, "node " + std::to_string(node_index) + " refers to mesh " +
                                                               std::to_string(node.mesh) + ", which does not exist");
    const tinygltf::Mesh& mesh = model_.meshes[std::size_t(node.mesh)];
    NodeImport entry;
    entry.name = nameOr(node.name, "#", node_index);
    entry.mesh = nameOr(mesh.name, "#", node.mesh);
    entry.transform = world;
    const bool flip = determinant3(world) < 0.0;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const BakeStatus status = addPrimitive(mesh.primitives[p], world, flip, entry, p);
      if (!status.ok())
        return BakeStatus::failure(status.code,
                                   "mesh " + entry.mesh + " primitive " + std::to_string(p) + ": " + status.message);
    }
    report_->triangles += entry.triangles;
    report_->skipped_primitives += entry.skipped_primitives;
    report_->nodes.push_back(entry);
    return BakeStatus::success();
  }

  BakeStatus addPrimitive(const tinygltf::Primitive& primitive, const Matrix& world, bool flip, NodeImport& entry,
                          std::size_t index) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      ++entry.skipped_primitives;
      static const char* const kModes[] = {"points", "lines", "line loop", "line strip"};
      report_->messages.push_back("node " + entry.name + ", mesh " + entry.mesh + " primitive " +
                                  std::to_string(index) + ": " +
                                  (mode >= 0 && mode < 4 ? kModes[mode] : "unknown mode") + " skipped (not triangles)");
      return BakeStatus::success();
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end())
      return BakeStatus::failure(BakeError::kInvalidInput, "has no POSITION attribute");
    BakeStatus status = readPositions(model_, position->second, &positions_);
    if (!status.ok()) return status;
    if (primitive.indices >= 0) {
      status = readIndices(model_, primitive.indices, positions_.size(), &order_);
      if (!status.ok()) return status;
    } else {
      order_.resize(positions_.size());
      for (std::size_t i = 0; i < order_.size(); ++i)
        order_[i] = std::uint32_t(i);
    }
    if (soup_->vertices.size() + positions_.size() > std::numeric_limits<std::uint32_t>::max())
      return BakeStatus::failure(BakeError::kInvalidInput, "more than 2^32 vertices");
    const auto base = std::uint32_t(soup_->vertices.size());
    for (const Vec3f& p : positions_)
      soup_->vertices.push_back(transformPoint(world, p));
    appendTriangles(mode, order_, base, flip, soup_, &entry.triangles);
    return BakeStatus::success();
  }

  const tinygltf::Model& model_;
  const ImportOptions& options_;
  TriangleSoup* soup_;
  ImportReport* report_;
  std::set<int> on_path_; // nodes between the root and here: a node met again is a cycle
  std::vector<Vec3f> positions_;
  std::vector<std::uint32_t> order_;
};

BakeStatus chooseScene(const tinygltf::Model& model, const ImportOptions& options, int* out_scene) {
  if (model.scenes.empty()) return BakeStatus::failure(BakeError::kInvalidInput, "the file has no scene");
  if (options.scene >= 0 && std::size_t(options.scene) >= model.scenes.size())
    return BakeStatus::failure(BakeError::kBadOption, "--scene " + std::to_string(options.scene) + ": the file has " +
                                                          std::to_string(model.scenes.size()) + " scenes");
  *out_scene = options.scene >= 0                                                                 ? options.scene
               : model.defaultScene >= 0 && std::size_t(model.defaultScene) < model.scenes.size() ? model.defaultScene
                                                                                                  : 0;
  return BakeStatus::success();
}

} // namespace

BakeStatus importGltf(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                      ImportReport* out_report) {
  out_report->importer = "tinygltf";
  out_report->units = LengthUnit::kMetre; // glTF 2.0 §3.2: units for all linear distances are metres
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return BakeStatus::failure(BakeError::kIo, "no such file");
  tinygltf::Model model;
  const bool binary = out_report->format == "glb";
  BakeStatus status = loadModel(path, binary, &model, out_report);
  if (!status.ok() || !(status = checkRequiredExtensions(model)).ok()) return status;
  int scene = 0;
  if (!(status = chooseScene(model, options, &scene)).ok()) return status;
  SceneWalker walker(model, options, io_soup, out_report);
  for (const int root : model.scenes[std::size_t(scene)].nodes) {
    if (!(status = walker.walk(root, kIdentity, options.nodes.empty(), 0)).ok()) return status;
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
