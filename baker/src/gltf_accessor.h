// Reading glTF accessors with every bound checked first: tinygltf parses the JSON and the buffers but
// leaves offsets, strides, counts and indices to the caller (import_gltf.cpp).
#pragma once

#include "stages.h"

#include <tiny_gltf.h>

#include <cstdint>
#include <vector>

namespace dng {
namespace baker {

/// Positions of accessor `index`: a VEC3 of float, or (KHR_mesh_quantization) of signed or unsigned
/// bytes or shorts, normalized or not; sparse substitutions applied. kInvalidInput, naming the
/// accessor, when it is missing, of another type, or reaches outside its buffer view or buffer.
BakeStatus readPositions(const tinygltf::Model& model, int index, std::vector<Vec3f>* out_positions);

/// Indices of accessor `index`: a SCALAR of unsigned byte, short or int, each < vertex_count (else
/// kInvalidInput), sparse substitutions applied.
BakeStatus readIndices(const tinygltf::Model& model, int index, std::size_t vertex_count,
                       std::vector<std::uint32_t>* out_indices);

} // namespace baker
} // namespace dng
