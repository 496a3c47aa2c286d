// Runs a shell command as a user would and captures its stdout and exit code.
#pragma once

#include <cstdio>
#include <string>

#include <sys/wait.h>

namespace dng {
namespace testing {

struct ProgramRun {
  int exit_code = -1; ///< -1 when the program did not exit normally
  std::string output;
};

/// A path in double quotes for a command line (also inside a `bash -c '...'` one): a checkout whose path
/// has spaces builds its tools there. Paths with `"`, `$` or a backquote are not supported.
inline std::string shellQuoted(const std::string& path) { return "\"" + path + "\""; }

inline ProgramRun runProgram(const std::string& command) {
  ProgramRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr)
    run.output += buffer;
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

} // namespace testing
} // namespace dng
