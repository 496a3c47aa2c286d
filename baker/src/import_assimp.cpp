// FBX, COLLADA, 3DS, Blender and the rest of assimp's formats: every mesh node of the scene with its
// transforms composed, polygons triangulated by assimp, points and lines reported and skipped.
// OpenMesh's formats and glTF have importers of their own (import_inputs.cpp picks them first).
// assimp's readers crash on some malformed files (fuzzing found a one-bit change to an ASE file), and
// there are too many to guard one by one: importAssimp runs them in a child process (import_isolated.cpp).
#include "dng/baker/import.h"

#include "stages.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <new>

namespace dng {
namespace baker {

namespace {

// FBX records centimetres per unit as "UnitScaleFactor"; assimp passes it on as scene metadata.
LengthUnit fbxUnit(const aiScene& scene, ImportReport* report) {
  double factor = 0.0;
  if (scene.mMetaData == nullptr || !scene.mMetaData->Get("UnitScaleFactor", factor)) {
    float f = 0.0f;
    if (scene.mMetaData == nullptr || !scene.mMetaData->Get("UnitScaleFactor", f)) return LengthUnit::kUnknown;
    factor = f;
  }
  const struct {
    double cm;
    LengthUnit unit;
  } known[] = {{1.0, LengthUnit::kCentimetre}, {100.0, LengthUnit::kMetre}, {0.1, LengthUnit::kMillimetre},
               {2.54, LengthUnit::kInch},      {30.48, LengthUnit::kFoot},  {100000.0, LengthUnit::kKilometre}};
  for (const auto& k : known)
    if (std::abs(factor - k.cm) <= 1e-6 * k.cm) return k.unit;
  report->messages.push_back("FBX UnitScaleFactor " + std::to_string(factor) + " cm is no unit dngbake names");
  return LengthUnit::kUnknown;
}

std::array<double, 16> columnMajor(const aiMatrix4x4& m) {
  return {m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4};
}

class NodeWalker {
public:
  NodeWalker(const aiScene& scene, const ImportOptions& options, TriangleSoup* soup, ImportReport* report)
      : scene_(scene), options_(options), soup_(soup), report_(report) {}

  BakeStatus walk(const aiNode& node, const aiMatrix4x4& parent, bool selected, int depth) {
    if (depth > 1000) return BakeStatus::failure(BakeError::kInvalidInput, "the node hierarchy is too deep");
    const aiMatrix4x4 world = parent * node.mTransformation;
    const std::string name = node.mName.C_Str();
    if (!selected && std::find(options_.nodes.begin(), options_.nodes.end(), name) != options_.nodes.end()) {
      selected = true;
      report_->matched_nodes.push_back(name);
    }
    if (selected && node.mNumMeshes > 0) {
      const BakeStatus status = addNode(node, world);
      if (!status.ok()) return status;
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) {
      if (node.mChildren[c] == nullptr) continue;
      const BakeStatus status = walk(*node.mChildren[c], world, selected, depth + 1);
      if (!status.ok()) return status;
    }
    return BakeStatus::success();
  }

private:
  BakeStatus addNode(const aiNode& node, const aiMatrix4x4& world) {
    NodeImport entry;
    entry.name = node.mName.length > 0 ? node.mName.C_Str() : "(unnamed)";
    entry.transform = columnMajor(world);
    const bool flip = world.Determinant() < 0.0f; // a mirror reverses the winding
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
      if (node.mMeshes[m] >= scene_.mNumMeshes || scene_.mMeshes[node.mMeshes[m]] == nullptr)
        return BakeStatus::failure(BakeError::kInvalidInput, "node " + entry.name + " refers to a missing mesh");
      const aiMesh& mesh = *scene_.mMeshes[node.mMeshes[m]];
      entry.mesh += (entry.mesh.empty() ? "" : ", ") + std::string(mesh.mName.length > 0 ? mesh.mName.C_Str() : "?");
      const BakeStatus status = addMesh(mesh, world, flip, &entry);
      if (!status.ok()) return status;
    }
    report_->triangles += entry.triangles;
    report_->skipped_primitives += entry.skipped_primitives;
    report_->nodes.push_back(entry);
    return BakeStatus::success();
  }

  BakeStatus addMesh(const aiMesh& mesh, const aiMatrix4x4& world, bool flip, NodeImport* entry) {
    if (mesh.mVertices == nullptr || (mesh.mNumFaces > 0 && mesh.mFaces == nullptr))
      return BakeStatus::failure(BakeError::kInvalidInput, "mesh " + entry->mesh + " has no vertex positions");
    if (soup_->vertices.size() + mesh.mNumVertices > std::numeric_limits<std::uint32_t>::max())
      return BakeStatus::failure(BakeError::kInvalidInput, "more than 2^32 vertices");
    const auto base = std::uint32_t(soup_->vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = world * mesh.mVertices[v];
      soup_->vertices.push_back({p.x, p.y, p.z});
    }
    std::uint64_t skipped = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3 || face.mIndices == nullptr) { // points and lines; polygons are triangulated
        ++skipped;
        continue;
      }
      std::uint32_t a = face.mIndices[0], b = face.mIndices[1], c = face.mIndices[2];
      if (a >= mesh.mNumVertices || b >= mesh.mNumVertices || c >= mesh.mNumVertices)
        return BakeStatus::failure(BakeError::kInvalidInput, "mesh " + entry->mesh + " has a face index out of range");
      if (flip) std::swap(b, c);
      soup_->triangles.push_back({base + a, base + b, base + c});
      ++entry->triangles;
    }
    if (skipped > 0) {
      ++entry->skipped_primitives;
      report_->messages.push_back("node " + entry->name + ": " + std::to_string(skipped) +
                                  " point or line faces skipped (not triangles)");
    }
    return BakeStatus::success();
  }

  const aiScene& scene_;
  const ImportOptions& options_;
  TriangleSoup* soup_;
  ImportReport* report_;
};

} // namespace

bool assimpReads(const std::string& extension) {
  return !extension.empty() && Assimp::Importer().IsExtensionSupported("." + extension);
}

BakeStatus importAssimp(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                        ImportReport* out_report) {
  out_report->importer = "assimp";
  return importIsolated(&importAssimpInProcess, path, options, io_soup, out_report);
}

BakeStatus importAssimpInProcess(const std::string& path, const ImportOptions& options, TriangleSoup* io_soup,
                                 ImportReport* out_report) {
  out_report->importer = "assimp";
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return BakeStatus::failure(BakeError::kIo, "no such file");
  if (options.scene > 0)
    return BakeStatus::failure(BakeError::kBadOption, "--scene " + std::to_string(options.scene) +
                                                          ": assimp files have one scene (--scene 0)");
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  try { // assimp reports failures through GetErrorString, but some of its readers throw past it
    scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  } catch (const std::bad_alloc&) {
    throw; // out of memory, not a broken file
  } catch (const std::exception& e) {
    return BakeStatus::failure(BakeError::kInvalidInput, std::string("assimp could not read it: ") + e.what());
  }
  // ReadFile catches what its readers throw and keeps it: memory running out is not a broken file.
  if (scene == nullptr && importer.GetException() != nullptr) {
    try {
      std::rethrow_exception(importer.GetException());
    } catch (const std::bad_alloc&) {
      throw;
    } catch (...) { // reported below, through GetErrorString
    }
  }
  if (scene == nullptr)
    return BakeStatus::failure(BakeError::kInvalidInput,
                               std::string("assimp could not read it: ") + importer.GetErrorString());
  if (scene->mRootNode == nullptr) return BakeStatus::failure(BakeError::kInvalidInput, "the file has no scene");
  // COLLADA's <unit> is applied to the root by assimp, so its scenes arrive in metres.
  out_report->units = out_report->format == "fbx"   ? fbxUnit(*scene, out_report)
                      : out_report->format == "dae" ? LengthUnit::kMetre
                                                    : LengthUnit::kUnknown;
  NodeWalker walker(*scene, options, io_soup, out_report);
  return walker.walk(*scene->mRootNode, aiMatrix4x4(), options.nodes.empty(), 0);
}

} // namespace baker
} // namespace dng
