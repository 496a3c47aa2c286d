// glTF accessors into plain arrays. Every byte range is checked against its buffer view and buffer
// before it is read: a file may claim any offset, stride or count (docs/BAKING.md, exit code 3).
#include "gltf_accessor.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace dng {
namespace baker {

namespace {

BakeStatus invalid(int accessor, const std::string& what) {
  return BakeStatus::failure(BakeError::kInvalidInput, "accessor " + std::to_string(accessor) + " " + what);
}

// An accessor without a buffer view is all zeros (before sparse substitution) and may claim any count:
// without this cap a few bytes of JSON could ask for terabytes.
constexpr std::size_t kMaxViewlessCount = std::size_t(1) << 26;

// Where the accessor's elements are: a pointer to element 0 and the distance between elements, after
// checking that every element lies inside the buffer view, and the view inside its buffer.
struct ElementRange {
  const unsigned char* first = nullptr; // null for an accessor without a buffer view (all zeros)
  std::size_t stride = 0;
};

BakeStatus locateView(const tinygltf::Model& model, int accessor, int view_index, std::size_t byte_offset,
                      std::size_t count, std::size_t element_bytes, std::size_t view_stride_override,
                      ElementRange* out) {
  if (view_index < 0 || std::size_t(view_index) >= model.bufferViews.size())
    return invalid(accessor, "refers to buffer view " + std::to_string(view_index) + ", which does not exist");
  const tinygltf::BufferView& view = model.bufferViews[std::size_t(view_index)];
  if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size())
    return invalid(accessor, "uses buffer view " + std::to_string(view_index) + " of a buffer that does not exist");
  const std::vector<unsigned char>& data = model.buffers[std::size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    return invalid(accessor, "uses buffer view " + std::to_string(view_index) + ", which reaches outside its buffer");
  const std::size_t stride = view_stride_override != 0 ? view_stride_override
                             : view.byteStride != 0    ? view.byteStride
                                                       : element_bytes;
  if (stride < element_bytes) return invalid(accessor, "has a byte stride smaller than its element");
  // Last byte needed: offset + (count - 1) * stride + element_bytes, computed without overflow.
  if (count > 0) {
    const std::size_t available = view.byteLength;
    if (byte_offset > available || element_bytes > available - byte_offset ||
        (count - 1) > (available - byte_offset - element_bytes) / stride)
      return invalid(accessor, "reaches outside its buffer view (" + std::to_string(count) + " elements of " +
                                   std::to_string(element_bytes) + " bytes from byte " + std::to_string(byte_offset) +
                                   ")");
  }
  out->first = data.data() + view.byteOffset + byte_offset;
  out->stride = stride;
  return BakeStatus::success();
}

std::size_t componentBytes(int component_type) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_BYTE:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
  case TINYGLTF_COMPONENT_TYPE_SHORT:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
  case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
  default: return 0;
  }
}

// One component as a float; normalized integers map to [0, 1] or [-1, 1] as the glTF spec says.
float readComponent(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_FLOAT: {
    float f;
    std::memcpy(&f, p, 4);
    return f;
  }
  case TINYGLTF_COMPONENT_TYPE_BYTE: {
    const float v = float(std::int8_t(p[0]));
    return normalized ? std::max(v / 127.0f, -1.0f) : v;
  }
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? float(p[0]) / 255.0f : float(p[0]);
  case TINYGLTF_COMPONENT_TYPE_SHORT: {
    std::int16_t s;
    std::memcpy(&s, p, 2);
    return normalized ? std::max(float(s) / 32767.0f, -1.0f) : float(s);
  }
  default: { // unsigned short: the only other type positions may have
    std::uint16_t u;
    std::memcpy(&u, p, 2);
    return normalized ? float(u) / 65535.0f : float(u);
  }
  }
}

std::uint32_t readIndex(const unsigned char* p, int component_type) {
  if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[0];
  if (component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    std::uint16_t u;
    std::memcpy(&u, p, 2);
    return u;
  }
  std::uint32_t u;
  std::memcpy(&u, p, 4);
  return u;
}

bool isIndexType(int t) {
  return t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

// Applies a sparse accessor's substitutions: values[k] replaces element indices[k]. `write(element,
// bytes)` stores one element from the values view.
template <typename Write>
BakeStatus applySparse(const tinygltf::Model& model, int index, const tinygltf::Accessor& a, std::size_t element_bytes,
                       Write write) {
  if (!a.sparse.isSparse) return BakeStatus::success();
  if (a.sparse.count < 0) return invalid(index, "has a negative sparse count");
  const std::size_t count = std::size_t(a.sparse.count);
  const int index_type = a.sparse.indices.componentType;
  if (!isIndexType(index_type)) return invalid(index, "has sparse indices of a type glTF does not allow");
  if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
    return invalid(index, "has a negative sparse byte offset");
  ElementRange indices, values;
  BakeStatus status = locateView(model, index, a.sparse.indices.bufferView, std::size_t(a.sparse.indices.byteOffset),
                                 count, componentBytes(index_type), componentBytes(index_type), &indices);
  if (!status.ok()) return status;
  status = locateView(model, index, a.sparse.values.bufferView, std::size_t(a.sparse.values.byteOffset), count,
                      element_bytes, element_bytes, &values);
  if (!status.ok()) return status;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t target = readIndex(indices.first + k * indices.stride, index_type);
    if (target >= a.count) return invalid(index, "has a sparse index past its count");
    write(target, values.first + k * values.stride);
  }
  return BakeStatus::success();
}

} // namespace

BakeStatus readPositions(const tinygltf::Model& model, int index, std::vector<Vec3f>* out) {
  out->clear();
  if (index < 0 || std::size_t(index) >= model.accessors.size()) return invalid(index, "(positions) does not exist");
  const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
  const std::size_t component = componentBytes(a.componentType);
  if (a.type != TINYGLTF_TYPE_VEC3 || component == 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return invalid(index, "(positions) is not a VEC3 of float, byte or short components");
  const std::size_t element = 3 * component;
  ElementRange range;
  if (a.bufferView < 0 && a.count > kMaxViewlessCount) return invalid(index, "claims too many elements");
  if (a.bufferView >= 0) {
    const BakeStatus status = locateView(model, index, a.bufferView, a.byteOffset, a.count, element, 0, &range);
    if (!status.ok()) return status;
  }
  out->resize(a.count); // zeros when there is no buffer view (a sparse-only accessor)
  auto read = [&](std::size_t i, const unsigned char* p) {
    (*out)[i] = {readComponent(p, a.componentType, a.normalized),
                 readComponent(p + component, a.componentType, a.normalized),
                 readComponent(p + 2 * component, a.componentType, a.normalized)};
  };
  if (range.first != nullptr) {
    for (std::size_t i = 0; i < a.count; ++i)
      read(i, range.first + i * range.stride);
  }
  return applySparse(model, index, a, element, read);
}

BakeStatus readIndices(const tinygltf::Model& model, int index, std::size_t vertex_count,
                       std::vector<std::uint32_t>* out) {
  out->clear();
  if (index < 0 || std::size_t(index) >= model.accessors.size()) return invalid(index, "(indices) does not exist");
  const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
  if (a.type != TINYGLTF_TYPE_SCALAR || !isIndexType(a.componentType))
    return invalid(index, "(indices) is not a SCALAR of unsigned byte, short or int");
  const std::size_t element = componentBytes(a.componentType);
  ElementRange range;
  if (a.bufferView < 0 && a.count > kMaxViewlessCount) return invalid(index, "claims too many elements");
  if (a.bufferView >= 0) {
    const BakeStatus status = locateView(model, index, a.bufferView, a.byteOffset, a.count, element, 0, &range);
    if (!status.ok()) return status;
  }
  out->assign(a.count, 0u);
  auto read = [&](std::size_t i, const unsigned char* p) { (*out)[i] = readIndex(p, a.componentType); };
  if (range.first != nullptr) {
    for (std::size_t i = 0; i < a.count; ++i)
      read(i, range.first + i * range.stride);
  }
  const BakeStatus status = applySparse(model, index, a, element, read);
  if (!status.ok()) return status;
  for (const std::uint32_t v : *out) {
    if (v >= vertex_count)
      return invalid(index, "(indices) refers to vertex " + std::to_string(v) + " of " + std::to_string(vertex_count));
  }
  return BakeStatus::success();
}

} // namespace baker
} // namespace dng
