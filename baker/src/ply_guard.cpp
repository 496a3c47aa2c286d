// The PLY guard (reader_guards.h checkPlyHeader): the header, then the body as OpenMesh 9.0's reader
// reads it, up to the faces.
#include "guard_text.h"
#include "reader_guards.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace dng {
namespace baker {

using namespace guard;

namespace {

bool isPlyType(const std::string& t) {
  static const char* const kTypes[] = {"char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                                       "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
}

// Empty when one header line (after "ply") is well-formed, else what is wrong with it.
std::string plyLineProblem(const std::string& line, std::uint64_t file_size, bool* io_seen_element) {
  std::istringstream words(line);
  std::vector<std::string> w;
  for (std::string word; words >> word;)
    w.push_back(word);
  if (w.empty()) return "is empty";
  if (w[0] == "comment") return {};
  // OpenMesh skips the rest of a comment's line, but not of an obj_info's: it reads each word after it
  // as a keyword, so an "element" there declares an element the guard would not know of (fuzzing: one
  // of 2 * 10^9 items took 24 GB).
  if (w[0] == "obj_info") {
    for (std::size_t n = 1; n < w.size(); ++n) {
      if (w[n] == "element" || w[n] == "property" || w[n] == "end_header")
        return "holds the word '" + w[n] + "', which OpenMesh's reader takes for a keyword";
    }
    return {};
  }
  if (w[0] == "format") {
    // PLY has one version; OpenMesh read a mangled one and then hung (found by fuzzing).
    const bool known = w.size() == 3 && w[2] == "1.0" &&
                       (w[1] == "ascii" || w[1] == "binary_little_endian" || w[1] == "binary_big_endian");
    return known ? "" : "is not 'format ascii|binary_little_endian|binary_big_endian 1.0'";
  }
  if (w[0] == "element") {
    *io_seen_element = true;
    if (w.size() != 3) return "is not 'element NAME COUNT'";
    // At least one byte per element: a count larger than the file is impossible.
    return isCount(w[2]) && std::stoull(w[2]) <= file_size ? "" : "has an impossible element count";
  }
  if (w[0] == "property") {
    if (!*io_seen_element) return "declares a property before any element";
    const bool scalar = w.size() == 3 && isPlyType(w[1]);
    const bool list = w.size() == 5 && w[1] == "list" && isPlyType(w[2]) && isPlyType(w[3]);
    return scalar || list ? "" : "is not 'property TYPE NAME' or 'property list TYPE TYPE NAME' with a PLY type";
  }
  return "has an unknown keyword '" + w[0] + "'";
}

// A PLY header as the body checks need it: the format, and each element's name, count and properties.
struct PlyProperty {
  std::string name, type, count_type; ///< count_type: lists only
  bool list = false;
};
struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};
struct PlyLayout {
  std::string format;
  std::vector<PlyElement> elements;
};

// Notes a well-formed header line (plyLineProblem found nothing wrong with it) in `io`.
void notePlyLine(const std::string& line, PlyLayout* io) {
  std::istringstream words(line);
  std::string keyword, a, b, c, d;
  words >> keyword >> a >> b >> c >> d;
  if (keyword == "format") io->format = a;
  if (keyword == "element") io->elements.push_back({a, std::stoull(b), {}});
  if (keyword != "property") return;
  PlyProperty p;
  p.list = a == "list";
  p.name = p.list ? d : b, p.type = p.list ? c : a, p.count_type = p.list ? b : "";
  io->elements.back().properties.push_back(p);
}

bool isFloatType(const std::string& t) { return t == "float" || t == "float32" || t == "double" || t == "float64"; }

std::size_t plyTypeSize(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  return t == "double" || t == "float64" ? 8 : 4;
}

// Whether [begin, end) is a whole decimal number as a stream reads one into `type`: digits with a
// sign for integer types (at most 9, so the read cannot overflow), a finite decimal for float types
// (no "nan", "inf" or hex, which a stream refuses). A word the reader cannot take whole fails its
// stream or leaves a piece for the next value, and it loses its place in the file.
bool plyNumber(const char* begin, const char* end, const std::string& type) {
  if (isFloatType(type)) return decimalNumber(begin, end);
  const char* at = begin + (begin != end && (*begin == '+' || *begin == '-'));
  const char* digits = at;
  while (at != end && std::isdigit(static_cast<unsigned char>(*at)))
    ++at;
  return at != digits && at == end && at - digits <= 9;
}

// The properties OpenMesh's reader reads as numbers: a vertex's position, normal and texture
// coordinates as floats, and colours (a face's without the diffuse_ names) by their type. The rest it
// skips.
const char* const kFloatNames[] = {"x", "y", "z", "nx", "ny", "nz", "u", "s", "v", "t"};
const char* const kColourNames[] = {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue"};

template <std::size_t N> bool named(const PlyProperty& p, const char* const (&names)[N]) {
  return std::find(std::begin(names), std::end(names), p.name) != std::end(names);
}

// Whether OpenMesh's reader reads property `p` of element `e` as a colour: a vertex's colour names, and a
// face's but the diffuse_ ones, which it skips as properties of its own (by their size in binary files,
// a word in ASCII ones).
bool readAsColour(const PlyElement& e, const PlyProperty& p) {
  return (e.name == "vertex" && named(p, kColourNames)) ||
         (e.name == "face" && named(p, kColourNames) && p.name.compare(0, 8, "diffuse_") != 0);
}

// How OpenMesh's ASCII reader reads property `p` of element `e`: "float" (positions, normals, texture
// coordinates, whatever their declared type, and float colours), "int" (other colours, double ones
// too), or "" for a word it skips.
std::string textRead(const PlyElement& e, const PlyProperty& p) {
  if (e.name == "vertex" && named(p, kFloatNames)) return "float";
  if (!readAsColour(e, p)) return "";
  return p.type == "float" || p.type == "float32" ? "float" : "int";
}

// What OpenMesh 9.0's binary PLY reader cannot read in place, found by trying every type: a vertex's
// position, normal or texture coordinate of an integer type, and a colour in double precision (a face's
// diffuse_red and the like it reads in place, as properties of their own). It reads such a value as
// nothing or as a float, and every value after it from the wrong bytes.
std::string plyBinaryTypeProblem(const PlyElement& e, const PlyProperty& p) {
  const bool float_read = e.name == "vertex" && named(p, kFloatNames);
  if ((float_read && !isFloatType(p.type)) || (readAsColour(e, p) && plyTypeSize(p.type) == 8))
    return e.name + " property '" + p.name + "' is " + p.type + ": OpenMesh's binary reader misreads it";
  return {};
}

// Whether `p` of element `e` is the list OpenMesh reads as a face's corners.
bool isFaceCorners(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// What OpenMesh 9.0's PLY reader cannot read in `layout`: it reads the elements up to the first face
// element, one value per property, except a face's vertex_indices list (a count, then the indices). Any
// other list it reads as one value and loses its place; face properties before vertex_indices it drops
// from its layout (but not from the file); a second vertex or face element it counts with the first.
std::string plyLayoutProblem(const PlyLayout& layout) {
  int vertices = 0, faces = 0;
  for (const PlyElement& e : layout.elements) {
    vertices += e.name == "vertex", faces += e.name == "face";
    if (vertices > 1 || faces > 1) return "has a second '" + e.name + "' element";
    for (std::size_t n = 0; n < e.properties.size(); ++n) {
      const PlyProperty& p = e.properties[n];
      if (p.list && !isFaceCorners(e, p))
        return "element '" + e.name + "' has the list property '" + p.name +
               "': OpenMesh reads lists only as a face's vertex_indices";
      if (const std::string problem = layout.format == "ascii" ? "" : plyBinaryTypeProblem(e, p); !problem.empty())
        return problem;
      if (isFaceCorners(e, p) && p.count_type != "uchar" && p.count_type != "uint8" && p.count_type != "uint16" &&
          p.count_type != "int")
        return "face vertex_indices are counted in " + p.count_type +
               ": OpenMesh's reader takes only uchar, uint8, uint16 or int";
      if (isFaceCorners(e, p) && isFloatType(p.type))
        return "face vertex_indices are " + p.type + ": OpenMesh reads indices as integers";
      if (isFaceCorners(e, p) && n > 0)
        return "face property '" + e.properties[0].name +
               "' comes before vertex_indices: OpenMesh's reader would drop it and misread every face";
    }
    if (e.name == "face") break; // the reader stops after the faces
  }
  return {};
}

// The faces' corner counts and indices, and every number OpenMesh reads before them, of an ASCII PLY,
// word by word across lines as the reader reads them. x, y and z must be finite (the reader stopped at
// "nan": "the mesh has no faces"); a count must be one the file can hold (a face of 2 * 10^9 corners
// took 20 GB before the reader gave up, a negative one is 4 * 10^9 to it); every other value it reads
// as a number must be a whole one of its type, so that the reader keeps its place (the rest it skips
// as words).
template <class Failure>
BakeStatus checkPlyTextBody(std::istream& in, std::uint64_t size, const PlyLayout& layout, Failure failure) {
  // The reader splits words at any white space (\v and \f too) and reads a NUL as part of a word; the
  // walk below splits at blanks and stops a line at a NUL. So no other control byte may be there.
  const std::streamoff body = in.tellg();
  for (char c; in.get(c);) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\t' && c != '\r' && c != '\n')
      return failure("holds the control byte " + std::to_string(int(u)) + " after its header");
  }
  in.clear();
  in.seekg(body);
  std::string line;
  const char* at = line.c_str();
  const char *begin = nullptr, *end = nullptr;
  const auto next = [&] { return nextWord(in, &line, &at, &begin, &end); };
  for (const PlyElement& e : layout.elements) {
    for (std::uint64_t item = 0; item < e.count; ++item) {
      const std::string which = e.name + " " + std::to_string(item);
      for (const PlyProperty& p : e.properties) {
        // Short: the reader made up a face from the last one's numbers (tried), a copy that counts
        // again in the inside test.
        if (!next())
          return failure("header declares " + std::to_string(e.count) + " " + e.name +
                         " elements but the file ends in " + which + ": truncated, or a wrong count");
        const bool axis = e.name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z");
        if (axis && !finiteNumber(begin, end)) return failure(which + " " + notFinite(begin, end));
        if (!isFaceCorners(e, p)) {
          const std::string read = textRead(e, p);
          if (!read.empty() && !plyNumber(begin, end, read))
            return failure(which + " has " + p.name + " '" + std::string(begin, end).substr(0, 24) + "', not a whole " +
                           (read == "int" ? "integer" : "finite number") + " as the reader reads it");
          continue;
        }
        const std::string count(begin, end);
        const std::uint64_t corners = isCount(count) ? std::stoull(count) : UINT64_MAX;
        if (corners > size / 2)
          return failure(which + " claims '" + count.substr(0, 24) + "' corners, not a count the file can hold");
        for (std::uint64_t corner = 0; corner < corners; ++corner) {
          if (!next())
            return failure(which + " claims " + count + " corners and the file ends after " + std::to_string(corner));
          if (!plyNumber(begin, end, "int")) // read as an unsigned integer, whatever the declared type
            return failure(which + " lists '" + std::string(begin, end).substr(0, 24) + "', not a vertex index");
        }
      }
    }
    if (e.name == "face") break;
  }
  return BakeStatus::success();
}

// The same for a binary PLY: the corner counts of its faces must fit in the file (the reader reads as
// many indices as a count says, end of file or not). The reader reads one value per other property.
template <class Failure>
BakeStatus checkPlyBinaryBody(std::istream& in, std::uint64_t size, const PlyLayout& layout, Failure failure) {
  const bool big = layout.format == "binary_big_endian";
  const std::streamoff start = in.tellg();
  std::uint64_t left = start < 0 ? 0 : size - std::uint64_t(start);
  // Read in order (a seek per face cost two system calls each): skips, and each face's corner count.
  const auto skip = [&](std::uint64_t bytes) {
    if (bytes > left) return false;
    in.ignore(std::streamsize(bytes));
    left -= bytes;
    return true;
  };
  for (const PlyElement& e : layout.elements) {
    for (std::uint64_t item = 0; item < e.count; ++item) {
      for (const PlyProperty& p : e.properties) {
        if (!isFaceCorners(e, p)) {
          if (!skip(plyTypeSize(p.type))) return BakeStatus::success(); // short: the reader's to say
          continue;
        }
        unsigned char b[4] = {}; // plyLayoutProblem allows counts of 1, 2 or 4 bytes only
        const std::size_t width = std::min(plyTypeSize(p.count_type), sizeof b);
        if (width > left || !in.read(reinterpret_cast<char*>(b), std::streamsize(width))) return BakeStatus::success();
        left -= width;
        std::uint64_t count = 0;
        for (std::size_t n = 0; n < width; ++n)
          count |= std::uint64_t(b[big ? n : width - 1 - n]) << (8 * (width - 1 - n));
        if (count > left / plyTypeSize(p.type))
          return failure("face " + std::to_string(item) + " claims " + std::to_string(count) +
                         " corners, more than the " + std::to_string(left) + " bytes after it hold");
        skip(count * plyTypeSize(p.type));
      }
    }
    if (e.name == "face") break;
  }
  return BakeStatus::success();
}

// Where OpenMesh's header parse stands after the header line `raw`, which began at `line_start`: just
// after its last word, or, for a comment (whose whole line it skips), at `next_line`. From there it takes
// binary data to begin 12 bytes on (14 when a CR LF follows): "\nend_header\n".
std::streamoff afterLastWord(const std::string& raw, std::streamoff line_start, std::streamoff next_line) {
  std::string keyword;
  std::istringstream(raw) >> keyword;
  const std::size_t last = raw.find_last_not_of(" \t\r\v\f");
  if (keyword == "comment" || last == std::string::npos) return next_line;
  return line_start + std::streamoff(last + 1);
}

// Whether OpenMesh's reader takes a binary PLY's data to start where it does, at `in`'s position (just
// after the end_header line), when the last word before end_header ends at `after_last_word`.
bool binaryStartAgrees(std::istream& in, std::streamoff after_last_word) {
  const std::streamoff data = in.tellg();
  if (data < 0) return true; // no data at all: the reader's to say
  char c[2] = {};
  in.seekg(after_last_word);
  in.read(c, 2);
  in.clear();
  in.seekg(data);
  return after_last_word + (c[0] == '\r' && c[1] == '\n' ? 14 : 12) == data;
}

// The checks after end_header (`in` just past it): the layout, where binary data begins, the body.
BakeStatus checkPlyBody(std::istream& in, const std::string& path, std::uint64_t size, const PlyLayout& layout,
                        std::streamoff after_last_word) {
  const auto failure = [&](const std::string& where, const std::string& why) {
    return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': PLY " + where + why);
  };
  if (const std::string problem = plyLayoutProblem(layout); !problem.empty()) return failure("header ", problem);
  if (layout.format != "ascii" && !binaryStartAgrees(in, after_last_word))
    return failure("header ", "ends where OpenMesh's reader does not find its binary data (a comment or trailing "
                              "spaces just before end_header, or mixed line ends)");
  const auto body = [&](const std::string& why) { return failure("", why); };
  return layout.format == "ascii" ? checkPlyTextBody(in, size, layout, body)
                                  : checkPlyBinaryBody(in, size, layout, body);
}

} // namespace

// OpenMesh 9.0's PLY reader trusts its header: a malformed element count made it spin for 85 s and
// then throw, and a property before any element (a misspelt "element", found by fuzzing) crashed it.
// So the whole header must be well-formed before it sees the file.
BakeStatus checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const auto size = std::uint64_t(std::filesystem::file_size(path));
  auto failure = [&](const std::string& why) {
    return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': PLY header " + why);
  };
  std::string line;
  bool seen_element = false;
  PlyLayout layout;
  std::streamoff after_last_word = 0; // where OpenMesh's header parse stands (afterLastWord)
  for (int n = 1; n <= 1000; ++n) {
    const std::streamoff line_start = in.tellg();
    if (!std::getline(in, line)) break;
    const std::string raw = line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n == 1 && line != "ply") return failure("does not start with 'ply'");
    if (n == 1) continue;
    // OpenMesh takes the three words after "ply" for the format, whatever the first of them is, and a
    // version that is not a number fails its stream: its header loop then never ends (fuzzing: a comment
    // there, NUL bytes for a version).
    if (n == 2 && line.compare(0, 7, "format ") != 0)
      return failure("line 2 '" + line.substr(0, 40) + "' is not the format line, which OpenMesh reads there");
    if (line == "end_header") return checkPlyBody(in, path, size, layout, after_last_word);
    const std::string problem = plyLineProblem(line, size, &seen_element);
    if (!problem.empty()) return failure("line " + std::to_string(n) + " '" + line + "' " + problem);
    notePlyLine(line, &layout);
    after_last_word = afterLastWord(raw, line_start, in.tellg());
  }
  return failure("has no end_header line in its first 1000 lines");
}

} // namespace baker
} // namespace dng
