// The STL and OBJ guards against inputs OpenMesh's readers mishandle (reader_guards.h); the PLY and OFF
// guards are ply_guard.cpp and off_guard.cpp.
#include "reader_guards.h"
#include "guard_text.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dng {
namespace baker {

using namespace guard;

namespace {

// The facet count a binary STL of `size` bytes declares in its 84-byte header, read from where `in`
// stands (its start); -1 when the size does not match it (ASCII, or not an STL).
long long declaredStlFacets(std::istream& in, std::uint64_t size) {
  char header[84];
  if (!in.read(header, sizeof header)) return -1;
  std::uint32_t count;
  std::memcpy(&count, header + 80, 4);
  return size == 84 + 50 * std::uint64_t(count) ? (long long)count : -1;
}

} // namespace

BakeStatus checkStlCoordinates(const std::string& path, long long* out_declared_facets) {
  const auto failure = [&](const std::string& where, const std::string& problem) {
    return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': " + where + " " + problem);
  };
  std::ifstream in(path, std::ios::binary);
  const auto size = std::uint64_t(std::filesystem::file_size(path));
  *out_declared_facets = declaredStlFacets(in, size);
  if (*out_declared_facets >= 0) { // binary: 50-byte facets of a normal, three vertices, two bytes, after the header
    char facet[50];
    for (std::uint64_t n = 0; in.read(facet, sizeof facet); ++n) {
      float xyz[9];
      std::memcpy(xyz, facet + 12, sizeof xyz);
      for (float c : xyz)
        if (!std::isfinite(c)) return failure("facet " + std::to_string(n), "has a NaN or infinite vertex coordinate");
    }
    return BakeStatus::success();
  }
  char start[512] = {};
  in.clear();
  in.seekg(0);
  in.read(start, sizeof start);
  if (!looksLikeText(start, std::size_t(in.gcount())) && size >= 84) { // binary, not 84 + 50 bytes per facet
    std::uint32_t count;
    std::memcpy(&count, start + 80, 4);
    return failure("binary STL", "declares " + std::to_string(count) + " facets, " +
                                     std::to_string(84 + 50 * std::uint64_t(count)) + " bytes, but has " +
                                     std::to_string(size) + ": truncated, or not an STL");
  }
  in.clear();
  in.seekg(0);
  std::string line;
  std::uint64_t open_facet = 0; // the line of a facet not closed yet
  for (std::uint64_t number = 1; std::getline(in, line); ++number) {
    const char* rest = nullptr;
    const std::string keyword = firstWord(line, &rest);
    if (keyword == "facet") open_facet = number;
    if (keyword == "endfacet") open_facet = 0;
    if (keyword != "vertex") continue;
    const std::string problem = coordinateProblem(rest);
    if (!problem.empty()) return failure("line " + std::to_string(number) + ": vertex", problem);
  }
  // OpenMesh drops a facet cut short, and a file cut in its first facet read as "no faces".
  if (open_facet != 0)
    return failure("line " + std::to_string(open_facet) + ": facet", "has no 'endfacet': the file is truncated");
  return BakeStatus::success();
}

namespace {

// Empty unless an OBJ's "mtllib" line (its rest from `rest`) names a file that is there and neither a
// regular file nor a folder. OpenMesh opens the rest of the line, trimmed, beside the OBJ and reads it
// to its end: /dev/zero there took 5.8 GB in 20 s, a FIFO would wait for ever. The baker reads no
// materials, but OpenMesh's reader reads them whatever it is asked.
std::string materialProblem(const std::string& obj_path, const char* rest, const char* end) {
  std::string name(rest, end);
  const std::size_t first = name.find_first_not_of(" \t\r\n"), last = name.find_last_not_of(" \t\r\n");
  name = first == std::string::npos ? "" : name.substr(first, last - first + 1);
  const std::size_t slash = obj_path.find_last_of('/');
  const std::string target = (slash == std::string::npos ? "" : obj_path.substr(0, slash + 1)) + name;
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(target, error);
  if (error || !std::filesystem::exists(status) || std::filesystem::is_regular_file(status) ||
      std::filesystem::is_directory(status))
    return {};
  return "mtllib names '" + name.substr(0, 80) + "', not a regular file (OpenMesh's reader would read it to its end)";
}

} // namespace

BakeStatus checkObjLines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::uint64_t number = 1;
  const auto failure = [&](const std::string& problem) {
    return BakeStatus::failure(BakeError::kInvalidInput,
                               "'" + path + "': line " + std::to_string(number) + ": " + problem);
  };
  for (; std::getline(in, line); ++number) {
    // The keyword as OpenMesh's reader takes it, up to any white space, \v and \f too: read up to a
    // blank only, "f\v/1" had hidden a face from the guard, and the '/1' made the reader assert (fuzzing).
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const char* rest = line.c_str() + (words.eof() ? line.size() : std::size_t(words.tellg()));
    if (keyword == "mtllib") {
      const std::string problem = materialProblem(path, rest, line.c_str() + line.size());
      if (!problem.empty()) return failure(problem);
    }
    if (keyword == "v") {
      const std::string problem = coordinateProblem(rest);
      if (!problem.empty()) return failure("vertex " + problem);
    }
    if (keyword != "f") continue;
    // The whole rest of the line, NUL bytes and all, as OpenMesh's reader sees it: from `rest` as a C
    // string the words after a NUL went unchecked, and a '/1' there made the reader abort (fuzzing).
    std::istringstream vertices(std::string(rest, line.c_str() + line.size()));
    for (std::string vertex; vertices >> vertex;) {
      if (vertex.front() == '/')
        return failure("face vertex '" + vertex + "' has no vertex index (OBJ needs v, v/vt, v//vn or v/vt/vn)");
    }
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
