// Shared by dngbake and dngdump: whether what they printed on standard output got there.
#pragma once

#include "exit_codes.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace dng {
namespace tools {

/// Flushes standard output and returns `code`; or, when anything written there was lost (a full disk,
/// /dev/full), prints why on stderr and returns kExitIo in place of kExitOk (another failure keeps its
/// own code). A script that reads a report, a JSON document or query answers must not take a cut one
/// for a whole one. `tool` names the program in the message.
inline int finishStandardOutput(const char* tool, int code) {
  errno = 0;
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return code;
  const int error = errno; // 0 when the write that failed was an earlier one, long since returned
  std::fprintf(stderr, "%s: error: cannot write to standard output: %s\n", tool,
               error != 0 ? std::strerror(error) : "an earlier write failed");
  return code == kExitOk ? kExitIo : code;
}

} // namespace tools
} // namespace dng
