// The guards against inputs OpenMesh's readers mishandle (reader_guards.h).
#include "reader_guards.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace dng {
namespace baker {

namespace {

bool isPlyType(const std::string& t) {
  static const char* const kTypes[] = {"char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                                       "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  return std::find(std::begin(kTypes), std::end(kTypes), t) != std::end(kTypes);
}

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

const char* skipBlanks(const char* at) {
  while (blank(*at))
    ++at;
  return at;
}

// Where the word at `at` ends: at a blank or the end of the line.
const char* wordEnd(const char* at) {
  while (*at != '\0' && !blank(*at))
    ++at;
  return at;
}

// What the guards say of a coordinate that is not a finite number: its word, cut at 24 characters.
std::string notFinite(const char* begin, const char* end) {
  return "has coordinate '" + std::string(begin, std::min<std::size_t>(std::size_t(end - begin), 24)) +
         "', not a finite number";
}

// A text line's first word, lower-cased (STL keywords may be upper case), and where the rest begins.
// In place: the guards read every line of files of millions of lines before OpenMesh reads them again.
std::string firstWord(const std::string& line, const char** out_rest) {
  const char* at = skipBlanks(line.c_str());
  std::string word;
  for (; *at != '\0' && !blank(*at); ++at)
    word += char(std::tolower(static_cast<unsigned char>(*at)));
  *out_rest = at;
  return word;
}

// Empty when the text at `at` starts with three coordinates, numbers read whole and finite as floats;
// else what is wrong with them. OpenMesh's text readers take "nan" or "1e99" without a word, and its
// STL reader keeps a NaN vertex (merged with another).
// `count` 6: a position and a normal (NOFF), as many numbers read from the same stream.
std::string coordinateProblem(const char* at, int count = 3) {
  for (int axis = 0; axis < count; ++axis) {
    at = skipBlanks(at);
    if (*at == '\0' || *at == '#')
      return count == 3 ? "has fewer than 3 coordinates" : "has fewer than 6 numbers, its position and normal";
    char* end = nullptr;
    const float value = std::strtof(at, &end); // infinite when beyond a float, as the readers' floats
    if (end == at || !(*end == '\0' || *end == '#' || blank(*end)) || !std::isfinite(value))
      return notFinite(at, wordEnd(at));
    at = end;
  }
  return {};
}

// Whether the start of a file is text: no control bytes but tabs and line ends (a binary STL's header
// may start with "solid" too, as some exporters write it).
bool looksLikeText(const char* bytes, std::size_t count) {
  for (std::size_t n = 0; n < count; ++n) {
    const auto c = static_cast<unsigned char>(bytes[n]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') return false;
  }
  return true;
}

bool isCount(const std::string& s) {
  return !s.empty() && s.size() < 19 &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// [ST][C][N][4][n]OFF, the OFF magic and its variants.
bool isOffVariant(const std::string& keyword) {
  std::size_t at = 0;
  for (const char* optional : {"ST", "C", "N", "4", "n"}) {
    const std::size_t n = std::strlen(optional);
    if (keyword.compare(at, n, optional) == 0) at += n;
  }
  return keyword.compare(at, std::string::npos, "OFF") == 0;
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

// Whether the word [begin, end) is a whole number that is finite as a float.
bool finiteNumber(const char* begin, const char* end) {
  char* stop = nullptr;
  const float value = std::strtof(begin, &stop);
  return stop == end && end != begin && std::isfinite(value);
}

// The next word of `in` across lines (blank lines and line breaks are only space to a PLY reader),
// read in place in *io_line from *io_at. False at the end of the file.
bool nextWord(std::istream& in, std::string* io_line, const char** io_at, const char** out_begin,
              const char** out_end) {
  for (;;) {
    const char* at = skipBlanks(*io_at);
    if (*at != '\0') {
      *out_begin = at, *out_end = *io_at = wordEnd(at);
      return true;
    }
    if (!std::getline(in, *io_line)) return false;
    *io_at = io_line->c_str();
  }
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
  const char* at = begin + (begin != end && (*begin == '+' || *begin == '-'));
  const char* digits = at;
  while (at != end && std::isdigit(static_cast<unsigned char>(*at)))
    ++at;
  if (!isFloatType(type)) return at != digits && at == end && at - digits <= 9;
  std::size_t mantissa = std::size_t(at - digits);
  if (at != end && *at == '.') {
    const char* fraction = ++at;
    while (at != end && std::isdigit(static_cast<unsigned char>(*at)))
      ++at;
    mantissa += std::size_t(at - fraction);
  }
  if (mantissa == 0) return false;
  if (at != end && (*at == 'e' || *at == 'E')) {
    at += 1 + (at + 1 != end && (at[1] == '+' || at[1] == '-'));
    const char* exponent = at;
    while (at != end && std::isdigit(static_cast<unsigned char>(*at)))
      ++at;
    if (at == exponent) return false;
  }
  return at == end && finiteNumber(begin, end);
}

// How OpenMesh's ASCII reader reads property `p` of element `e`: "float" (positions, normals, texture
// coordinates, whatever their declared type, and float colours), "int" (other colours, double ones
// too), or "" for a word it skips.
std::string textRead(const PlyElement& e, const PlyProperty& p) {
  static const char* const kFloats[] = {"x", "y", "z", "nx", "ny", "nz", "u", "s", "v", "t"};
  static const char* const kColours[] = {"red",         "green",         "blue",        "alpha",
                                         "diffuse_red", "diffuse_green", "diffuse_blue"};
  const auto in = [&p](const auto& names) {
    return std::find(std::begin(names), std::end(names), p.name) != std::end(names);
  };
  if (e.name == "vertex" && in(kFloats)) return "float";
  const bool colour = (e.name == "vertex" && in(kColours)) ||
                      (e.name == "face" && in(kColours) && p.name.compare(0, 8, "diffuse_") != 0);
  if (!colour) return "";
  return p.type == "float" || p.type == "float32" ? "float" : "int";
}

// What OpenMesh 9.0's binary PLY reader cannot read in place, found by trying every type: a vertex's
// position, normal or texture coordinate of an integer type, and a colour in double precision. It reads
// such a value as nothing or as a float, and every value after it from the wrong bytes.
std::string plyBinaryTypeProblem(const PlyElement& e, const PlyProperty& p) {
  static const char* const kFloats[] = {"x", "y", "z", "nx", "ny", "nz", "u", "s", "v", "t"};
  static const char* const kColours[] = {"red",         "green",         "blue",        "alpha",
                                         "diffuse_red", "diffuse_green", "diffuse_blue"};
  const bool float_read =
      e.name == "vertex" && std::find(std::begin(kFloats), std::end(kFloats), p.name) != std::end(kFloats);
  const bool colour = (e.name == "vertex" || e.name == "face") &&
                      std::find(std::begin(kColours), std::end(kColours), p.name) != std::end(kColours);
  if ((float_read && !isFloatType(p.type)) || (colour && plyTypeSize(p.type) == 8))
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
        if (!next()) return BakeStatus::success(); // short: the reader's to say
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
        if (!isCount(count) || std::stoull(count) > size / 2)
          return failure(which + " claims '" + count.substr(0, 24) + "' corners, not a count the file can hold");
        for (std::uint64_t corner = 0; corner < std::stoull(count); ++corner) {
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

} // namespace

namespace {

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
  // Where OpenMesh's reader ends its header: just after the last word it read before end_header (after
  // a comment's whole line), as the stream's position, from which it takes binary data to begin 12 bytes
  // on (14 when a CR LF follows).
  std::streamoff after_last_word = 0, line_start = 0;
  for (int n = 1; n <= 1000 && (line_start = in.tellg(), std::getline(in, line)); ++n) {
    const std::string raw = line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n == 1 && line != "ply") return failure("does not start with 'ply'");
    if (n == 1) continue;
    if (line == "end_header") {
      if (const std::string problem = plyLayoutProblem(layout); !problem.empty()) return failure(problem);
      const auto body = [&](const std::string& why) {
        return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': PLY " + why);
      };
      if (layout.format != "ascii" && !binaryStartAgrees(in, after_last_word))
        return failure("ends where OpenMesh's reader does not find its binary data (a comment or trailing spaces "
                       "just before end_header, or mixed line ends)");
      return layout.format == "ascii" ? checkPlyTextBody(in, size, layout, body)
                                      : checkPlyBinaryBody(in, size, layout, body);
    }
    const std::string problem = plyLineProblem(line, size, &seen_element);
    if (!problem.empty()) return failure("line " + std::to_string(n) + " '" + line + "' " + problem);
    notePlyLine(line, &layout);
    const std::size_t last = raw.find_last_not_of(" \t\r\v\f");
    std::string keyword;
    std::istringstream(raw) >> keyword;
    if (keyword == "comment") // the reader skips the rest of a comment's line, its line end too
      after_last_word = in.tellg();
    else if (last != std::string::npos)
      after_last_word = line_start + std::streamoff(last + 1);
  }
  return failure("has no end_header line in its first 1000 lines");
}

namespace {

// The next number as OpenMesh's `in >> unsigned` reads one: blanks (line ends too) skipped, then a sign
// and the digits after it, the rest of the word left for the next read ("0-4" is 0, then -4). Empty
// when no digit follows: the stream then fails, and so does every later read.
std::string nextUnsigned(std::istream& in) {
  in >> std::ws;
  std::string number;
  if (in.peek() == '+' || in.peek() == '-') number += char(in.get());
  while (std::isdigit(in.peek()))
    number += char(in.get());
  return number.find_first_of("0123456789") == std::string::npos ? std::string() : number;
}

// What an unsigned read makes of `number` (nextUnsigned's): more than `limit` when it is above it,
// negative (unsigned arithmetic makes -4 a count of 4 * 10^9) or beyond any integer.
std::uint64_t unsignedValue(const std::string& number, std::uint64_t limit) {
  const bool negative = number[0] == '-';
  const std::string digits = number.substr(number[0] == '+' || negative ? 1 : 0);
  const std::size_t first = std::min(digits.find_first_not_of('0'), digits.size());
  if (first == digits.size()) return 0; // zero, with any sign
  if (negative || digits.size() - first > 18) return limit + 1;
  return std::stoull(digits.substr(first));
}

} // namespace

// Each vertex line must start with three finite coordinates (six numbers with NOFF's normal: one the
// stream cannot read fails it, and each face then reads the vertex count as its valence), and each
// face must list as many indices
// as its valence says: OpenMesh reserved room for a valence of 3 * 10^86 (read as a huge number) and
// tried to allocate 2 GB (found by fuzzing). OpenMesh reads a vertex per line but the faces as one
// stream of numbers, line ends included (a face's valence may follow another face's indices on its
// line), each read as far as its digits go, so the faces are checked the same way: read line by line,
// a valence after a face of valence 0 had passed unchecked, and read word by word, an index "0-4" had
// hidden the valence -4 that OpenMesh read after its 0; each made it allocate 2 GB (fuzzing).
template <class Failure>
BakeStatus checkOffBody(std::istream& in, std::uint64_t size, std::uint64_t vertices, std::uint64_t faces, int numbers,
                        Failure failure) {
  std::string line;
  for (std::uint64_t vertex = 0; vertex < vertices && std::getline(in, line);) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue; // a blank line is only space to the reader
    // The reader reads "#" as a coordinate, fails, and then reads every face's valence as the vertex
    // count: faces times vertices of work, and no mesh.
    if (line[first] == '#')
      return failure("vertex " + std::to_string(vertex) + " is a comment line: OpenMesh's reader cannot skip it");
    const std::string problem = coordinateProblem(line.c_str() + first, numbers);
    if (!problem.empty()) return failure("vertex " + std::to_string(vertex) + " " + problem);
    ++vertex;
  }
  for (std::uint64_t face = 0; face < faces; ++face) {
    in >> std::ws;
    if (in.peek() == std::char_traits<char>::eof()) break; // short: no more faces, and OpenMesh reads none
    const std::string valence = nextUnsigned(in);
    // At least a digit and a space per index.
    if (valence.empty() || unsignedValue(valence, size / 2) > size / 2) {
      in.clear();
      std::string word;
      in >> word;
      return failure("face " + std::to_string(face) + " claims '" + (valence.empty() ? word : valence).substr(0, 20) +
                     "' vertices, not a count of indices the file can hold");
    }
    const std::uint64_t claimed = unsignedValue(valence, size / 2);
    for (std::uint64_t listed = 0; listed < claimed; ++listed) {
      in >> std::ws;
      if (in.peek() == std::char_traits<char>::eof())
        return failure("face " + std::to_string(face) + " claims " + valence + " vertices and the file ends after " +
                       std::to_string(listed));
      // Beyond 32 bits the read fails, and every later one: each later face reads the last valence.
      const std::string index = nextUnsigned(in);
      if (index.empty() || unsignedValue(index, UINT32_MAX) > UINT32_MAX) {
        std::string word = index;
        in.clear();
        if (word.empty()) in >> word;
        return failure("face " + std::to_string(face) + " lists '" + word.substr(0, 20) + "', not a vertex index");
      }
    }
  }
  return BakeStatus::success();
}

namespace {

// A little-endian 32-bit word from `in`; false at the end of the file.
bool readLittle32(std::istream& in, std::uint32_t* out) {
  unsigned char b[4];
  if (!in.read(reinterpret_cast<char*>(b), sizeof b)) return false;
  *out = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
  return true;
}

// Whether OpenMesh reads an OFF file whose first line is `line`, keyword `keyword`, as binary: it
// looks for BINARY exactly one character after the keyword (so "OFF  BINARY" is read as text).
bool openMeshReadsBinary(const std::string& line, const std::string& keyword) {
  return line.compare(0, keyword.size(), keyword) == 0 && line.size() >= keyword.size() + 7 &&
         line.compare(keyword.size() + 1, 6, "BINARY") == 0;
}

} // namespace

// A binary OFF after its keyword's line, as OpenMesh 9.0 reads one (with the baker's reading options):
// little-endian 32-bit counts of vertices, faces and edges; each vertex three floats, then three more
// for N, three 32-bit colour words for C and two floats for ST; each face a 32-bit valence and as
// many indices. The reader reads as many faces as the count says, end of file or not: a count or a
// valence the file cannot hold kept it reading for ever (found seeding the fuzzer with a binary OFF).
template <class Failure>
BakeStatus checkOffBinary(std::istream& in, std::uint64_t size, const std::string& keyword, Failure failure) {
  const std::string prefix = keyword.substr(0, keyword.size() - 3);
  const std::uint64_t record = 12 + (prefix.find('N') != std::string::npos ? 12 : 0) +
                               (prefix.find('C') != std::string::npos ? 12 : 0) + (prefix.rfind("ST", 0) == 0 ? 8 : 0);
  std::uint32_t vertices = 0, faces = 0, edges = 0;
  if (!readLittle32(in, &vertices) || !readLittle32(in, &faces) || !readLittle32(in, &edges))
    return failure("binary file ends before its vertex, face and edge counts");
  std::uint64_t left = size - std::uint64_t(in.tellg());
  if (vertices > left / record)
    return failure("binary header declares " + std::to_string(vertices) + " vertices of " + std::to_string(record) +
                   " bytes, more than the " + std::to_string(left) + " bytes after it");
  left -= vertices * record;
  if (faces > left / 4)
    return failure("binary header declares " + std::to_string(faces) + " faces, more than the " + std::to_string(left) +
                   " bytes after the vertices can hold");
  in.seekg(std::streamoff(vertices * record), std::ios::cur);
  for (std::uint32_t face = 0; face < faces; ++face) {
    std::uint32_t valence = 0;
    if (!readLittle32(in, &valence))
      return failure("binary file ends before face " + std::to_string(face) + " of " + std::to_string(faces));
    left -= 4;
    if (valence > left / 4)
      return failure("face " + std::to_string(face) + " claims " + std::to_string(valence) +
                     " vertices, more than the file holds");
    in.ignore(std::streamsize(valence) * 4);
    left -= std::uint64_t(valence) * 4;
  }
  return BakeStatus::success();
}

// OpenMesh 9.0's OFF reader trusts the counts too: "OFF\n0 -1 2" (a negative face count, found by
// fuzzing) kept it reading for more than 10 s. The counts must be plain numbers the file can hold.
BakeStatus checkOffHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const auto size = std::uint64_t(std::filesystem::file_size(path));
  auto failure = [&](const std::string& why) {
    return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': OFF " + why);
  };
  std::string first_line;
  std::getline(in, first_line);
  // No "OFF" at all: not an OFF file (OpenMesh's reader refused it as if it could not read it, an I/O
  // error, where the other formats' garbage is invalid input). Anything else must be one of the
  // variants [ST][C][N][4][n]OFF [BINARY], alone on its line.
  if (first_line.find("OFF") == std::string::npos)
    return failure(size == 0 ? "file is empty" : "file has no OFF keyword on its first line");
  std::istringstream words(first_line);
  std::string keyword, binary;
  words >> keyword >> binary;
  if (!isOffVariant(keyword) || (!binary.empty() && binary != "BINARY" && !isCount(binary)))
    return failure("header '" + first_line.substr(0, 40) + "' is not OFF, COFF, NOFF, STOFF, 4OFF or nOFF");
  // OpenMesh reads the counts after the keyword's line: on it, they went unread ("no faces"), and the
  // guard, reading them there, had passed a file whose counts OpenMesh took from the vertices (a count
  // of 3 * 10^11 kept it reading for ever: found by fuzzing).
  if (isCount(binary))
    return failure("header '" + first_line.substr(0, 40) + "' has its counts on the keyword's line: OpenMesh " +
                   "reads them from the next line");
  // OpenMesh refuses the n-dimensional and 4D variants itself.
  if (keyword.find('n') != std::string::npos || keyword.find('4') != std::string::npos) return BakeStatus::success();
  if (openMeshReadsBinary(first_line, keyword)) return checkOffBinary(in, size, keyword, failure);
  // The next three words, across lines, as OpenMesh reads them (a comment there is not a count to it).
  std::vector<std::string> counts;
  for (std::string word; counts.size() < 3 && in >> word;)
    counts.push_back(word);
  if (counts.size() < 3) return failure("header does not give vertex, face and edge counts");
  // The rest of the counts' line is not skipped: OpenMesh goes on reading there too (with no vertices,
  // its faces begin there: fuzzing).
  for (std::size_t n = 0; n < 3; ++n) {
    if (!isCount(counts[n])) return failure("header count '" + counts[n] + "' is not a number");
  }
  // At least "0 0 0" and a line end per vertex and a digit and a line end per face.
  const std::uint64_t vertices = std::stoull(counts[0]), faces = std::stoull(counts[1]);
  if (vertices > size / 6 || faces > size / 2)
    return failure("header counts " + counts[0] + " " + counts[1] + " are impossible in a file of " +
                   std::to_string(size) + " bytes");
  // OpenMesh reads a NOFF vertex's normal from the stream too (the rest of its line it reads apart).
  const int numbers = keyword.find('N') != std::string::npos ? 6 : 3;
  return checkOffBody(in, size, vertices, faces, numbers, failure);
}

BakeStatus checkStlCoordinates(const std::string& path) {
  const auto failure = [&](const std::string& where, const std::string& problem) {
    return BakeStatus::failure(BakeError::kInvalidInput, "'" + path + "': " + where + " " + problem);
  };
  std::ifstream in(path, std::ios::binary);
  if (declaredStlFacets(path) >= 0) { // binary: 50-byte facets of a normal, three vertices, two bytes
    in.seekg(84);
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
  in.read(start, sizeof start);
  const auto size = std::uint64_t(std::filesystem::file_size(path));
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

long long declaredStlFacets(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[84];
  if (!in.read(header, sizeof header)) return -1;
  std::uint32_t count;
  std::memcpy(&count, header + 80, 4);
  const auto size = std::uint64_t(std::filesystem::file_size(path));
  return size == 84 + 50 * std::uint64_t(count) ? (long long)count : -1;
}

BakeStatus checkObjLines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (std::uint64_t number = 1; std::getline(in, line); ++number) {
    const char* rest = nullptr;
    const std::string keyword = firstWord(line, &rest);
    if (keyword == "v") {
      const std::string problem = coordinateProblem(rest);
      if (!problem.empty())
        return BakeStatus::failure(BakeError::kInvalidInput,
                                   "'" + path + "': line " + std::to_string(number) + ": vertex " + problem);
    }
    if (keyword != "f") continue;
    // The whole rest of the line, NUL bytes and all, as OpenMesh's reader sees it: from `rest` as a C
    // string the words after a NUL went unchecked, and a '/1' there made the reader abort (fuzzing).
    std::istringstream words(std::string(rest, line.c_str() + line.size()));
    for (std::string vertex; words >> vertex;) {
      if (vertex.front() == '/')
        return BakeStatus::failure(BakeError::kInvalidInput,
                                   "'" + path + "': line " + std::to_string(number) + ": face vertex '" + vertex +
                                       "' has no vertex index (OBJ needs v, v/vt, v//vn or v/vt/vn)");
    }
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
