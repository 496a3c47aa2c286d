// Internal: the word and number readers the mesh guards (reader_guards.h) share: text read in place,
// line by line, as the guards read files of millions of lines before OpenMesh reads them again.
#pragma once

#include <cstddef>
#include <istream>
#include <string>

namespace dng {
namespace baker {
namespace guard {

/// A space, tab or carriage return: what separates words on a line.
bool blank(char c);
/// The first character at or after `at` that is not blank.
const char* skipBlanks(const char* at);
/// Where the word at `at` ends: at a blank or the end of the line.
const char* wordEnd(const char* at);
/// What the guards say of a coordinate that is not a finite number: its word, cut at 24 characters.
std::string notFinite(const char* begin, const char* end);
/// A line's first word, lower-cased, and in *out_rest where the rest begins.
std::string firstWord(const std::string& line, const char** out_rest);
/// Empty when the text at `at` starts with `count` (3, or 6 for a position and a normal) finite numbers
/// read whole as floats; else what is wrong with them.
std::string coordinateProblem(const char* at, int count = 3);
/// Whether `count` bytes are text: no control bytes but tabs and line ends.
bool looksLikeText(const char* bytes, std::size_t count);
/// Whether `s` is a plain count: digits only, fewer than 19.
bool isCount(const std::string& s);
/// Whether the word [begin, end) is a whole number that is finite as a float.
bool finiteNumber(const char* begin, const char* end);
/// The next word of `in` across lines, read in place in *io_line from *io_at. False at the end.
bool nextWord(std::istream& in, std::string* io_line, const char** io_at, const char** out_begin, const char** out_end);

} // namespace guard
} // namespace baker
} // namespace dng
