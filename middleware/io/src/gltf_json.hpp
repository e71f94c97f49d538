// Private to the glTF importer: safe look-ups in the raw JSON document and a
// type check of the glTF 2.0 core schema.
//
// Why a schema check of our own: tinygltf silently skips properties of the
// wrong type (a scene index given as a string, `primitives` given as an object,
// a name given as a number), which would make us import a different file from
// the one that was written. We want such files rejected with a message that
// names the property.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace marionette::gltf_detail {

using Json = nlohmann::json;

// Member `key` of `object`, or nullptr when absent or `object` is not an object.
inline const Json* member(const Json& object, std::string_view key) {
  if (!object.is_object()) return nullptr;
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

// Element `i` of `array`, or nullptr.
inline const Json* element(const Json* array, std::size_t i) {
  if (!array || !array->is_array() || i >= array->size()) return nullptr;
  return &(*array)[i];
}

// A non-negative integer (JSON integers, or floats with an integral value).
inline std::optional<long long> asIndex(const Json* v) {
  if (!v) return std::nullopt;
  if (v->is_number_unsigned()) {
    auto u = v->get<unsigned long long>();
    if (u > static_cast<unsigned long long>(INT32_MAX)) return std::nullopt;
    return static_cast<long long>(u);
  }
  if (v->is_number_integer()) {
    auto i = v->get<long long>();
    return i < 0 ? std::nullopt : std::optional<long long>(i);
  }
  if (v->is_number_float()) {
    double d = v->get<double>();
    if (std::isfinite(d) && d >= 0.0 && d <= INT32_MAX && std::floor(d) == d) return static_cast<long long>(d);
  }
  return std::nullopt;
}

inline std::optional<double> asNumber(const Json* v) {
  if (!v || !v->is_number()) return std::nullopt;
  return v->get<double>();
}

inline std::string asString(const Json* v, std::string fallback = {}) {
  return v && v->is_string() ? v->get<std::string>() : fallback;
}

// Nesting depth of a document, computed without recursion. tinygltf converts
// `extras` and `extensions` recursively, so an absurdly deep file would
// overflow its stack; we measure first.
inline std::size_t nestingDepth(const Json& doc) {
  std::size_t deepest = 0;
  std::vector<std::pair<const Json*, std::size_t>> stack{{&doc, 1}};
  while (!stack.empty()) {
    const auto [v, depth] = stack.back();
    stack.pop_back();
    deepest = std::max(deepest, depth);
    if (v->is_structured())
      for (const Json& child : *v) stack.emplace_back(&child, depth + 1);
  }
  return deepest;
}

// ---- schema ------------------------------------------------------------------

enum class Kind {
  Index,   // non-negative integer
  Number,  // finite number
  String,
  Bool,
  Object,       // object checked against `schema`
  ObjectArray,  // array of objects checked against `schema`
  IndexArray,
  NumberArray,
  StringArray,
  IndexMap,      // object whose values are indices (primitive attributes)
  IndexMapArray  // array of IndexMap (morph targets)
};

struct Schema;
struct Field {
  std::string_view name;
  Kind kind;
  const Schema* schema = nullptr;
  bool required = false;
};
struct Schema {
  std::span<const Field> fields;
};

// Every glTF object may also carry `name` (string), `extensions` (object of
// objects) and `extras` (anything); those are checked for all objects.
namespace schema {
inline constexpr Field kTextureInfo[] = {{"index", Kind::Index, nullptr, true},
                                         {"texCoord", Kind::Index},
                                         {"scale", Kind::Number},
                                         {"strength", Kind::Number}};
inline constexpr Schema kTextureInfoS{kTextureInfo};
inline constexpr Field kPbr[] = {{"baseColorFactor", Kind::NumberArray},
                                 {"baseColorTexture", Kind::Object, &kTextureInfoS},
                                 {"metallicFactor", Kind::Number},
                                 {"roughnessFactor", Kind::Number},
                                 {"metallicRoughnessTexture", Kind::Object, &kTextureInfoS}};
inline constexpr Schema kPbrS{kPbr};
inline constexpr Field kMaterial[] = {{"pbrMetallicRoughness", Kind::Object, &kPbrS},
                                      {"normalTexture", Kind::Object, &kTextureInfoS},
                                      {"occlusionTexture", Kind::Object, &kTextureInfoS},
                                      {"emissiveTexture", Kind::Object, &kTextureInfoS},
                                      {"emissiveFactor", Kind::NumberArray},
                                      {"alphaMode", Kind::String},
                                      {"alphaCutoff", Kind::Number},
                                      {"doubleSided", Kind::Bool}};
inline constexpr Field kAsset[] = {{"version", Kind::String, nullptr, true},
                                   {"generator", Kind::String},
                                   {"minVersion", Kind::String},
                                   {"copyright", Kind::String}};
inline constexpr Field kScene[] = {{"nodes", Kind::IndexArray}};
inline constexpr Field kNode[] = {{"camera", Kind::Index},       {"children", Kind::IndexArray},
                                  {"skin", Kind::Index},         {"matrix", Kind::NumberArray},
                                  {"mesh", Kind::Index},         {"rotation", Kind::NumberArray},
                                  {"scale", Kind::NumberArray},  {"translation", Kind::NumberArray},
                                  {"weights", Kind::NumberArray}};
inline constexpr Field kPrimitive[] = {{"attributes", Kind::IndexMap, nullptr, true},
                                       {"indices", Kind::Index},
                                       {"material", Kind::Index},
                                       {"mode", Kind::Index},
                                       {"targets", Kind::IndexMapArray}};
inline constexpr Schema kPrimitiveS{kPrimitive};
inline constexpr Field kMesh[] = {{"primitives", Kind::ObjectArray, &kPrimitiveS, true},
                                  {"weights", Kind::NumberArray}};
inline constexpr Field kSparseIndices[] = {{"bufferView", Kind::Index, nullptr, true},
                                           {"byteOffset", Kind::Index},
                                           {"componentType", Kind::Index, nullptr, true}};
inline constexpr Schema kSparseIndicesS{kSparseIndices};
inline constexpr Field kSparseValues[] = {{"bufferView", Kind::Index, nullptr, true}, {"byteOffset", Kind::Index}};
inline constexpr Schema kSparseValuesS{kSparseValues};
inline constexpr Field kSparse[] = {{"count", Kind::Index, nullptr, true},
                                    {"indices", Kind::Object, &kSparseIndicesS, true},
                                    {"values", Kind::Object, &kSparseValuesS, true}};
inline constexpr Schema kSparseS{kSparse};
inline constexpr Field kAccessor[] = {{"bufferView", Kind::Index},
                                      {"byteOffset", Kind::Index},
                                      {"componentType", Kind::Index, nullptr, true},
                                      {"normalized", Kind::Bool},
                                      {"count", Kind::Index, nullptr, true},
                                      {"type", Kind::String, nullptr, true},
                                      {"max", Kind::NumberArray},
                                      {"min", Kind::NumberArray},
                                      {"sparse", Kind::Object, &kSparseS}};
inline constexpr Field kBufferView[] = {{"buffer", Kind::Index, nullptr, true},
                                        {"byteOffset", Kind::Index},
                                        {"byteLength", Kind::Index, nullptr, true},
                                        {"byteStride", Kind::Index},
                                        {"target", Kind::Index}};
inline constexpr Field kBuffer[] = {{"uri", Kind::String}, {"byteLength", Kind::Index, nullptr, true}};
inline constexpr Field kTarget[] = {{"node", Kind::Index}, {"path", Kind::String, nullptr, true}};
inline constexpr Schema kTargetS{kTarget};
inline constexpr Field kChannel[] = {{"sampler", Kind::Index, nullptr, true},
                                     {"target", Kind::Object, &kTargetS, true}};
inline constexpr Schema kChannelS{kChannel};
inline constexpr Field kSampler[] = {
    {"input", Kind::Index, nullptr, true}, {"interpolation", Kind::String}, {"output", Kind::Index, nullptr, true}};
inline constexpr Schema kSamplerS{kSampler};
inline constexpr Field kAnimation[] = {{"channels", Kind::ObjectArray, &kChannelS, true},
                                       {"samplers", Kind::ObjectArray, &kSamplerS, true}};
inline constexpr Field kSkin[] = {
    {"inverseBindMatrices", Kind::Index}, {"skeleton", Kind::Index}, {"joints", Kind::IndexArray, nullptr, true}};
inline constexpr Field kTexture[] = {{"sampler", Kind::Index}, {"source", Kind::Index}};
inline constexpr Field kImage[] = {{"uri", Kind::String}, {"mimeType", Kind::String}, {"bufferView", Kind::Index}};
inline constexpr Field kTexSampler[] = {
    {"magFilter", Kind::Index}, {"minFilter", Kind::Index}, {"wrapS", Kind::Index}, {"wrapT", Kind::Index}};
inline constexpr Field kCamera[] = {{"type", Kind::String, nullptr, true}};

inline constexpr Schema kMaterialS{kMaterial}, kAssetS{kAsset}, kSceneS{kScene}, kNodeS{kNode}, kMeshS{kMesh},
    kAccessorS{kAccessor}, kBufferViewS{kBufferView}, kBufferS{kBuffer}, kAnimationS{kAnimation}, kSkinS{kSkin},
    kTextureS{kTexture}, kImageS{kImage}, kTexSamplerS{kTexSampler}, kCameraS{kCamera};

inline constexpr Field kRoot[] = {{"asset", Kind::Object, &kAssetS, true},
                                  {"scene", Kind::Index},
                                  {"scenes", Kind::ObjectArray, &kSceneS},
                                  {"nodes", Kind::ObjectArray, &kNodeS},
                                  {"meshes", Kind::ObjectArray, &kMeshS},
                                  {"accessors", Kind::ObjectArray, &kAccessorS},
                                  {"bufferViews", Kind::ObjectArray, &kBufferViewS},
                                  {"buffers", Kind::ObjectArray, &kBufferS},
                                  {"animations", Kind::ObjectArray, &kAnimationS},
                                  {"skins", Kind::ObjectArray, &kSkinS},
                                  {"materials", Kind::ObjectArray, &kMaterialS},
                                  {"textures", Kind::ObjectArray, &kTextureS},
                                  {"images", Kind::ObjectArray, &kImageS},
                                  {"samplers", Kind::ObjectArray, &kTexSamplerS},
                                  {"cameras", Kind::ObjectArray, &kCameraS},
                                  {"extensionsUsed", Kind::StringArray},
                                  {"extensionsRequired", Kind::StringArray}};
inline constexpr Schema kRootS{kRoot};
}  // namespace schema

class SchemaChecker {
 public:
  static constexpr std::size_t kMaxProblems = 20;

  std::vector<std::string> check(const Json& doc) {
    problems_.clear();
    if (!doc.is_object())
      problem("(document)", "the top level must be a JSON object, found " + typeName(doc));
    else
      object(doc, schema::kRootS, "");
    return problems_;
  }

 private:
  std::vector<std::string> problems_;

  static std::string typeName(const Json& v) {
    if (v.is_number()) return "number " + v.dump();
    if (v.is_string()) return "string " + v.dump();
    return std::string(v.type_name());
  }
  void problem(const std::string& where, const std::string& what) {
    if (problems_.size() < kMaxProblems) problems_.push_back(where + ": " + what);
  }
  static std::string join(const std::string& where, std::string_view key) {
    return where.empty() ? std::string(key) : where + "." + std::string(key);
  }
  static std::string at(const std::string& where, std::size_t i) { return where + "[" + std::to_string(i) + "]"; }

  void object(const Json& v, const Schema& s, const std::string& where) {
    if (!v.is_object()) return problem(where, "expected an object, found " + typeName(v));
    for (const Field& f : s.fields) {
      const Json* m = member(v, f.name);
      if (!m) {
        if (f.required) problem(where, "required property '" + std::string(f.name) + "' is missing");
        continue;
      }
      value(*m, f, join(where, f.name));
    }
    if (const Json* n = member(v, "name"); n && !n->is_string())
      problem(join(where, "name"), "expected a string, found " + typeName(*n));
    if (const Json* e = member(v, "extensions")) extensions(*e, join(where, "extensions"));
  }

  void extensions(const Json& e, const std::string& where) {
    if (!e.is_object()) return problem(where, "expected an object, found " + typeName(e));
    for (auto it = e.begin(); it != e.end(); ++it)
      if (!it->is_object()) problem(join(where, it.key()), "expected an object, found " + typeName(*it));
  }

  void scalar(const Json& v, Kind kind, const std::string& where) {
    switch (kind) {
      case Kind::Index:
        if (!asIndex(&v)) problem(where, "expected a non-negative integer, found " + typeName(v));
        break;
      case Kind::Number:
        if (!v.is_number() || !std::isfinite(v.get<double>()))
          problem(where, "expected a finite number, found " + typeName(v));
        break;
      case Kind::String:
        if (!v.is_string()) problem(where, "expected a string, found " + typeName(v));
        break;
      case Kind::Bool:
        if (!v.is_boolean()) problem(where, "expected true or false, found " + typeName(v));
        break;
      default:
        break;
    }
  }

  void array(const Json& v, Kind element, const Schema* s, const std::string& where) {
    if (!v.is_array()) return problem(where, "expected an array, found " + typeName(v));
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (s)
        object(v[i], *s, at(where, i));
      else if (element == Kind::IndexMap)
        indexMap(v[i], at(where, i));
      else
        scalar(v[i], element, at(where, i));
    }
  }

  void indexMap(const Json& v, const std::string& where) {
    if (!v.is_object()) return problem(where, "expected an object, found " + typeName(v));
    for (auto it = v.begin(); it != v.end(); ++it) scalar(*it, Kind::Index, join(where, it.key()));
  }

  void value(const Json& v, const Field& f, const std::string& where) {
    switch (f.kind) {
      case Kind::Object:
        return object(v, *f.schema, where);
      case Kind::ObjectArray:
        return array(v, Kind::Object, f.schema, where);
      case Kind::IndexArray:
        return array(v, Kind::Index, nullptr, where);
      case Kind::NumberArray:
        return array(v, Kind::Number, nullptr, where);
      case Kind::StringArray:
        return array(v, Kind::String, nullptr, where);
      case Kind::IndexMap:
        return indexMap(v, where);
      case Kind::IndexMapArray:
        return array(v, Kind::IndexMap, nullptr, where);
      default:
        return scalar(v, f.kind, where);
    }
  }
};

}  // namespace marionette::gltf_detail
