// The exit codes of dngbake and dngdump: one table for both tools, documented in docs/BAKING.md
// ("Exit codes"). Scripts depend on these numbers; never renumber one.
#pragma once

namespace dng {
namespace tools {

enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 1,        ///< bad command line or option value
  kExitIo = 2,           ///< a file could not be read or written
  kExitInvalid = 3,      ///< the input is unusable: a mesh that cannot be baked, a .dng that breaks a rule
  kExitInternal = 4,     ///< a bug or a resource failure (out of memory)
  kExitUnsupported = 5,  ///< a format or feature this build does not handle
  kExitInterrupted = 130 ///< SIGINT or SIGTERM stopped the work; nothing was written (128 + SIGINT)
};

} // namespace tools
} // namespace dng
