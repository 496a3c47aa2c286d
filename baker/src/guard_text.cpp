// The word and number readers the mesh guards share (guard_text.h).
#include "guard_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace dng {
namespace baker {
namespace guard {

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
std::string coordinateProblem(const char* at, int count) {
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

} // namespace guard
} // namespace baker
} // namespace dng
