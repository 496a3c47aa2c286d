// Internal to the writer: helpers both encoders share.
#pragma once

#include "dng/format/writer.h"

#include <string_view>

namespace dng {
namespace format {

/// GRID section for `g` with the encoding-independent fields filled and the bricked ones zero.
GridSection makeGridSection(const GridGeometry& g, Encoding encoding);

/// Adds the required GRID section and, when `metadata_json` is not empty, the optional META one.
void addCommonSections(ContainerBuilder& builder, const GridSection& grid, std::string_view metadata_json);

} // namespace format
} // namespace dng
