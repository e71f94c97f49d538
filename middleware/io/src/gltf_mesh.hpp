// Private to the glTF importer: morph-target names, meshes and materials.
#pragma once
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "gltf_skeleton.hpp"
#include "marionette/asset/asset.hpp"

namespace marionette::gltf_detail {

// ---- morph targets ---------------------------------------------------------------

// Names of mesh `m`'s targets: mesh.extras.targetNames (the common convention),
// else primitives[0].extras.targetNames (Blender's VRM exporter), else "<mesh>_<k>".
inline std::vector<std::string> morphTargetNames(const Context& ctx, std::size_t m, std::size_t count) {
  const Json* mesh = element(member(ctx.json, "meshes"), m);
  const Json* firstPrimitive = mesh ? element(member(*mesh, "primitives"), 0) : nullptr;
  const Json* candidates[] = {mesh ? member(*mesh, "extras") : nullptr,
                              firstPrimitive ? member(*firstPrimitive, "extras") : nullptr};
  for (const Json* extras : candidates) {
    const Json* names = extras ? member(*extras, "targetNames") : nullptr;
    if (!names || !names->is_array()) continue;
    if (names->size() != count ||
        !std::all_of(names->begin(), names->end(), [](const Json& n) { return n.is_string(); })) {
      ctx.warning("mesh '" + ctx.meshName(m) + "' has targetNames that do not match its " + std::to_string(count) +
                  " morph targets; using generated names");
      break;
    }
    std::vector<std::string> out;
    for (const Json& n : *names) out.push_back(n.get<std::string>());
    return out;
  }
  std::vector<std::string> out;
  for (std::size_t k = 0; k < count; ++k) out.push_back(ctx.meshName(m) + "_" + std::to_string(k));
  return out;
}

// The character-level morph-target list (unique names; meshes with a target of
// the same name share the entry, so one weight drives e.g. every part of a face)
// and, per mesh, the index of each of its targets in that list. Also computed
// when meshes are not loaded: weight tracks and VRM expressions refer to it.
inline std::vector<std::vector<int>> collectMorphTargets(const Context& ctx, std::vector<std::string>& list) {
  std::vector<std::vector<int>> perMesh(ctx.model.meshes.size());
  std::map<std::string, int> index;
  for (std::size_t m = 0; m < ctx.model.meshes.size(); ++m) {
    const auto& prims = ctx.model.meshes[m].primitives;
    const std::size_t count = prims.empty() ? 0 : prims[0].targets.size();
    std::vector<std::string> names = morphTargetNames(ctx, m, count);
    std::set<std::string> own;
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::string name = names[k];
      if (!own.insert(name).second) {  // two targets of one mesh must not share a weight
        name += "_" + std::to_string(k);
        ctx.warning("mesh '" + ctx.meshName(m) + "' has two morph targets named '" + names[k] + "'; target " +
                    std::to_string(k) + " is renamed '" + name + "'");
      }
      auto [it, added] = index.emplace(name, static_cast<int>(list.size()));
      if (added) list.push_back(name);
      perMesh[m].push_back(it->second);
    }
  }
  return perMesh;
}

// ---- meshes ------------------------------------------------------------------------

// How a mesh's vertices relate to the skeleton.
struct MeshBinding {
  int skin = -1;                 // the skin of the instancing node, or -1
  int rigidJoint = -1;           // skeleton joint a rigid mesh follows, or -1
  glm::mat4 bake{1.0f};          // applied to positions (file units) before extraScale
  std::vector<int> skinToJoint;  // skin joint index -> skeleton joint index
};

class MeshBuilder {
 public:
  MeshBuilder(const Context& ctx, const AccessorReader& reader, const NodeGraph& graph, const Skeleton& skeleton,
              const SkeletonMap& map, const std::vector<std::vector<int>>& morphs)
      : ctx_(ctx), reader_(reader), graph_(graph), skeleton_(skeleton), map_(map), morphs_(morphs) {}

  bool build(std::vector<Mesh>& meshes) {
    if (skeleton_.jointCount() > 65535) {
      ctx_.error("the skeleton has " + std::to_string(skeleton_.jointCount()) +
                 " joints; meshes can address at most 65535");
      return false;
    }
    bool ok = true;
    for (std::size_t m = 0; m < ctx_.model.meshes.size(); ++m) {
      Mesh mesh;
      if (buildMesh(m, mesh))
        meshes.push_back(std::move(mesh));
      else
        ok = false;
    }
    return ok;
  }

 private:
  const Context& ctx_;
  const AccessorReader& reader_;
  const NodeGraph& graph_;
  const Skeleton& skeleton_;
  const SkeletonMap& map_;
  const std::vector<std::vector<int>>& morphs_;

  struct Vertices {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
  };

  bool buildMesh(std::size_t m, Mesh& mesh) {
    mesh.name = ctx_.meshName(m);
    mesh.morphTargets = morphs_[m];
    MeshBinding binding;
    if (!bind(m, binding)) return false;
    mesh.skinned = binding.skin >= 0 || binding.rigidJoint >= 0;
    const auto& prims = ctx_.model.meshes[m].primitives;
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const std::string where = "mesh '" + mesh.name + "' primitive " + std::to_string(p);
      const tinygltf::Primitive& prim = prims[p];
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) {
        ctx_.warning(where + " has mode " + std::to_string(prim.mode) + " (only triangles are supported); skipped");
        continue;
      }
      if (prim.targets.size() != mesh.morphTargets.size()) {
        ctx_.error(where + " has " + std::to_string(prim.targets.size()) +
                   " morph targets but the mesh's first primitive has " + std::to_string(mesh.morphTargets.size()) +
                   "; all primitives must have the same number");
        return false;
      }
      if (!prim.attributes.count("POSITION")) {
        ctx_.warning(where + " has no POSITION attribute; skipped");
        continue;
      }
      MeshPrimitive out;
      if (!buildPrimitive(where, prim, binding, out)) return false;
      mesh.primitives.push_back(std::move(out));
    }
    return true;
  }

  // Skinned meshes (a node with `skin`) keep their bind-space vertices. Rigid
  // meshes under a joint (RobotExpressive is built that way) become skinned to
  // that joint with weight 1: their vertices are moved into the joint's bind
  // space, inverse(inverseBind) * (joint-to-node transform), so that
  // jointModel * inverseBind * vertex is where the node puts them.
  // Meshes under no joint get their node's scene transform baked in.
  bool bind(std::size_t m, MeshBinding& b) const {
    int node = -1;
    for (std::size_t n = 0; n < ctx_.model.nodes.size() && node < 0; ++n)
      if (ctx_.model.nodes[n].mesh == static_cast<int>(m)) node = static_cast<int>(n);
    if (node < 0) return true;  // not instanced: vertices as written
    const tinygltf::Node& n = ctx_.model.nodes[static_cast<std::size_t>(node)];
    if (n.skin >= 0) {
      b.skin = n.skin;
      for (int j : ctx_.model.skins[static_cast<std::size_t>(n.skin)].joints)
        b.skinToJoint.push_back(map_.nodeToJoint[static_cast<std::size_t>(j)]);
      return true;
    }
    int a = node;
    while (a >= 0 && map_.nodeToJoint[static_cast<std::size_t>(a)] < 0) a = graph_.parent[static_cast<std::size_t>(a)];
    if (a < 0) {
      b.bake = graph_.world[static_cast<std::size_t>(node)];
      return true;
    }
    b.rigidJoint = map_.nodeToJoint[static_cast<std::size_t>(a)];
    const glm::mat4 bindFromJoint = glm::inverse(map_.rawInverseBind[static_cast<std::size_t>(b.rigidJoint)]);
    b.bake = bindFromJoint * graph_.relative(a, node);
    if (!isFinite(b.bake)) {
      ctx_.error("mesh '" + ctx_.meshName(m) + "' follows joint '" +
                 skeleton_.names[static_cast<std::size_t>(b.rigidJoint)] +
                 "', whose inverse bind matrix cannot be inverted");
      return false;
    }
    return true;
  }

  // Attribute `name` of `attrs` as vec3s (empty when absent); `count` is the
  // required element count, SIZE_MAX for any.
  std::optional<std::vector<glm::vec3>> vec3s(const std::map<std::string, int>& attrs, const char* name,
                                              const std::string& where, std::size_t count) const {
    auto it = attrs.find(name);
    if (it == attrs.end()) return std::vector<glm::vec3>{};
    auto data = reader_.floats(it->second, where + " " + name, {TINYGLTF_TYPE_VEC3});
    if (!data) return std::nullopt;
    if (count != SIZE_MAX && data->count != count) {
      ctx_.error(where + " " + name + " has " + std::to_string(data->count) + " elements but POSITION has " +
                 std::to_string(count));
      return std::nullopt;
    }
    std::vector<glm::vec3> out(data->count);
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = glm::vec3(data->values[i * 3], data->values[i * 3 + 1], data->values[i * 3 + 2]);
    return out;
  }

  bool readVertices(const std::string& where, const tinygltf::Primitive& prim, Vertices& v) const {
    auto positions = vec3s(prim.attributes, "POSITION", where, SIZE_MAX);
    if (!positions) return false;
    v.positions = std::move(*positions);
    auto normals = vec3s(prim.attributes, "NORMAL", where, v.positions.size());
    if (!normals) return false;
    v.normals = std::move(*normals);
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      auto uv = reader_.floats(it->second, where + " TEXCOORD_0", {TINYGLTF_TYPE_VEC2});
      if (!uv) return false;
      if (uv->count != v.positions.size()) {
        ctx_.error(where + " TEXCOORD_0 has " + std::to_string(uv->count) + " elements but POSITION has " +
                   std::to_string(v.positions.size()));
        return false;
      }
      for (std::size_t i = 0; i < uv->count; ++i) v.uvs.emplace_back(uv->values[i * 2], uv->values[i * 2 + 1]);
    }
    return true;
  }

  bool readIndices(const std::string& where, const tinygltf::Primitive& prim, std::size_t vertexCount,
                   std::vector<std::uint32_t>& out) const {
    if (prim.indices < 0) {
      out.resize(vertexCount);
      std::iota(out.begin(), out.end(), 0u);
    } else {
      auto data = reader_.integers(prim.indices, where + " indices", {TINYGLTF_TYPE_SCALAR}, nullptr);
      if (!data) return false;
      out = std::move(*data);
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (out[i] >= vertexCount) {
        ctx_.error(where + ": vertex index " + std::to_string(out[i]) + " (at position " + std::to_string(i) +
                   " of the index list) is out of range; the primitive has " + std::to_string(vertexCount) +
                   " vertices");
        return false;
      }
    }
    if (out.size() % 3 != 0) {
      ctx_.error(where + " has " + std::to_string(out.size()) + " indices, which is not a whole number of triangles");
      return false;
    }
    return true;
  }

  bool readSkin(const std::string& where, const tinygltf::Primitive& prim, const MeshBinding& b, std::size_t count,
                MeshPrimitive& out) const {
    if (b.rigidJoint >= 0) {
      out.joints.assign(count, glm::u16vec4(static_cast<std::uint16_t>(b.rigidJoint), 0, 0, 0));
      out.weights.assign(count, glm::vec4(1, 0, 0, 0));
      return true;
    }
    if (b.skin < 0) return true;
    auto ji = prim.attributes.find("JOINTS_0");
    auto wi = prim.attributes.find("WEIGHTS_0");
    if (ji == prim.attributes.end() || wi == prim.attributes.end()) {
      ctx_.error(where + " belongs to a skinned mesh but lacks JOINTS_0 or WEIGHTS_0");
      return false;
    }
    if (prim.attributes.count("JOINTS_1"))
      ctx_.warning(where + " has more than 4 influences per vertex (JOINTS_1); only the first 4 are used");
    auto joints = reader_.integers(ji->second, where + " JOINTS_0", {TINYGLTF_TYPE_VEC4}, nullptr);
    if (!joints) return false;
    auto weights = reader_.floats(wi->second, where + " WEIGHTS_0", {TINYGLTF_TYPE_VEC4}, IntegerMode::Normalized);
    if (!weights) return false;
    if (joints->size() != count * 4 || weights->count != count) {
      ctx_.error(where + " JOINTS_0 / WEIGHTS_0 do not have one element per vertex (" + std::to_string(count) + ")");
      return false;
    }
    out.joints.resize(count);
    out.weights.resize(count);
    std::size_t fixed = 0;
    for (std::size_t v = 0; v < count; ++v) {
      glm::vec4 w(weights->values[v * 4], weights->values[v * 4 + 1], weights->values[v * 4 + 2],
                  weights->values[v * 4 + 3]);
      for (int c = 0; c < 4; ++c) {
        const std::uint32_t j = (*joints)[v * 4 + static_cast<std::size_t>(c)];
        if (w[c] < 0.0f) w[c] = 0.0f, ++fixed;
        if (j >= b.skinToJoint.size()) {
          // Exporters pad unused influences with arbitrary numbers; only a used one is an error.
          if (w[c] > 0.0f) {
            ctx_.error(where + " vertex " + std::to_string(v) + ": JOINTS_0 refers to skin joint " + std::to_string(j) +
                       " but skin " + std::to_string(b.skin) + " has " + std::to_string(b.skinToJoint.size()) +
                       " joints");
            return false;
          }
          out.joints[v][c] = 0;
        } else {
          out.joints[v][c] = static_cast<std::uint16_t>(b.skinToJoint[j]);
        }
      }
      const float sum = w.x + w.y + w.z + w.w;
      if (sum > 0.0f) {
        out.weights[v] = w / sum;  // quantized weights rarely sum to exactly 1
      } else {
        out.weights[v] = glm::vec4(1, 0, 0, 0);
        ++fixed;
      }
    }
    if (fixed > 0)
      ctx_.warning(where + ": " + std::to_string(fixed) + " negative or all-zero skin weights were repaired");
    return true;
  }

  bool readMorphTargets(const std::string& where, const tinygltf::Primitive& prim, std::size_t count,
                        MeshPrimitive& out) const {
    for (std::size_t k = 0; k < prim.targets.size(); ++k) {
      const std::string w = where + " morph target " + std::to_string(k);
      MorphTargetDelta d;
      auto positions = vec3s(prim.targets[k], "POSITION", w, count);
      auto normals = positions ? vec3s(prim.targets[k], "NORMAL", w, count) : std::nullopt;
      if (!normals) return false;
      d.positions = std::move(*positions);
      d.normals = std::move(*normals);
      out.morphTargets.push_back(std::move(d));
    }
    return true;
  }

  // Moves the vertices by the binding's bake matrix and applies extraScale.
  void transform(const MeshBinding& b, MeshPrimitive& out) const {
    const float s = ctx_.options.extraScale;
    const glm::mat3 linear(b.bake);
    const glm::mat3 normalMatrix = glm::inverseTranspose(linear);
    const bool normalsOk = isFinite(glm::mat4(normalMatrix));
    for (glm::vec3& p : out.positions) p = s * glm::vec3(b.bake * glm::vec4(p, 1.0f));
    for (glm::vec3& n : out.normals) {
      const glm::vec3 t = normalsOk ? normalMatrix * n : n;
      const float len = glm::length(t);
      n = len > 0.0f && std::isfinite(len) ? t / len : n;
    }
    for (MorphTargetDelta& d : out.morphTargets) {
      for (glm::vec3& p : d.positions) p = s * (linear * p);
      if (normalsOk)
        for (glm::vec3& n : d.normals) n = normalMatrix * n;
    }
  }

  bool buildPrimitive(const std::string& where, const tinygltf::Primitive& prim, const MeshBinding& b,
                      MeshPrimitive& out) const {
    Vertices v;
    if (!readVertices(where, prim, v)) return false;
    const std::size_t count = v.positions.size();
    out.positions = std::move(v.positions);
    out.normals = std::move(v.normals);
    out.uvs = std::move(v.uvs);
    out.material = prim.material;
    if (!readIndices(where, prim, count, out.indices) || !readSkin(where, prim, b, count, out) ||
        !readMorphTargets(where, prim, count, out))
      return false;
    transform(b, out);
    return true;
  }
};

// ---- materials -------------------------------------------------------------------

inline std::string percentDecoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// An image stored in the glTF file itself (a buffer view or a data URI), not a file of its own.
inline bool imageInsideFile(const tinygltf::Image& image) {
  return image.bufferView >= 0 || image.uri.empty() || image.uri.rfind("data:", 0) == 0;
}

// Texture reference of `textureIndex`: the image file resolved against the
// glTF file's folder, or "embedded:<image index>" for images inside the file.
inline std::string textureReference(const Context& ctx, int textureIndex) {
  if (!Context::inRange(textureIndex, ctx.model.textures)) return {};
  const int source = ctx.model.textures[static_cast<std::size_t>(textureIndex)].source;
  if (!Context::inRange(source, ctx.model.images)) return {};
  const tinygltf::Image& image = ctx.model.images[static_cast<std::size_t>(source)];
  if (imageInsideFile(image)) return "embedded:" + std::to_string(source);
  const std::filesystem::path dir = std::filesystem::path(ctx.file).parent_path();
  const std::filesystem::path file = (dir / percentDecoded(image.uri)).lexically_normal();
  if (!ctx.options.allowFilesOutsideModelFolder && !insideFolder(file, dir)) {
    ctx.warning("image " + std::to_string(source) + " '" + image.uri +
                "' is outside the model's folder: no texture (ImportOptions::allowFilesOutsideModelFolder allows it)");
    return {};
  }
  return file.string();
}

inline std::vector<Material> buildMaterials(const Context& ctx) {
  std::vector<Material> out;
  for (std::size_t i = 0; i < ctx.model.materials.size(); ++i) {
    const tinygltf::Material& m = ctx.model.materials[i];
    Material mat;
    mat.name = m.name.empty() ? "material_" + std::to_string(i) : m.name;
    const auto& f = m.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4 && allFinite(f))
      mat.baseColor = glm::vec4(static_cast<float>(f[0]), static_cast<float>(f[1]), static_cast<float>(f[2]),
                                static_cast<float>(f[3]));
    else
      ctx.warning("material '" + mat.name + "' baseColorFactor is not 4 finite numbers; white is used");
    mat.baseColorTexture = textureReference(ctx, m.pbrMetallicRoughness.baseColorTexture.index);
    out.push_back(std::move(mat));
  }
  return out;
}

}  // namespace marionette::gltf_detail
