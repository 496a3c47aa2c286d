// Printing JSON that holds untrusted text (dump_json.h).
#include "dump_json.h"

#include <algorithm>

namespace dng {
namespace dump {

namespace {

// Deepest bracket nesting outside strings; stops counting once past `limit`. Malformed text may give a
// wrong answer, which is harmless: the parser rejects it anyway.
int nestingDepth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) break;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

} // namespace

std::string toText(const Json& j, int indent) { return j.dump(indent, ' ', false, Json::error_handler_t::replace); }

Json metadataJson(std::string_view text) {
  if (text.empty()) return nullptr;
  if (nestingDepth(text, kMaxMetadataDepth) <= kMaxMetadataDepth) {
    Json parsed = Json::parse(text.begin(), text.end(), nullptr, false);
    if (!parsed.is_discarded()) return parsed;
  }
  return Json(std::string(text)); // unparsable or too deep: kept as text
}

} // namespace dump
} // namespace dng
