// Internal to dngdump: JSON built from untrusted file contents, made safe to print. A .dng's metadata
// and its section tags are arbitrary bytes; nlohmann's serializer throws on invalid UTF-8 and recurses
// once per nesting level, so neither may reach it unguarded.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace dng {
namespace dump {

using Json = nlohmann::ordered_json;

/// Deepest metadata nesting shown as JSON; deeper text is shown as a string (the serializer's recursion
/// must stay far from the stack's end, and no bake writes more than a few levels).
inline constexpr int kMaxMetadataDepth = 64;

/// `j` as text, never throwing: bytes that are not UTF-8 become U+FFFD. indent < 0: one line.
std::string toText(const Json& j, int indent = 2);

/// The META section's text as JSON: parsed when it is valid JSON no deeper than kMaxMetadataDepth,
/// otherwise kept as a string (print it with toText). Null when empty.
Json metadataJson(std::string_view text);

} // namespace dump
} // namespace dng
