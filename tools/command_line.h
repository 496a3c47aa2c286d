// Shared by dngbake and dngdump: parse with CLI11 and map its own exit codes (100 and up) to the
// tools' documented ones: 0 after --help or --version, 1 for any usage error.
#pragma once

#include "exit_codes.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

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

/// A whole number from 0 to 2^31 - 1, refused in one line (CLI11's own range checks print the whole
/// range of a double).
inline CLI::Validator wholeAtLeastZero() {
  return CLI::Validator(
      [](std::string& text) {
        char* end = nullptr;
        const long value = std::strtol(text.c_str(), &end, 10);
        return end != text.c_str() && *end == '\0' && value >= 0 && value <= INT32_MAX
                   ? std::string()
                   : "must be a whole number >= 0, got '" + text + "'";
      },
      "INDEX");
}

/// A number > 0 that is a normal float (what the option stores: 1e-46 would be 0, 1e39 infinity),
/// refused in one line.
inline CLI::Validator finitePositive() {
  return CLI::Validator(
      [](std::string& text) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        return end != text.c_str() && *end == '\0' && value > 0.0 && std::isnormal(float(value))
                   ? std::string()
                   : "must be a finite number > 0, got '" + text + "'";
      },
      "POSITIVE");
}

} // namespace tools
} // namespace dng
