#include "sample_output.h"

#include "run_program.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace dng {
namespace testing {

std::map<std::string, std::string> parseFlatJson(const std::string& line) {
  std::map<std::string, std::string> out;
  std::size_t i = line.find('{');
  while (i != std::string::npos && line[i] != '}') {
    const std::size_t key_start = line.find('"', i + 1);
    const std::size_t key_end = key_start == std::string::npos ? key_start : line.find('"', key_start + 1);
    if (key_end == std::string::npos || key_end + 2 >= line.size() || line[key_end + 1] != ':') break;
    const std::size_t value_start = key_end + 2;
    std::size_t value_end = 0;
    if (line[value_start] == '"') { // a string: up to the closing quote
      value_end = line.find('"', value_start + 1);
      if (value_end == std::string::npos) break;
      out[line.substr(key_start + 1, key_end - key_start - 1)] =
          line.substr(value_start + 1, value_end - value_start - 1);
      ++value_end;
    } else { // a number: up to the next separator
      value_end = line.find_first_of(",}", value_start);
      if (value_end == std::string::npos) break;
      out[line.substr(key_start + 1, key_end - key_start - 1)] = line.substr(value_start, value_end - value_start);
    }
    i = line.find_first_of(",}", value_end);
  }
  return out;
}

double SampleOutput::get(const std::string& sample, const std::string& key) const {
  const auto by_sample = numbers.find(sample);
  if (by_sample == numbers.end()) return std::nan("");
  const auto value = by_sample->second.find(key);
  return value == by_sample->second.end() ? std::nan("") : value->second;
}

SampleOutput runSample(const std::string& command) {
  const ProgramRun run = runProgram(command);
  SampleOutput output;
  output.exit_code = run.exit_code;
  output.text = run.output;
  std::istringstream lines(run.output);
  for (std::string line; std::getline(lines, line);) {
    const std::map<std::string, std::string> fields = parseFlatJson(line);
    const auto name = fields.find("sample");
    if (name == fields.end()) continue;
    for (const auto& [key, text] : fields) {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (key != "sample" && !text.empty() && *end == '\0') output.numbers[name->second][key] = value;
    }
  }
  return output;
}

} // namespace testing
} // namespace dng
