// Baker stage 1-2: loading meshes with OpenMesh into a soup, and the mesh checks.
#include "stages.h"

#include "temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

namespace dng {
namespace baker {
namespace {

namespace fs = std::filesystem;

// A unit cube as 8 vertices and 6 quads, outward winding.
const float kCubeVertices[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

class MeshTest : public ::testing::Test {
protected:
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  // The cube as OBJ; `skip_face` >= 0 leaves one face out (an open box).
  std::string cubeObj(const std::string& name, int skip_face = -1, float offset = 0.0f) const {
    std::string text;
    for (const auto& v : kCubeVertices)
      text += "v " + std::to_string(v[0] + offset) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    for (int f = 0; f < 6; ++f) {
      if (f == skip_face) continue;
      text += "f";
      for (int i : kCubeQuads[f])
        text += " " + std::to_string(i + 1);
      text += "\n";
    }
    return write(name, text);
  }
  // Writes `text` as `name` and expects loadMesh to refuse it with `code`, its message holding `why`.
  void expectRefused(const std::string& name, const std::string& text, const std::string& why,
                     BakeError code = BakeError::kInvalidInput) {
    TriangleSoup soup;
    const BakeStatus s = loadMesh(write(name, text), &soup);
    EXPECT_EQ(s.code, code) << name << ": " << s.message;
    EXPECT_NE(s.message.find(why), std::string::npos) << name << ": " << s.message;
  }
  TriangleSoup load(const std::string& path) {
    TriangleSoup soup;
    const BakeStatus status = loadMesh(path, &soup);
    EXPECT_TRUE(status.ok()) << status.message;
    return soup;
  }
  testing::TempDir temp_{"mesh_test"};
  const fs::path& dir_ = temp_.path();
};

TEST_F(MeshTest, ClosedCubeFromObjIsTriangulatedAndClosed) {
  const TriangleSoup soup = load(cubeObj("cube.obj"));
  EXPECT_EQ(soup.polygons, 6u);
  const MeshReport r = checkMesh(soup);
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.wellFormedSolid());
  EXPECT_NEAR(r.signed_volume, 1.0, 1e-6);
  EXPECT_FLOAT_EQ(r.bounds_max.z, 1.0f);
  EXPECT_TRUE(requireBakeable(r).ok());
}

// The PLY guard checks x, y and z by name among a vertex's properties: others before or between them
// are not coordinates (a confidence of 1e39, beyond a float, is not the guard's business). Like the
// reader, it takes blank lines and a vertex broken over two lines as space.
TEST_F(MeshTest, PlyVerticesWithMorePropertiesThanCoordinatesLoad) {
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float confidence\nproperty float x\n"
                          "property float y\nproperty uchar flags\nproperty float z\nelement face 4\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "\n-7 0 0 200 0\n\n1e39 1 0\n0 0\n2 0 1 1 0\n3 0 0 9 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const TriangleSoup soup = load(write("tetra.ply", ply));
  EXPECT_EQ(checkMesh(soup).triangles, 4u);
  EXPECT_TRUE(checkMesh(soup).closed());
  const std::string nan_z =
      ply.substr(0, ply.find("3 0 0 9 1")) + "3 0 0 9 nan" + ply.substr(ply.find("3 0 0 9 1") + 9);
  expectRefused("nan_z.ply", nan_z, "vertex 3 has coordinate 'nan'");
}

// A face vertex without its index makes OpenMesh's OBJ reader abort, even after a NUL byte in the line.
TEST_F(MeshTest, ObjFaceVertexWithoutIndexAfterANulIsRefused) {
  const char kObj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \0 /1\n";
  const std::string obj(kObj, sizeof kObj - 1); // with the NUL
  expectRefused("nul.obj", obj, "face vertex '/1' has no vertex index");
  // The reader splits the keyword off at a vertical tab too (fuzzing: it asserted on this one).
  expectRefused("tab.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf\v/1 2 3\n", "line 4: face vertex '/1' has no vertex index");
}

// OpenMesh reads OFF faces as one stream of numbers: a face may go on over a line end, or follow a
// face of no vertices on its line, and a number ends where its digits do. The guard reads them so, and
// refuses a valence no file could hold.
TEST_F(MeshTest, OffFacesAreAStreamOfWords) {
  const std::string head = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  EXPECT_EQ(checkMesh(load(write("wrapped.off", head + "3 0 2 1 3\n0 1 3\n"))).triangles, 2u);
  expectRefused("huge.off", head + "0 99999999999999999949 0 1\n", "face 1 claims '99999999999999999949' vertices");
  // No vertices: the faces begin on the counts' line, where OpenMesh goes on reading.
  expectRefused("same_line.off", "OFF\n0 2 0 0 77777777777777777777\n",
                "face 1 claims '77777777777777777777' vertices");
  // OpenMesh reads "2-4" as the index 2, then -4, a valence of 4 * 10^9 to it (fuzzing).
  expectRefused("negative.off", head + "3 0 1 2-4 0\n", "face 1 claims '-4' vertices");
  expectRefused("word.off", head + "3 0 1 two\n", "face 0 lists 'two', not a vertex index");
  // An index beyond 32 bits fails OpenMesh's read, and every later face then reads the last valence.
  expectRefused("wide.off", head + "3 0 1 99999999999\n3 0 1 2\n", "face 0 lists '99999999999', not a vertex index");
  // NOFF: the normal is read from the same stream, so it must be numbers too.
  expectRefused("normal.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 nan\n0 1 0 0 0 1\n3 0 1 2\n",
                "vertex 1 has coordinate 'nan'");
  EXPECT_EQ(load(write("normals.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")).polygons, 1u);
  expectRefused("cut.off", head + "3 0 2 1\n3 0 1\n", "face 1 claims 3 vertices and the file ends after 2");
}

// OpenMesh reads a vertex's numbers with the stream too, across line ends and blank lines, and then
// the rest of the last number's line apart: a NOFF normal may sit on the line after its position.
TEST_F(MeshTest, OffVerticesMaySpanLines) {
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const std::string noff = "NOFF\n4 4 0\n0 0 0\n0 0 -1\n1 0 0\n0 0 -1\n0 1 0 0\n\n0 -1\n0 0 1 1 1 1 # tip\n";
  const TriangleSoup soup = load(write("next_line.off", noff + faces));
  EXPECT_EQ(checkMesh(soup).triangles, 4u);
  EXPECT_TRUE(checkMesh(soup).closed());
  ASSERT_EQ(soup.vertices.size(), 4u);
  EXPECT_EQ(soup.vertices[3].z, 1.0f);
  // Plain OFF: a position broken over lines; the rest of its last line is the vertex's, unread.
  EXPECT_EQ(checkMesh(load(write("split.off", "OFF\n4 4 0\n0 0\n0\n1 0 0 7 7\n0 1\n0\n0 0 1\n" + faces))).triangles,
            4u);
  // A comment where a number is due fails the reader's read, on the vertex's first line or after it.
  expectRefused("comment_between.off", "OFF\n4 4 0\n0 0\n# c\n0\n1 0 0\n0 1 0\n0 0 1\n" + faces,
                "vertex 0 has fewer than 3 coordinates");
  expectRefused("comment_glued.off", "NOFF\n4 4 0\n0 0 0 0#c\n0 -1\n" + faces, "vertex 0 has fewer than 6 numbers");
  expectRefused("comment_line.off", "OFF\n4 4 0\n0 0 0\n# c\n1 0 0\n" + faces, "vertex 1 is a comment line");
  expectRefused("normal_cut.off", "NOFF\n1 0 0\n0 0 0 0 0", "vertex 0 has fewer than 6 numbers");
  // A NUL byte fails the reader's read as a comment does; so does hex, which it reads as 0 and then
  // fails on the "x" (strtof would have taken it whole).
  const char kNul[] = "OFF\n4 4 0\n0 0 \0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string nul(kNul, sizeof kNul - 1); // with the NUL
  expectRefused("nul.off", nul + faces, "vertex 0 has a NUL byte where a number is due");
  expectRefused("hex.off", "OFF\n4 4 0\n0x1p3 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces,
                "vertex 0 has coordinate '0x1p3', not a finite number written in decimal");
  expectRefused("hex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0x1p3\nf 1 2 3\n", "has coordinate '0x1p3'");
}

// An OFF or ASCII PLY file that ends before its counts do is refused: OpenMesh made each missing face
// from the last face's numbers, copies that count again in the inside test (and 100,000 copies of one
// large triangle took a bake 23 GB).
TEST_F(MeshTest, TruncatedOffAndTextPlyAreRefused) {
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  expectRefused("faces.off", "OFF\n4 4 0\n" + vertices + "3 0 2 1\n3 0 1 3\n  \n",
                "header declares 4 faces but the file ends after 2: truncated");
  expectRefused("vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n          \n",
                "header declares 4 vertices but the file ends after 2");
  EXPECT_EQ(checkMesh(load(write("whole.off", "OFF\n4 2 0\n" + vertices + "3 0 2 1\n3 0 1 3\n"))).triangles, 2u);
  // An ASCII PLY too: its reader made up one face from the last one's numbers.
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n" +
                          vertices + "3 0 2 1\n3 0 1 3\n";
  expectRefused("faces.ply", ply + "\n\n", "header declares 4 face elements but the file ends in face 2: truncated");
  EXPECT_EQ(checkMesh(load(write("whole.ply", ply + "3 0 3 2\n3 1 2 3\n"))).triangles, 4u);
}

// A binary OFF as OpenMesh reads one: little-endian 32-bit counts, vertex records (three floats, three
// more with N) and faces of a valence and its indices.
std::string binaryOff(const std::string& keyword, std::uint32_t vertices, std::uint32_t faces,
                      const std::vector<float>& vertex_floats, const std::vector<std::uint32_t>& face_words) {
  std::string out = keyword + " BINARY\n";
  const auto word = [&out](std::uint32_t w) {
    for (int byte = 0; byte < 4; ++byte)
      out += char((w >> (8 * byte)) & 0xFFu);
  };
  word(vertices), word(faces), word(0);
  for (float f : vertex_floats) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    word(bits);
  }
  for (std::uint32_t w : face_words)
    word(w);
  return out;
}

// OpenMesh reads as many binary faces as the count says, past the end of the file: a count or valence
// the file cannot hold kept it reading for ever. A binary OFF is checked as it reads one.
TEST_F(MeshTest, BinaryOffCountsAndValencesMustFitTheFile) {
  const std::vector<float> tetra{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<std::uint32_t> faces{3, 0, 2, 1, 3, 0, 1, 3, 3, 0, 3, 2, 3, 1, 2, 3};
  EXPECT_EQ(checkMesh(load(write("tetra.off", binaryOff("OFF", 4, 4, tetra, faces)))).triangles, 4u);
  // With N each vertex carries its normal too: 24 bytes.
  std::vector<float> with_normals;
  for (std::size_t v = 0; v < 4; ++v) {
    with_normals.insert(with_normals.end(), tetra.begin() + 3 * v, tetra.begin() + 3 * v + 3);
    with_normals.insert(with_normals.end(), {0.0f, 0.0f, 1.0f});
  }
  EXPECT_EQ(checkMesh(load(write("normals.off", binaryOff("NOFF", 4, 4, with_normals, faces)))).triangles, 4u);
  // And with ST and C, two texture coordinates and three colour words: 44 bytes.
  std::vector<float> everything;
  for (std::size_t v = 0; v < 4; ++v) {
    everything.insert(everything.end(), with_normals.begin() + 6 * v, with_normals.begin() + 6 * v + 6);
    everything.insert(everything.end(), {0.0f, 0.0f, 0.0f, 0.5f, 0.5f});
  }
  const TriangleSoup all = load(write("everything.off", binaryOff("STCNOFF", 4, 4, everything, faces)));
  EXPECT_EQ(checkMesh(all).triangles, 4u);
  ASSERT_EQ(all.vertices.size(), 4u);
  EXPECT_EQ(all.vertices[3].z, 1.0f); // the records were read at the right size
  expectRefused("big_endian.off", binaryOff("OFF", 4u << 24, 4u << 24, tetra, faces),
                "declares 67108864 vertices of 12 bytes");
  expectRefused("too_many.off", binaryOff("OFF", 4, 5, tetra, faces), "ends before face 4 of 5");
  std::vector<std::uint32_t> huge = faces;
  huge[4] = 0xFFFFFFF0u; // the second face's valence
  expectRefused("valence.off", binaryOff("OFF", 4, 4, tetra, huge), "face 1 claims 4294967280 vertices");
}

// OpenMesh reads an OBJ's material library to its end, whatever the baker asks: one that is a device
// (/dev/zero took 5.8 GB in 20 s) or a FIFO is refused; a real one is read as before.
TEST_F(MeshTest, ObjMaterialLibraryMustBeARegularFile) {
  const std::string body = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir_ / "real.mtl") << "newmtl grey\nKd 0.5 0.5 0.5\n";
  EXPECT_EQ(load(write("real.obj", "mtllib real.mtl\n" + body)).polygons, 1u);
  std::error_code error;
  fs::create_symlink("/dev/zero", dir_ / "zero.mtl", error);
  ASSERT_FALSE(error) << error.message();
  expectRefused("zero.obj", "mtllib   zero.mtl  \n" + body, "line 1: mtllib names 'zero.mtl', not a regular file");
}

// OpenMesh's PLY reader reads as many corners as a face's count says, end of file or not: an ASCII face
// of 2 * 10^9 corners took 20 GB before it gave up, and a binary one the same. It reads lists only as a
// face's vertex_indices, so other lists, and face properties before them, are refused.
TEST_F(MeshTest, PlyCornerCountsMustFitTheFile) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 2\n";
  const std::string corners = "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  EXPECT_EQ(checkMesh(load(write("two.ply", head + corners + "3 0 2 1\n3 0 1 3\n"))).triangles, 2u);
  expectRefused("huge.ply", head + corners + "3 0 2 1\n2000000000 0 1 3\n",
                "face 1 claims '2000000000' corners, not a count the file can hold");
  expectRefused("negative.ply", head + corners + "-4 0 2 1\n", "face 0 claims '-4' corners");
  expectRefused("glued.ply", head + corners + "3 0 2 1-4\n", "face 0 lists '1-4', not a vertex index");
  expectRefused("cut.ply", head + corners + "3 0 2 1\n3 0 1\n", "face 1 claims 3 corners and the file ends");
  expectRefused("texcoord.ply",
                head + "property list uchar int vertex_indices\nproperty list uchar float "
                       "texcoord\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 6 0 0 1 0 0 1\n"
                       "3 0 1 3 6 0 0 1 0 0 1\n",
                "element 'face' has the list property 'texcoord'");
  expectRefused("double_count.ply", head + "property list double int vertex_indices\nend_header\n",
                "face vertex_indices are counted in double: OpenMesh's reader takes only");
  // The reader splits words at \v and reads a NUL inside a word: a corner count the walk would not see.
  expectRefused("nul.ply", head + corners + "3 0 2 1\n3 0 1 3" + std::string(1, '\0') + " 2000000000\n",
                "holds the control byte 0 after its header");
  // Colours it reads as integers unless declared float, so a double colour must be a whole number.
  const std::string coloured = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nproperty double red\nelement face 1\n" +
                               corners.substr(0, corners.find("0 0 0"));
  expectRefused("double_red.ply", coloured + "0 0 0 0.5\n1 0 0 1\n0 1 0 1\n3 0 1 2\n",
                "vertex 0 has red '0.5', not a whole integer as the reader reads it");
  EXPECT_EQ(load(write("whole_red.ply", coloured + "0 0 0 0\n1 0 0 1\n0 1 0 1\n3 0 1 2\n")).polygons, 1u);
  // A layout common exporters write: CR LF, normals, colours as uchar.
  std::string exported = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 3\r\n";
  for (const char* p : {"float x", "float y", "float z", "float nx", "float ny", "float nz", "uchar red", "uchar green",
                        "uchar blue", "uchar alpha"})
    exported += std::string("property ") + p + "\r\n";
  exported += "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n";
  exported += "0 0 0 0 0 1 255 0 0 255\r\n1 0 0 0 0 1 0 255 0 255\r\n0 1 0 0 0 1 0 0 255 255\r\n3 0 1 2\r\n";
  EXPECT_EQ(load(write("exported.ply", exported)).polygons, 1u);
  expectRefused("before.ply", head + "property uchar red\n" + corners, "face property 'red' comes before");
  // OpenMesh reads the three words after "ply" as the format line, whatever they are (fuzzing: it looped
  // for ever on a comment there).
  expectRefused("late_format.ply",
                "ply\ncomment binary_little_endian x\nformat ascii 1.0\n" + head.substr(head.find("element")) + corners,
                "line 2 'comment binary_little_endian x' is not the format line");
  // OpenMesh reads the words after obj_info as keywords (a comment's it skips).
  EXPECT_EQ(checkMesh(load(write("info.ply", head + "obj_info made by hand\ncomment element x 9\n" + corners +
                                                 "3 0 2 1\n3 0 1 3\n")))
                .triangles,
            2u);
  expectRefused("info_element.ply", head + "obj_info element extra 2000000000\n" + corners,
                "obj_info element extra 2000000000' holds the word 'element'");
  // Binary, big-endian: a count of -4 is 4 * 10^9 to the reader.
  std::string binary = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
  binary += std::string(36, '\0');                                      // three vertices at the origin
  binary += std::string("\xff\xff\xff\xfc", 4) + std::string(12, '\0'); // a count of -4, three indices
  expectRefused("negative_binary.ply", binary, "face 0 claims 4294967292 corners, more than the 12 bytes");
  binary.replace(binary.size() - 16, 4, std::string("\0\0\0\3", 4));
  TriangleSoup soup;
  EXPECT_TRUE(loadMesh(write("binary.ply", binary), &soup).ok());
  EXPECT_EQ(soup.polygons, 1u);
  // The reader finds binary data 12 bytes after the last word it read before end_header, a comment's
  // line end included: after a comment it reads from one byte too far.
  const std::string commented =
      binary.substr(0, binary.find("end_header")) + "comment last\n" + binary.substr(binary.find("end_header"));
  expectRefused("commented.ply", commented, "ends where OpenMesh's reader does not find its binary data");
}

// OpenMesh's binary PLY reader reads positions, normals and texture coordinates only as float or double,
// and colours only as integers or float (each of 16 types tried): it misreads the rest and every value
// after them, which is how a fuzzed file made it allocate 2 GB. Such files are refused.
TEST_F(MeshTest, BinaryPlyTypesTheReaderMisreadsAreRefused) {
  const auto ply = [](const std::string& x_type, const std::string& colour_type) {
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty " + x_type +
                       " x\nproperty float y\nproperty float z\nproperty " + colour_type +
                       " red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int v = 0; v < 3; ++v) {
      if (x_type == "double") {
        const double x = v == 1 ? 1.0 : 0.0;
        text.append(reinterpret_cast<const char*>(&x), sizeof x);
      } else {
        const float x = v == 1 ? 1.0f : 0.0f;
        text.append(reinterpret_cast<const char*>(&x), sizeof x);
      }
      const float yz[2] = {v == 2 ? 1.0f : 0.0f, 0.0f};
      text.append(reinterpret_cast<const char*>(yz), sizeof yz);
      text.append(colour_type == "uchar" ? 1u : 4u, '\0');
    }
    const std::int32_t corners[3] = {0, 1, 2};
    text += '\3';
    text.append(reinterpret_cast<const char*>(corners), sizeof corners);
    return text;
  };
  const TriangleSoup soup = load(write("double_x.ply", ply("double", "uchar")));
  ASSERT_EQ(soup.vertices.size(), 3u);
  EXPECT_EQ(soup.vertices[1].x, 1.0f);
  EXPECT_EQ(checkMesh(soup).triangles, 1u);
  expectRefused("short_x.ply", ply("short", "uchar"),
                "vertex property 'x' is short: OpenMesh's binary reader misreads it");
  expectRefused("double_red.ply", ply("float", "double"), "vertex property 'red' is double");
}

// OpenMesh's STL reader drops a facet whose corners are one point without a word: the loader says how
// many facets the binary header declared against how many were kept.
TEST_F(MeshTest, BinaryStlFacetsTheReaderDropsAreReported) {
  const float tetra[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                                {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                                {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::string stl(80, ' ');
  const std::uint32_t declared = 5;
  stl.append(reinterpret_cast<const char*>(&declared), 4);
  const auto facet = [&stl](const float corners[3][3]) {
    const float normal[3] = {0, 0, 0};
    const char attributes[2] = {0, 0};
    stl.append(reinterpret_cast<const char*>(normal), sizeof normal);
    stl.append(reinterpret_cast<const char*>(corners), 9 * sizeof(float));
    stl.append(attributes, sizeof attributes);
  };
  for (const auto& corners : tetra)
    facet(corners);
  const float point[3][3] = {{2, 2, 2}, {2, 2, 2}, {2, 2, 2}};
  facet(point);
  const TriangleSoup soup = load(write("dropped.stl", stl));
  EXPECT_EQ(soup.polygons, 4u);
  EXPECT_EQ(checkMesh(soup).triangles, 4u);
  const std::string said = "the STL declares 5 facets but OpenMesh kept 4";
  EXPECT_TRUE(std::any_of(soup.reader_messages.begin(), soup.reader_messages.end(),
                          [&](const std::string& m) { return m.find(said) != std::string::npos; }));
}

// A face's diffuse_red, diffuse_green and diffuse_blue are not colours to OpenMesh's binary reader: it
// skips them by their size, double or not, where a face's red in double precision derails it.
TEST_F(MeshTest, BinaryPlyFaceDiffuseDoublesLoad) {
  const auto ply = [](const std::string& face_colour) {
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 4\nproperty list uchar int vertex_indices\nproperty double " +
                       face_colour + "\nend_header\n";
    const float positions[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    text.append(reinterpret_cast<const char*>(positions), sizeof positions);
    const std::int32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const double shade = 0.5;
    for (const auto& corners : faces) {
      text += '\3';
      text.append(reinterpret_cast<const char*>(corners), sizeof corners);
      text.append(reinterpret_cast<const char*>(&shade), sizeof shade);
    }
    return text;
  };
  const TriangleSoup soup = load(write("diffuse.ply", ply("diffuse_red")));
  EXPECT_EQ(checkMesh(soup).triangles, 4u);
  EXPECT_TRUE(checkMesh(soup).closed());
  expectRefused("face_red.ply", ply("red"), "face property 'red' is double");
}

// OpenMesh's .om reader needs a whole OpenMesh mesh, which the soup importer is not: such files are
// refused as unsupported, with what to do instead. (The bytes: a triangle as OpenMesh 9.0 writes it.)
TEST_F(MeshTest, OpenMeshNativeFilesAreRefusedAsUnsupported) {
  const unsigned char om[] = {0x4f, 0x4d, 0x54, 0x42, 0x03, 0, 0, 0, 0x01, 0, 0, 0, 0x03, 0, 0, 0,    0,
                              0x16, 0,    0,    0,    0,    0, 0, 0, 0,    0, 0, 0, 0,    0, 0, 0x80, 0x3f};
  expectRefused("triangle.om", std::string(reinterpret_cast<const char*>(om), sizeof om),
                "native .om format is not supported: save the mesh as .obj, .off or .ply", BakeError::kUnsupported);
}

// OFF counts are the three words after the keyword's line, on one line or several, as OpenMesh reads
// them; a comment where they belong is not one.
TEST_F(MeshTest, OffCountsAreTheWordsAfterTheKeywordLine) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  EXPECT_EQ(checkMesh(load(write("split.off", "OFF\n4\n4 0\n" + body))).triangles, 4u);
  EXPECT_EQ(checkMesh(load(write("blank.off", "OFF\n\n4 4 0\n" + body))).triangles, 4u);
  expectRefused("comment.off", "OFF\n# made by hand\n4 4 0\n" + body, "count '#' is not a number");
  // Nor among the vertices, where OpenMesh reads it as a coordinate and fails (no faces, and with many
  // faces and vertices their product of work).
  const std::string among = "OFF\n4 4 0\n0 0 0\n# made by hand\n" + body.substr(6);
  expectRefused("among.off", among, "vertex 1 is a comment line");
}

TEST_F(MeshTest, EveryFormatGivesTheSameCube) {
  std::string off = "OFF\n8 6 0\n", ply, stl = "solid cube\n";
  for (const auto& v : kCubeVertices)
    off += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 6\nproperty list uchar int vertex_indices\nend_header\n" +
        off.substr(off.find('\n', 4) + 1);
  for (const auto& q : kCubeQuads) {
    off += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
           std::to_string(q[3]) + "\n";
    ply += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
           std::to_string(q[3]) + "\n";
    for (int t = 0; t < 2; ++t) { // STL is triangles only
      const int tri[3] = {q[0], q[1 + t], q[2 + t]};
      stl += " facet normal 0 0 0\n  outer loop\n";
      for (int i : tri)
        stl += "   vertex " + std::to_string(kCubeVertices[i][0]) + " " + std::to_string(kCubeVertices[i][1]) + " " +
               std::to_string(kCubeVertices[i][2]) + "\n";
      stl += "  endloop\n endfacet\n";
    }
  }
  stl += "endsolid cube\n";
  for (const std::string& path : {write("cube.off", off), write("cube.ply", ply), write("cube.stl", stl)}) {
    SCOPED_TRACE(path);
    const MeshReport r = checkMesh(load(path));
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_TRUE(r.closed()) << r.boundary_edges << " boundary edges";
    EXPECT_EQ(r.components, 1u);
  }
}

TEST_F(MeshTest, FlippedFacesAndInsideOutMeshesAreNotWellFormedSolids) {
  const TriangleSoup cube = load(cubeObj("cube.obj"));
  TriangleSoup flipped_one = cube;
  std::swap(flipped_one.triangles[0][1], flipped_one.triangles[0][2]);
  const MeshReport one = checkMesh(flipped_one);
  EXPECT_TRUE(one.closed());
  EXPECT_EQ(one.misoriented_edges, 3u);
  EXPECT_FALSE(one.wellFormedSolid());
  TriangleSoup inside_out = cube;
  for (auto& t : inside_out.triangles)
    std::swap(t[1], t[2]);
  const MeshReport out = checkMesh(inside_out);
  EXPECT_EQ(out.misoriented_edges, 0u);
  EXPECT_NEAR(out.signed_volume, -1.0, 1e-6);
  EXPECT_FALSE(out.wellFormedSolid());
}

TEST_F(MeshTest, OpenBoxReportsItsBoundaryAndStillBakes) {
  const MeshReport r = checkMesh(load(cubeObj("open.obj", 1)));
  EXPECT_EQ(r.triangles, 10u);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_EQ(r.hole_edges, 4u);
  EXPECT_FALSE(r.closed());
  EXPECT_TRUE(requireBakeable(r).ok());
}

// Files repeat a vertex where its normal or texture coordinates change: each face of this cube has
// its own four corners. Open by its indices, but without a hole.
TEST_F(MeshTest, SeamsOfRepeatedVerticesAreNoHoles) {
  std::string text;
  for (int f = 0; f < 6; ++f) {
    for (int i : kCubeQuads[f]) {
      const auto& v = kCubeVertices[std::size_t(i)];
      text += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
    }
    text += "f " + std::to_string(4 * f + 1) + " " + std::to_string(4 * f + 2) + " " + std::to_string(4 * f + 3) + " " +
            std::to_string(4 * f + 4) + "\n";
  }
  const MeshReport r = checkMesh(load(write("seams.obj", text)));
  EXPECT_EQ(r.vertices, 24u);
  EXPECT_EQ(r.boundary_edges, 24u);
  EXPECT_FALSE(r.closed());
  EXPECT_EQ(r.hole_edges, 0u);
}

// OpenMesh's own mesh kernel would refuse the third triangle on the shared edge; the soup keeps it.
TEST_F(MeshTest, NonManifoldEdgeKeepsEveryTriangle) {
  const std::string path =
      write("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  const TriangleSoup soup = load(path);
  EXPECT_EQ(soup.triangles.size(), 3u);
  const MeshReport r = checkMesh(soup);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_TRUE(requireBakeable(r).ok());
}

TEST_F(MeshTest, SeparateShellsAreSeparateComponents) {
  TriangleSoup a = load(cubeObj("a.obj"));
  const TriangleSoup b = load(cubeObj("b.obj", -1, 3.0f));
  const auto base = std::uint32_t(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles)
    a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const MeshReport r = checkMesh(a);
  EXPECT_EQ(r.components, 2u);
  EXPECT_FLOAT_EQ(r.bounds_max.x, 4.0f);
}

TEST_F(MeshTest, UnusableMeshesAreRefusedWithInvalidInput) {
  TriangleSoup nan_soup;
  nan_soup.vertices = {{0, 0, 0}, {1, 0, 0}, {NAN, 1, 0}};
  nan_soup.triangles = {{0, 1, 2}};
  const BakeStatus nan_status = requireBakeable(checkMesh(nan_soup));
  EXPECT_EQ(nan_status.code, BakeError::kInvalidInput);
  EXPECT_NE(nan_status.message.find("NaN"), std::string::npos);

  TriangleSoup flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  flat.triangles = {{0, 1, 2}, {1, 2, 3}, {0, 0, 1}};
  const MeshReport r = checkMesh(flat);
  EXPECT_EQ(r.degenerate_triangles, 3u);
  EXPECT_EQ(requireBakeable(r).code, BakeError::kInvalidInput);
  // A sliver has some area, but thinner than float's precision over its length (here 10^-12 as thick as
  // it is long) it has no usable normal: degenerate, and the message says why. 10^-6 is a triangle.
  TriangleSoup sliver;
  sliver.vertices = {{0, 0, 0}, {1, 0, 0}, {1000, 0, 1e-6f}};
  sliver.triangles = {{0, 1, 2}};
  const BakeStatus sliver_status = requireBakeable(checkMesh(sliver));
  EXPECT_EQ(sliver_status.code, BakeError::kInvalidInput);
  EXPECT_NE(sliver_status.message.find("thinner than 1e-7 of their longest edge"), std::string::npos)
      << sliver_status.message;
  sliver.vertices[2].z = 1.0f;
  EXPECT_EQ(checkMesh(sliver).degenerate_triangles, 0u);

  const TriangleSoup empty = load(write("empty.obj", ""));
  const BakeStatus empty_status = requireBakeable(checkMesh(empty));
  EXPECT_EQ(empty_status.code, BakeError::kInvalidInput);
  EXPECT_NE(empty_status.message.find("no faces"), std::string::npos);
}

TEST_F(MeshTest, FilesThatCannotBeReadSayWhy) {
  TriangleSoup soup;
  BakeStatus s = loadMesh((dir_ / "absent.obj").string(), &soup);
  EXPECT_EQ(s.code, BakeError::kIo);
  EXPECT_NE(s.message.find("absent.obj"), std::string::npos);
  expectRefused("mesh.fbx", "not supported", ".fbx", BakeError::kUnsupported);
  fs::create_directories(dir_ / "folder.obj");
  EXPECT_EQ(loadMesh((dir_ / "folder.obj").string(), &soup).code, BakeError::kIo);
  // OpenMesh alone spins on this header for over a minute, then throws.
  expectRefused("broken.ply", "ply\nformat ascii 1.0\nelement vertex banana\nend_header\n", "element vertex banana");
  s = loadMesh(write("huge.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999\nend_header\n"), &soup);
  EXPECT_EQ(s.code, BakeError::kInvalidInput) << s.message;
  s = loadMesh(write("headless.ply", "ply\nformat ascii 1.0\n"), &soup);
  EXPECT_EQ(s.code, BakeError::kInvalidInput) << s.message;
  // Files naming OFF must be OFF: OpenMesh's reader accepts a mangled magic and then reads garbage counts.
  expectRefused("garbage.off", "this is not an OFF file at all\n", "is not OFF");
  // No OFF keyword at all is invalid input too, as other formats' garbage is (OpenMesh refused it as
  // if it could not read the file, an I/O error).
  expectRefused("unrelated.off", "nothing to see here\n", "no OFF keyword");
  expectRefused("empty.off", "", "OFF file is empty");
}

TEST_F(MeshTest, FaceIndicesOutOfRangeAreSkippedAndCounted) {
  const TriangleSoup soup = load(write("bad_index.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n"));
  EXPECT_EQ(soup.polygons, 2u);
  EXPECT_EQ(soup.faces_with_bad_index, 1u);
  EXPECT_EQ(soup.triangles.size(), 1u);
}

} // namespace
} // namespace baker
} // namespace dng
