// Private to the glTF importer: reading accessors with every bound checked.
//
// tinygltf checks that buffers have their declared size, but not that an
// accessor stays inside its buffer view, that the view stays inside its buffer,
// or that sparse indices are in range. Each read here checks all of that before
// touching a byte, and names the accessor and its use in every message, e.g.
// "accessor 3 (animation 'Walk' channel 2 output) reads past the end of buffer view 5".
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "gltf_context.hpp"
#include "marionette/core/limits.hpp"

namespace marionette::gltf_detail {

struct AccessorData {
  std::vector<float> values;  // count * components, element after element
  std::size_t count = 0;
  int components = 0;
};

// How integer components become floats.
enum class IntegerMode {
  AsDeclared,  // normalized when the accessor says `normalized`, else the plain integer value
  Normalized   // always normalized (rotations and weights are only meaningful that way)
};

class AccessorReader {
 public:
  explicit AccessorReader(const Context& ctx) : ctx_(ctx) {}

  // Reads accessor `index` as floats. `what` names the use for messages.
  std::optional<AccessorData> floats(int index, const std::string& what, std::initializer_list<int> types,
                                     IntegerMode mode = IntegerMode::AsDeclared) const {
    Raw raw;
    if (!decode(index, what, types, raw)) return std::nullopt;
    AccessorData out;
    out.count = raw.count;
    out.components = raw.components;
    out.values.resize(raw.values.size());
    const bool integer = raw.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool normalize = integer && (mode == IntegerMode::Normalized || raw.normalized);
    for (std::size_t i = 0; i < raw.values.size(); ++i) {
      const double v = normalize ? normalized(raw.values[i], raw.componentType) : raw.values[i];
      if (!std::isfinite(v)) {
        ctx_.error(label(index, what) + " element " + std::to_string(i / raw.components) + " component " +
                   std::to_string(i % raw.components) + " is not finite (" + std::to_string(v) + ")");
        return std::nullopt;
      }
      out.values[i] = static_cast<float>(v);
    }
    return out;
  }

  // Reads an accessor of integer components (indices, joint numbers).
  std::optional<std::vector<std::uint32_t>> integers(int index, const std::string& what,
                                                     std::initializer_list<int> types, int* components) const {
    Raw raw;
    if (!decode(index, what, types, raw)) return std::nullopt;
    if (raw.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
      ctx_.error(label(index, what) + " has float components, expected integers");
      return std::nullopt;
    }
    std::vector<std::uint32_t> out(raw.values.size());
    for (std::size_t i = 0; i < raw.values.size(); ++i) {
      if (raw.values[i] < 0.0) {
        ctx_.error(label(index, what) + " element " + std::to_string(i / raw.components) + " is negative");
        return std::nullopt;
      }
      out[i] = static_cast<std::uint32_t>(raw.values[i]);
    }
    if (components) *components = raw.components;
    return out;
  }

  static std::string label(int index, const std::string& what) {
    return "accessor " + std::to_string(index) + " (" + what + ")";
  }

 private:
  static constexpr std::size_t kMaxElements = limits::kMaxArrayElements;
  // An accessor without a buffer view is zeros we must allocate; cap it lower.
  static constexpr std::size_t kMaxZeroComponents = std::size_t{1} << 24;

  struct Raw {
    std::vector<double> values;
    std::size_t count = 0;
    int components = 0;
    int componentType = 0;
    bool normalized = false;
  };

  const Context& ctx_;

  static int componentSize(int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
      default:
        return 0;  // INT and DOUBLE are not glTF 2.0 component types
    }
  }
  static int componentCount(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR:
        return 1;
      case TINYGLTF_TYPE_VEC2:
        return 2;
      case TINYGLTF_TYPE_VEC3:
        return 3;
      case TINYGLTF_TYPE_VEC4:
        return 4;
      case TINYGLTF_TYPE_MAT2:
        return 4;
      case TINYGLTF_TYPE_MAT3:
        return 9;
      case TINYGLTF_TYPE_MAT4:
        return 16;
      default:
        return 0;
    }
  }
  static std::string typeName(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR:
        return "SCALAR";
      case TINYGLTF_TYPE_VEC2:
        return "VEC2";
      case TINYGLTF_TYPE_VEC3:
        return "VEC3";
      case TINYGLTF_TYPE_VEC4:
        return "VEC4";
      case TINYGLTF_TYPE_MAT2:
        return "MAT2";
      case TINYGLTF_TYPE_MAT3:
        return "MAT3";
      case TINYGLTF_TYPE_MAT4:
        return "MAT4";
      default:
        return "unknown (" + std::to_string(type) + ")";
    }
  }
  static double normalized(double v, int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return std::max(v / 127.0, -1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return v / 255.0;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return std::max(v / 32767.0, -1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return v / 65535.0;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return v / 4294967295.0;
      default:
        return v;
    }
  }
  static double component(const unsigned char* p, int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        std::int8_t v;
        std::memcpy(&v, p, 1);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return *p;
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      default: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }

  bool decode(int index, const std::string& what, std::initializer_list<int> types, Raw& out) const {
    const std::string where = label(index, what);
    if (!Context::inRange(index, ctx_.model.accessors)) {
      ctx_.error(where + " does not exist; the file has " + std::to_string(ctx_.model.accessors.size()) + " accessors");
      return false;
    }
    const tinygltf::Accessor& a = ctx_.model.accessors[static_cast<std::size_t>(index)];
    if (!checkShape(a, where, types)) return false;
    out.components = componentCount(a.type);
    out.componentType = a.componentType;
    out.normalized = a.normalized;
    out.count = a.count;
    // Locate (and so bound-check) before allocating: memory follows the file's real size.
    std::optional<Located> data;
    if (a.bufferView >= 0) {
      data = locate(where, a.bufferView, a.byteOffset, a.count, out.components, a.componentType, true);
      if (!data) return false;
    } else if (a.count * static_cast<std::size_t>(out.components) > kMaxZeroComponents) {
      ctx_.error(where + " has no buffer view and an implausible count of " + std::to_string(a.count));
      return false;
    }
    // Without a buffer view the accessor is all zeros (then usually sparse).
    out.values.assign(a.count * static_cast<std::size_t>(out.components), 0.0);
    if (data) copy(*data, a.count, out.components, a.componentType, out.values.data());
    return !a.sparse.isSparse || applySparse(a, where, out);
  }

  bool checkShape(const tinygltf::Accessor& a, const std::string& where, std::initializer_list<int> types) const {
    bool allowed = false;
    std::string expected;
    for (int t : types) {
      allowed = allowed || t == a.type;
      expected += (expected.empty() ? "" : " or ") + typeName(t);
    }
    if (!allowed) {
      ctx_.error(where + " has type " + typeName(a.type) + ", expected " + expected);
      return false;
    }
    const int size = componentSize(a.componentType);
    if (size == 0) {
      ctx_.error(where + " has unsupported component type " + std::to_string(a.componentType));
      return false;
    }
    // Matrices of 1- and 2-byte components have padded columns; glTF never uses them for what we read.
    if (componentCount(a.type) > 4 && size < 4) {
      ctx_.error(where + " is a matrix of " + std::to_string(size) + "-byte components, which is not supported");
      return false;
    }
    if (a.count > kMaxElements) {
      ctx_.error(where + " has " + std::to_string(a.count) + " elements, more than the " +
                 std::to_string(kMaxElements) + " one array may have (limits::kMaxArrayElements)");
      return false;
    }
    return true;
  }

  struct Located {
    const unsigned char* base;
    std::size_t stride;
  };

  // Checks that `count` elements of `components` components starting at
  // `byteOffset` lie inside the buffer view and the view inside its buffer.
  std::optional<Located> locate(const std::string& where, int viewIndex, std::size_t byteOffset, std::size_t count,
                                int components, int componentType, bool useViewStride) const {
    const auto& views = ctx_.model.bufferViews;
    if (!Context::inRange(viewIndex, views)) {
      ctx_.error(where + " refers to buffer view " + std::to_string(viewIndex) + ", which does not exist");
      return std::nullopt;
    }
    const tinygltf::BufferView& view = views[static_cast<std::size_t>(viewIndex)];
    if (!Context::inRange(view.buffer, ctx_.model.buffers)) {
      ctx_.error(where + ": buffer view " + std::to_string(viewIndex) + " refers to buffer " +
                 std::to_string(view.buffer) + ", which does not exist");
      return std::nullopt;
    }
    const std::vector<unsigned char>& data = ctx_.model.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
      ctx_.error(where + ": buffer view " + std::to_string(viewIndex) + " (bytes " + std::to_string(view.byteOffset) +
                 " to " + std::to_string(view.byteOffset + view.byteLength) + ") extends past the end of buffer " +
                 std::to_string(view.buffer) + " (" + std::to_string(data.size()) + " bytes)");
      return std::nullopt;
    }
    const std::size_t element =
        static_cast<std::size_t>(componentSize(componentType)) * static_cast<std::size_t>(components);
    const std::size_t stride = useViewStride && view.byteStride != 0 ? view.byteStride : element;
    if (stride < element || stride > 4096) {
      ctx_.error(where + " has " + std::to_string(element) + "-byte elements but buffer view " +
                 std::to_string(viewIndex) + " has a stride of " + std::to_string(stride) + " bytes");
      return std::nullopt;
    }
    // count <= kMaxElements and stride <= 4096, so this cannot overflow.
    const std::size_t span = count == 0 ? 0 : (count - 1) * stride + element;
    if (byteOffset > view.byteLength || span > view.byteLength - byteOffset) {
      ctx_.error(where + " reads past the end of buffer view " + std::to_string(viewIndex) + " (needs " +
                 std::to_string(span) + " bytes from offset " + std::to_string(byteOffset) + ", the view has " +
                 std::to_string(view.byteLength) + ")");
      return std::nullopt;
    }
    return Located{data.data() + view.byteOffset + byteOffset, stride};
  }

  static void copy(const Located& at, std::size_t count, int components, int componentType, double* dst) {
    const auto size = static_cast<std::size_t>(componentSize(componentType));
    const auto n = static_cast<std::size_t>(components);
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t c = 0; c < n; ++c) dst[i * n + c] = component(at.base + i * at.stride + c * size, componentType);
  }

  bool applySparse(const tinygltf::Accessor& a, const std::string& where, Raw& out) const {
    const auto& s = a.sparse;
    if (s.count < 0 || static_cast<std::size_t>(s.count) > a.count || s.indices.byteOffset < 0 ||
        s.values.byteOffset < 0) {
      ctx_.error(where + " has a sparse part with count " + std::to_string(s.count) + " for " +
                 std::to_string(a.count) + " elements");
      return false;
    }
    const int indexType = s.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
      ctx_.error(where + " has sparse indices of component type " + std::to_string(indexType) +
                 ", expected an unsigned integer type");
      return false;
    }
    const auto n = static_cast<std::size_t>(s.count);
    // Sparse views are tightly packed (no byteStride).
    const auto indexData = locate(where + " sparse indices", s.indices.bufferView,
                                  static_cast<std::size_t>(s.indices.byteOffset), n, 1, indexType, false);
    if (!indexData) return false;
    const auto valueData =
        locate(where + " sparse values", s.values.bufferView, static_cast<std::size_t>(s.values.byteOffset), n,
               out.components, a.componentType, false);
    if (!valueData) return false;
    std::vector<double> indices(n), values(n * static_cast<std::size_t>(out.components));
    copy(*indexData, n, 1, indexType, indices.data());
    copy(*valueData, n, out.components, a.componentType, values.data());
    for (std::size_t k = 0; k < n; ++k) {
      if (indices[k] >= static_cast<double>(a.count) || (k > 0 && indices[k] <= indices[k - 1])) {
        ctx_.error(where + " sparse index " + std::to_string(k) + " (" + std::to_string(indices[k]) +
                   ") is out of range or not increasing");
        return false;
      }
      const auto e = static_cast<std::size_t>(indices[k]);
      for (int c = 0; c < out.components; ++c)
        out.values[e * static_cast<std::size_t>(out.components) + static_cast<std::size_t>(c)] =
            values[k * static_cast<std::size_t>(out.components) + static_cast<std::size_t>(c)];
    }
    return true;
  }
};

}  // namespace marionette::gltf_detail
