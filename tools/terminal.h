// Shared by dngbake and dngdump: whether a progress line on stderr has a person to read it.
#pragma once

#include <cstdlib>
#include <cstring>

#include <unistd.h>

namespace dng {
namespace tools {

/// True when stderr is a terminal that draws "\r\033[K" redraws: never for a pipe, a log file, a
/// fuzzer or TERM=dumb.
inline bool stderrIsTerminal() {
  const char* term = std::getenv("TERM");
  return ::isatty(STDERR_FILENO) && term != nullptr && std::strcmp(term, "dumb") != 0;
}

} // namespace tools
} // namespace dng
