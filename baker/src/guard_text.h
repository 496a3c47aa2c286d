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
/// Empty when the text at `at` starts with three coordinates, each a whole decimalNumber (a comment may
/// follow the last); else what is wrong with them.
std::string coordinateProblem(const char* at);
/// Whether `count` bytes are text: no control bytes but tabs and line ends.
bool looksLikeText(const char* bytes, std::size_t count);
/// Whether `s` is a plain count: digits only, fewer than 19.
bool isCount(const std::string& s);
/// Whether the word [begin, end) is a whole number that is finite as a float (strtof's syntax).
bool finiteNumber(const char* begin, const char* end);
/// Whether the word [begin, end) is a whole finite number as a stream reads one into a float: decimal,
/// with an optional sign, fraction and exponent; no "nan", "inf" or hex.
bool decimalNumber(const char* begin, const char* end);
/// The next word of `in` across lines, read in place in *io_line from *io_at (which must point into
/// *io_line, its end included). A NUL byte is a word of its own. False at the end of the file.
bool nextWord(std::istream& in, std::string* io_line, const char** io_at, const char** out_begin, const char** out_end);

} // namespace guard
} // namespace baker
} // namespace dng
