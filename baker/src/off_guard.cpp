// The OFF guard (reader_guards.h checkOffHeader): counts, vertices and faces as OpenMesh 9.0's reader
// reads them, ASCII or binary.
#include "guard_text.h"
#include "reader_guards.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace dng {
namespace baker {

using namespace guard;

namespace {

// [ST][C][N][4][n]OFF, the OFF magic and its variants.
bool isOffVariant(const std::string& keyword) {
  std::size_t at = 0;
  for (const char* optional : {"ST", "C", "N", "4", "n"}) {
    const std::size_t n = std::strlen(optional);
    if (keyword.compare(at, n, optional) == 0) at += n;
  }
  return keyword.compare(at, std::string::npos, "OFF") == 0;
}

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

// For a message: `number` (nextUnsigned's), or when it is empty the word the read stopped at.
std::string offendingWord(std::istream& in, const std::string& number) {
  std::string word = number;
  in.clear();
  if (word.empty()) in >> word;
  return word.substr(0, 20);
}

// What is wrong with a vertex's `count` numbers (3, or 6 with NOFF's normal), empty when nothing is.
// OpenMesh reads them with the stream's `>>`, so across blank lines and line ends, and then the rest
// of the last one's line apart (its colours): *io_line and *io_at are where the reading stands, and
// the rest of the line is dropped when the vertex is read. A number must be a whole decimal word,
// finite as a float; a comment may follow the last one. `*out_end` is set when the file ends before
// the vertex.
std::string vertexProblem(std::istream& in, int count, std::string* io_line, const char** io_at, bool* out_end) {
  const char* const fewer =
      count == 3 ? "has fewer than 3 coordinates" : "has fewer than 6 numbers, its position and normal";
  for (int read = 0; read < count; ++read) {
    const char *begin = nullptr, *end = nullptr;
    if (!nextWord(in, io_line, io_at, &begin, &end)) {
      *out_end = read == 0; // the file ends before this vertex
      return read == 0 ? std::string() : fewer;
    }
    // The reader reads "#" (or a NUL byte) as a number, fails, and then reads every face's valence as
    // the vertex count: faces times vertices of work, and no mesh.
    if (*begin == '#') return read == 0 ? "is a comment line: OpenMesh's reader cannot skip it" : fewer;
    if (*begin == '\0') return "has a NUL byte where a number is due";
    const char* number_end = std::find(begin, end, '#');
    if (!decimalNumber(begin, number_end)) return notFinite(begin, number_end);
    if (number_end != end && read + 1 < count) return fewer; // the next read starts at the comment
  }
  *io_at = io_line->c_str() + io_line->size();
  return {};
}

// Each vertex must start with finite coordinates (vertexProblem; a number the stream cannot read fails
// it, and each face then reads the vertex count as its valence), and each face must list as many
// indices as its valence says: OpenMesh reserved room for a valence of 3 * 10^86 (read as a huge
// number) and tried to allocate 2 GB (found by fuzzing). OpenMesh reads the faces as one stream
// of numbers, line ends included (a face's valence may follow another face's indices on its line), each read as far as
// its digits go, so the faces are checked the same way: read line by line, a valence after a face of valence 0 had
// passed unchecked, and read word by word, an index "0-4" had hidden the valence -4 that OpenMesh read after its 0;
// each made it allocate 2 GB (fuzzing).
template <class Failure>
BakeStatus checkOffBody(std::istream& in, std::uint64_t size, std::uint64_t vertices, std::uint64_t faces, int numbers,
                        Failure failure) {
  // A file that ends before its counts do is refused: OpenMesh's reads fail from there on, and it made
  // each missing face from the last face's numbers (tried). A 300 kB file of one large triangle and
  // blanks became 100,000 copies of it, which took the bake 23 GB; copies of a small face would each
  // count again in the winding number's inside test.
  const auto truncated = [&](const char* what, std::uint64_t declared, std::uint64_t read) {
    return failure("header declares " + std::to_string(declared) + " " + what + " but the file ends after " +
                   std::to_string(read) + ": truncated, or a wrong count");
  };
  std::string line;
  const char* at = line.c_str();
  for (std::uint64_t vertex = 0; vertex < vertices; ++vertex) {
    bool file_ended = false;
    const std::string problem = vertexProblem(in, numbers, &line, &at, &file_ended);
    if (file_ended) return truncated("vertices", vertices, vertex);
    if (!problem.empty()) return failure("vertex " + std::to_string(vertex) + " " + problem);
  }
  for (std::uint64_t face = 0; face < faces; ++face) {
    in >> std::ws;
    if (in.peek() == std::char_traits<char>::eof()) return truncated("faces", faces, face);
    const std::string valence = nextUnsigned(in);
    // At least a digit and a space per index.
    const std::uint64_t claimed = valence.empty() ? UINT64_MAX : unsignedValue(valence, size / 2);
    if (claimed > size / 2)
      return failure("face " + std::to_string(face) + " claims '" + offendingWord(in, valence) +
                     "' vertices, not a count of indices the file can hold");
    for (std::uint64_t listed = 0; listed < claimed; ++listed) {
      in >> std::ws;
      if (in.peek() == std::char_traits<char>::eof())
        return failure("face " + std::to_string(face) + " claims " + valence + " vertices and the file ends after " +
                       std::to_string(listed));
      // Beyond 32 bits the read fails, and every later one: each later face reads the last valence.
      const std::string index = nextUnsigned(in);
      if (index.empty() || unsignedValue(index, UINT32_MAX) > UINT32_MAX)
        return failure("face " + std::to_string(face) + " lists '" + offendingWord(in, index) +
                       "', not a vertex index");
    }
  }
  return BakeStatus::success();
}

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

} // namespace

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
  // OpenMesh reads a NOFF vertex's normal from the stream too, on the position's line or after it.
  const int numbers = keyword.find('N') != std::string::npos ? 6 : 3;
  return checkOffBody(in, size, vertices, faces, numbers, failure);
}

} // namespace baker
} // namespace dng
