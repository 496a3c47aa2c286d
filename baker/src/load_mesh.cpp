// Mesh loading through OpenMesh's readers into a triangle soup.
//
// Why not read into an OpenMesh PolyMesh: its kernel refuses faces that would make an edge
// non-manifold ("complex edge") and splits non-manifold vertices, so triangles would vanish or move
// silently. A BaseImporter of our own receives exactly what the file says.
#include "reader_guards.h"
#include "stages.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <new>
#include <sstream>

namespace dng {
namespace baker {

namespace {

namespace om = OpenMesh;

// Records vertices and faces; ignores normals, colours, texture coordinates and status bits.
class SoupImporter final : public om::IO::BaseImporter {
public:
  explicit SoupImporter(TriangleSoup* soup) : soup_(soup) {}

  om::VertexHandle add_vertex(const om::Vec3f& p) override {
    soup_->vertices.push_back({p[0], p[1], p[2]});
    return om::VertexHandle(int(soup_->vertices.size() - 1));
  }
  om::VertexHandle add_vertex() override { return add_vertex(om::Vec3f(0.0f, 0.0f, 0.0f)); }
  om::HalfedgeHandle add_edge(om::VertexHandle, om::VertexHandle) override { return om::HalfedgeHandle(); }
  om::FaceHandle add_face(const VHandles& indices) override {
    ++soup_->polygons;
    for (const om::VertexHandle& v : indices) {
      if (!v.is_valid() || std::size_t(v.idx()) >= soup_->vertices.size()) {
        ++soup_->faces_with_bad_index;
        return om::FaceHandle();
      }
    }
    for (std::size_t i = 2; i < indices.size(); ++i) // fan: exact for the convex polygons files hold
      soup_->triangles.push_back(
          {std::uint32_t(indices[0].idx()), std::uint32_t(indices[i - 1].idx()), std::uint32_t(indices[i].idx())});
    return om::FaceHandle(int(soup_->polygons - 1));
  }
  om::FaceHandle add_face(om::HalfedgeHandle) override { return om::FaceHandle(); }
  void set_point(om::VertexHandle v, const om::Vec3f& p) override {
    if (v.is_valid() && std::size_t(v.idx()) < soup_->vertices.size()) soup_->vertices[v.idx()] = {p[0], p[1], p[2]};
  }
  size_t n_vertices() const override { return soup_->vertices.size(); }
  size_t n_faces() const override { return std::size_t(soup_->polygons); }
  size_t n_edges() const override { return 0; }

  // Attributes the baker does not use.
  void add_face_texcoords(om::FaceHandle, om::VertexHandle, const std::vector<om::Vec2f>&) override {}
  void add_face_texcoords(om::FaceHandle, om::VertexHandle, const std::vector<om::Vec3f>&) override {}
  void set_face_texindex(om::FaceHandle, int) override {}
  void set_halfedge(om::VertexHandle, om::HalfedgeHandle) override {}
  void set_normal(om::VertexHandle, const om::Vec3f&) override {}
  void set_normal(om::VertexHandle, const om::Vec3d&) override {}
  void set_color(om::VertexHandle, const om::Vec3uc&) override {}
  void set_color(om::VertexHandle, const om::Vec4uc&) override {}
  void set_color(om::VertexHandle, const om::Vec3f&) override {}
  void set_color(om::VertexHandle, const om::Vec4f&) override {}
  void set_texcoord(om::VertexHandle, const om::Vec2f&) override {}
  void set_status(om::VertexHandle, const om::Attributes::StatusInfo&) override {}
  void set_next(om::HalfedgeHandle, om::HalfedgeHandle) override {}
  void set_face(om::HalfedgeHandle, om::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(om::HalfedgeHandle, const om::Vec2f&) override {}
  void set_texcoord(om::VertexHandle, const om::Vec3f&) override {}
  void set_texcoord(om::HalfedgeHandle, const om::Vec3f&) override {}
  void set_status(om::HalfedgeHandle, const om::Attributes::StatusInfo&) override {}
  void set_color(om::EdgeHandle, const om::Vec3uc&) override {}
  void set_color(om::EdgeHandle, const om::Vec4uc&) override {}
  void set_color(om::EdgeHandle, const om::Vec3f&) override {}
  void set_color(om::EdgeHandle, const om::Vec4f&) override {}
  void set_status(om::EdgeHandle, const om::Attributes::StatusInfo&) override {}
  void set_normal(om::FaceHandle, const om::Vec3f&) override {}
  void set_normal(om::FaceHandle, const om::Vec3d&) override {}
  void set_color(om::FaceHandle, const om::Vec3uc&) override {}
  void set_color(om::FaceHandle, const om::Vec4uc&) override {}
  void set_color(om::FaceHandle, const om::Vec3f&) override {}
  void set_color(om::FaceHandle, const om::Vec4f&) override {}
  void set_status(om::FaceHandle, const om::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

private:
  TriangleSoup* soup_;
};

// Routes OpenMesh's error log into a string for as long as it lives, instead of stderr. It swaps the
// stream's buffer rather than using OpenMesh's connect/disconnect: in OpenMesh 9.0 disconnect forgets
// its target without deleting it (16 bytes per call, reported by LeakSanitizer while fuzzing).
class CapturedReaderLog {
public:
  CapturedReaderLog() : previous_(::omerr().rdbuf(buffer_.rdbuf())) {}
  ~CapturedReaderLog() {
    ::omerr().flush();
    ::omerr().rdbuf(previous_);
  }
  CapturedReaderLog(const CapturedReaderLog&) = delete;
  CapturedReaderLog& operator=(const CapturedReaderLog&) = delete;
  std::vector<std::string> lines() {
    ::omerr().flush();
    std::vector<std::string> out;
    std::istringstream in(buffer_.str());
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) out.push_back(line);
    }
    return out;
  }

private:
  std::ostringstream buffer_; // before previous_: the constructor hands its buffer to omerr()
  std::streambuf* previous_;
};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// OpenMesh's .om reader needs a whole OpenMesh mesh to read into (it refused the soup importer, so no
// .om file ever loaded here), and it asserts on malformed chunks, which would abort a bake.
BakeStatus openMeshNativeRefused(const std::string& path) {
  return BakeStatus::failure(BakeError::kUnsupported, "'" + path +
                                                          "': OpenMesh's native .om format is not supported: save "
                                                          "the mesh as .obj, .off or .ply (OpenMesh writes all three)");
}

} // namespace

BakeStatus loadMesh(const std::string& path, TriangleSoup* out_soup) {
  *out_soup = TriangleSoup();
  const std::string ext = lowerExtension(path);
  if (ext == ".om") return openMeshNativeRefused(path);
  static const char* const kSupported[] = {".obj", ".off", ".ply", ".stl"};
  if (std::find(std::begin(kSupported), std::end(kSupported), ext) == std::end(kSupported))
    return BakeStatus::failure(BakeError::kUnsupported,
                               "'" + path + "': unknown mesh format '" + ext + "' (use .obj, .off, .ply or .stl)");
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    return BakeStatus::failure(BakeError::kIo, "'" + path + "': no such file");
  long long declared_facets = -1; // a binary STL's
  const BakeStatus guarded = ext == ".ply"   ? checkPlyHeader(path)
                             : ext == ".obj" ? checkObjLines(path)
                             : ext == ".off" ? checkOffHeader(path)
                             : ext == ".stl" ? checkStlCoordinates(path, &declared_facets)
                                             : BakeStatus{};
  if (!guarded.ok()) return guarded;
  TriangleSoup soup;
  SoupImporter importer(&soup);
  CapturedReaderLog log;
  om::IO::Options options;
  bool read = false;
  try {
    read = om::IO::IOManager().read(path, importer, options);
  } catch (const std::bad_alloc&) {
    throw;                            // out of memory, not an unreadable file
  } catch (const std::exception& e) { // OpenMesh's readers may throw on malformed files
    soup.reader_messages.insert(soup.reader_messages.begin(), e.what());
  }
  const std::vector<std::string> logged = log.lines();
  soup.reader_messages.insert(soup.reader_messages.end(), logged.begin(), logged.end());
  if (!read) {
    const std::string why = soup.reader_messages.empty() ? "" : ": " + soup.reader_messages.front();
    return BakeStatus::failure(BakeError::kIo, "'" + path + "': OpenMesh could not read it" + why);
  }
  if (declared_facets > (long long)soup.polygons)
    soup.reader_messages.push_back("the STL declares " + std::to_string(declared_facets) +
                                   " facets but OpenMesh kept " + std::to_string(soup.polygons) +
                                   " (it drops degenerate facets)");
  *out_soup = std::move(soup);
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
