// Private to the glTF writer: the one binary buffer every accessor's data and
// every embedded image goes into, with its buffer views and accessors as JSON.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <vector>

namespace marionette::gltf_writer_detail {

using Json = nlohmann::json;

constexpr int kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::vec2) == 2 * sizeof(float) &&
              sizeof(glm::mat4) == 16 * sizeof(float) && sizeof(glm::u16vec4) == 4 * sizeof(std::uint16_t));

// One buffer holding every accessor's data and the embedded images; each view
// starts on a 4-byte boundary, which satisfies every component type's alignment.
class BinaryBuffer {
 public:
  std::vector<unsigned char> bytes;
  Json views = Json::array();
  Json accessors = Json::array();

  int view(const void* data, std::size_t size, int target) {
    bytes.resize((bytes.size() + 3) & ~std::size_t{3}, 0);
    Json v = {{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}};
    if (target != 0) v["target"] = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), p, p + size);
    views.push_back(std::move(v));
    return static_cast<int>(views.size()) - 1;
  }

  // Float accessor of `count` elements of `components` floats; min/max when asked
  // (required for POSITION and animation input; the validator checks them exactly).
  int floats(const float* data, std::size_t count, int components, const char* type, int target, bool bounds) {
    const int v = view(data, count * static_cast<std::size_t>(components) * sizeof(float), target);
    Json a = {{"bufferView", v}, {"componentType", kFloat}, {"count", count}, {"type", type}};
    if (bounds && count > 0) {
      Json lo = Json::array(), hi = Json::array();
      for (int c = 0; c < components; ++c) {
        float mn = data[c], mx = data[c];
        for (std::size_t i = 1; i < count; ++i) {
          mn = std::min(mn, data[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)]);
          mx = std::max(mx, data[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)]);
        }
        lo.push_back(mn);
        hi.push_back(mx);
      }
      a["min"] = std::move(lo);
      a["max"] = std::move(hi);
    }
    accessors.push_back(std::move(a));
    return static_cast<int>(accessors.size()) - 1;
  }

  int vec3s(const std::vector<glm::vec3>& v, int target, bool bounds) {
    return floats(reinterpret_cast<const float*>(v.data()), v.size(), 3, "VEC3", target, bounds);
  }
  int scalars(const std::vector<float>& v, bool bounds) { return floats(v.data(), v.size(), 1, "SCALAR", 0, bounds); }

  // Triangle indices in the smallest type that holds them. The largest value of
  // a type is the primitive-restart marker, which glTF forbids as an index.
  int indices(const std::vector<std::uint32_t>& idx, std::uint32_t maxIndex) {
    int v = 0, type = kUnsignedInt;
    if (maxIndex < 0xFFFFu) {
      std::vector<std::uint16_t> shorts(idx.begin(), idx.end());
      v = view(shorts.data(), shorts.size() * 2, kElementArrayBuffer);
      type = kUnsignedShort;
    } else {
      v = view(idx.data(), idx.size() * 4, kElementArrayBuffer);
    }
    accessors.push_back({{"bufferView", v}, {"componentType", type}, {"count", idx.size()}, {"type", "SCALAR"}});
    return static_cast<int>(accessors.size()) - 1;
  }

  int joints(const std::vector<glm::u16vec4>& j) {
    const int v = view(j.data(), j.size() * sizeof(glm::u16vec4), kArrayBuffer);
    accessors.push_back({{"bufferView", v}, {"componentType", kUnsignedShort}, {"count", j.size()}, {"type", "VEC4"}});
    return static_cast<int>(accessors.size()) - 1;
  }
};

}  // namespace marionette::gltf_writer_detail
