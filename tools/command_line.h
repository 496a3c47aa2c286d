// Shared by dngbake and dngdump: parse with CLI11 and map its own exit codes (100 and up) to the
// tools' documented ones: 0 after --help or --version, 1 for any usage error.
#pragma once

#include "exit_codes.h"

#include <CLI/CLI.hpp>

namespace dng {
namespace tools {

/// Parses argv into `app`. Returns -1 to go on; otherwise the exit code to return right away (CLI11
/// has already printed the help, version or error).
inline int parseOrExitCode(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return -1;
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
}

} // namespace tools
} // namespace dng
