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
         "', not a finite number written in decimal";
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

// Empty when the text at `at` starts with three coordinates, whole decimal numbers finite as floats;
// else what is wrong with them. OpenMesh's text readers take "nan" or "1e99" without a word, and its
// STL reader keeps a NaN vertex (merged with another). A comment may follow the last coordinate.
std::string coordinateProblem(const char* at) {
  for (int axis = 0; axis < 3; ++axis) {
    at = skipBlanks(at);
    if (*at == '\0' || *at == '#') return "has fewer than 3 coordinates";
    const char* end = at;
    while (*end != '\0' && *end != '#' && !blank(*end))
      ++end;
    if (!decimalNumber(at, end)) return notFinite(at, wordEnd(at));
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

// Whether [begin, end) is a whole decimal number that is finite as a float: an optional sign, digits
// with an optional fraction, an optional exponent. strtof alone would also take hex ("0x1p3"), which
// a stream reads as 0 and then fails its next read on the "x": the OFF reader then reads every later
// number wrong.
bool decimalNumber(const char* begin, const char* end) {
  const char* at = begin + (begin != end && (*begin == '+' || *begin == '-'));
  const auto digits = [&at, end] {
    const char* first = at;
    while (at != end && std::isdigit(static_cast<unsigned char>(*at)))
      ++at;
    return std::size_t(at - first);
  };
  std::size_t mantissa = digits();
  if (at != end && *at == '.') {
    ++at;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (at != end && (*at == 'e' || *at == 'E')) {
    at += 1 + (at + 1 != end && (at[1] == '+' || at[1] == '-'));
    if (digits() == 0) return false;
  }
  return at == end && finiteNumber(begin, end);
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
    if (at != io_line->data() + io_line->size()) { // a word, or a NUL byte: a word of its own
      *out_begin = at, *out_end = *io_at = *at == '\0' ? at + 1 : wordEnd(at);
      return true;
    }
    if (!std::getline(in, *io_line)) return false;
    *io_at = io_line->c_str();
  }
}

} // namespace guard
} // namespace baker
} // namespace dng
