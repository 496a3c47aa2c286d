// What a sample program printed: one flat JSON object per line, each naming its scene in "sample"
// ({"sample":"fig3a_bouncy","particles":400,...}). samples_test runs the programs and reads these.
#pragma once

#include <map>
#include <string>

namespace dng {
namespace testing {

/// The keys and values of one flat JSON object (no nesting, no escapes: what the samples print), the
/// values as written with string quotes removed. Empty when the line holds no object.
std::map<std::string, std::string> parseFlatJson(const std::string& line);

struct SampleOutput {
  int exit_code = -1; ///< -1 when the program did not exit normally
  std::string text;   ///< everything it printed on stdout, for failure messages
  /// Every numeric value, by the line's "sample" name and then by key; lines of one name are merged.
  std::map<std::string, std::map<std::string, double>> numbers;

  /// numbers[sample][key], or NaN when absent, so that any comparison with a missing value fails.
  double get(const std::string& sample, const std::string& key) const;
};

/// Runs a shell command line and reads its output as sample lines.
SampleOutput runSample(const std::string& command);

} // namespace testing
} // namespace dng
