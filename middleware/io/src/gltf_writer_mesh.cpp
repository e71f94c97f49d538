// glTF writer: meshes. One glTF mesh and node per Asset mesh, a primitive per
// primitive with whole triangles: positions, repaired normals, texture
// coordinates, skin joints and weights, and morph targets.
#include "marionette/core/finite.hpp"

#include <algorithm>
#include <cmath>

#include "gltf_writer_context.hpp"

namespace marionette::gltf_writer_detail {
namespace {

// Unit normals; zero or non-finite ones get the area-weighted normal of the
// triangles around the vertex (or +Y for an isolated vertex). Returns how many.
std::size_t repairNormals(const MeshPrimitive& p, std::vector<glm::vec3>& normals) {
  std::vector<std::size_t> broken;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const float len = glm::length(normals[v]);
    if (len > 1e-12f && std::isfinite(len))
      normals[v] /= len;
    else
      broken.push_back(v);
  }
  if (broken.empty()) return 0;
  std::vector<glm::vec3> face(normals.size(), glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
    const std::uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
    const glm::vec3 n = glm::cross(p.positions[b] - p.positions[a], p.positions[c] - p.positions[a]);
    face[a] += n, face[b] += n, face[c] += n;
  }
  for (std::size_t v : broken) {
    const float len = glm::length(face[v]);
    normals[v] = len > 1e-20f && std::isfinite(len) ? face[v] / len : glm::vec3(0, 1, 0);
  }
  return broken.size();
}

}  // namespace

// Skin attributes for a skinned primitive: joints as skin indices (skin joint
// k is skeleton joint k), weights renormalized to sum 1, a joint listed twice
// merged, unused slots joint 0 weight 0. Returns how many vertices were repaired.
std::size_t Writer::skinAttributes(const Mesh& mesh, const MeshPrimitive& p, std::vector<glm::u16vec4>& joints,
                                   std::vector<glm::vec4>& weights) const {
  const std::size_t count = p.positions.size();
  const bool have = p.joints.size() == count && p.weights.size() == count;
  const auto fallback = static_cast<std::uint16_t>(mesh.joint >= 0 ? mesh.joint : 0);
  joints.assign(count, glm::u16vec4(0));
  weights.assign(count, glm::vec4(0.0f));
  std::size_t repaired = 0;
  for (std::size_t v = 0; v < count; ++v) {
    glm::u16vec4 j(0);
    glm::vec4 w(0.0f);
    int used = 0;
    for (int c = 0; have && c < 4; ++c) {
      const float wc = p.weights[v][c];
      if (!(wc > 0.0f) || !std::isfinite(wc) || p.joints[v][c] >= skeleton_.jointCount()) continue;
      int slot = 0;
      while (slot < used && j[slot] != p.joints[v][c]) ++slot;
      if (slot == used) j[used++] = p.joints[v][c];
      w[slot] += wc;
    }
    const float sum = w.x + w.y + w.z + w.w;
    if (!(sum > 0.0f)) {
      j = glm::u16vec4(fallback, 0, 0, 0);
      w = glm::vec4(1, 0, 0, 0);
      ++repaired;
    } else {
      w /= sum;
    }
    joints[v] = j;
    weights[v] = w;
  }
  return repaired;
}

bool Writer::primitiveData(const std::string& where, const MeshPrimitive& p) {
  const std::size_t count = p.positions.size();
  if (!allFinite(p.positions) || !allFinite(p.uvs) || !allFinite(p.weights)) {
    error(where + " has non-finite vertex data (positions, texture coordinates or weights)");
    return false;
  }
  for (const MorphTargetDelta& d : p.morphTargets)
    if (!allFinite(d.positions) || !allFinite(d.normals)) {
      error(where + " has a morph target with non-finite deltas");
      return false;
    }
  for (std::size_t i = 0; i < p.indices.size(); ++i)
    if (p.indices[i] >= count) {
      error(where + ": index " + std::to_string(p.indices[i]) + " (at position " + std::to_string(i) +
            ") is out of range; the primitive has " + std::to_string(count) + " vertices");
      return false;
    }
  return true;
}

std::optional<Json> Writer::primitive(const Mesh& mesh, std::size_t pi, bool skinned) {
  const MeshPrimitive& p = mesh.primitives[pi];
  const std::string where = "mesh '" + mesh.name + "' primitive " + std::to_string(pi);
  const std::size_t count = p.positions.size();
  if (count == 0 || p.indices.empty() || p.indices.size() % 3 != 0) {
    warning(where + " has no vertices or no whole triangles (" + std::to_string(p.indices.size()) +
            " indices); skipped");
    return std::nullopt;
  }
  if (!primitiveData(where, p)) return std::nullopt;
  Json attributes = {{"POSITION", buffer_.vec3s(p.positions, kArrayBuffer, true)}};
  if (p.normals.size() == count) {
    std::vector<glm::vec3> normals = p.normals;
    if (const std::size_t fixed = repairNormals(p, normals); fixed > 0)
      warning(where + ": " + std::to_string(fixed) + " zero or non-finite normal(s) replaced by face normals");
    attributes["NORMAL"] = buffer_.vec3s(normals, kArrayBuffer, false);
  } else if (!p.normals.empty()) {
    warning(where + " has " + std::to_string(p.normals.size()) + " normals for " + std::to_string(count) +
            " vertices; normals dropped");
  }
  if (p.uvs.size() == count)
    attributes["TEXCOORD_0"] =
        buffer_.floats(reinterpret_cast<const float*>(p.uvs.data()), count, 2, "VEC2", kArrayBuffer, false);
  else if (!p.uvs.empty())
    warning(where + " has " + std::to_string(p.uvs.size()) + " texture coordinates for " + std::to_string(count) +
            " vertices; dropped");
  if (skinned) {
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> weights;
    if (const std::size_t repaired = skinAttributes(mesh, p, joints, weights); repaired > 0)
      warning(where + ": " + std::to_string(repaired) +
              " vertices without usable skin weights bound to one joint with weight 1");
    attributes["JOINTS_0"] = buffer_.joints(joints);
    attributes["WEIGHTS_0"] =
        buffer_.floats(reinterpret_cast<const float*>(weights.data()), count, 4, "VEC4", kArrayBuffer, false);
  }
  const std::uint32_t maxIndex = *std::max_element(p.indices.begin(), p.indices.end());
  Json out = {{"attributes", std::move(attributes)}, {"indices", buffer_.indices(p.indices, maxIndex)}, {"mode", 4}};
  if (p.material >= 0 && static_cast<std::size_t>(p.material) < asset_.materials.size())
    out["material"] = p.material;
  if (!mesh.morphTargets.empty()) out["targets"] = morphTargets(where, mesh, p);
  return out;
}

// One target per entry of Mesh::morphTargets, in that order, on every
// primitive (glTF requires the same count); a target without deltas in this
// primitive is written as zero offsets.
Json Writer::morphTargets(const std::string& where, const Mesh& mesh, const MeshPrimitive& p) {
  const std::size_t count = p.positions.size();
  Json targets = Json::array();
  std::size_t misfit = 0;
  for (std::size_t k = 0; k < mesh.morphTargets.size(); ++k) {
    const MorphTargetDelta* d = k < p.morphTargets.size() ? &p.morphTargets[k] : nullptr;
    Json t = Json::object();
    if (d && d->positions.size() == count) {
      t["POSITION"] = buffer_.vec3s(d->positions, kArrayBuffer, true);
    } else {
      misfit += d && !d->positions.empty() ? 1 : 0;
      t["POSITION"] = buffer_.vec3s(std::vector<glm::vec3>(count, glm::vec3(0.0f)), kArrayBuffer, true);
    }
    if (d && d->normals.size() == count) t["NORMAL"] = buffer_.vec3s(d->normals, kArrayBuffer, false);
    targets.push_back(std::move(t));
  }
  if (misfit > 0)
    warning(where + ": " + std::to_string(misfit) +
            " morph target(s) have a delta count other than the vertex count; written as zero offsets");
  return targets;
}

void Writer::writeMeshes() {
  Json meshes = Json::array();
  meshNode_.assign(asset_.meshes.size(), -1);
  for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
    const Mesh& mesh = asset_.meshes[m];
    const bool skinned = mesh.skinned && skin_ >= 0;
    if (mesh.skinned && !skinned)
      warning("mesh '" + mesh.name + "' is skinned but the skeleton has no joints; written unskinned");
    Json prims = Json::array();
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      if (auto prim = primitive(mesh, p, skinned)) prims.push_back(std::move(*prim));
    if (!ok_) return;
    if (prims.empty()) {
      warning("mesh '" + mesh.name + "' has no primitive with triangles; not written");
      continue;
    }
    Json out = {{"primitives", std::move(prims)}};
    if (!mesh.name.empty()) out["name"] = mesh.name;
    if (!mesh.morphTargets.empty()) out["extras"] = {{"targetNames", morphNames(mesh)}};
    meshes.push_back(std::move(out));
    Json node = {{"name", mesh.name}, {"mesh", meshes.size() - 1}};
    if (skinned) node["skin"] = skin_;
    nodes_.push_back(std::move(node));
    const int index = static_cast<int>(nodes_.size()) - 1;
    meshNode_[m] = index;
    attachMeshNode(mesh, skinned, index);
  }
  if (!meshes.empty()) doc_["meshes"] = std::move(meshes);
}

// Skinned meshes sit at the scene root: glTF ignores their node's transform and
// the validator warns about any parent. A rigid mesh follows its joint.
void Writer::attachMeshNode(const Mesh& mesh, bool skinned, int index) {
  if (!skinned && mesh.joint >= 0 && static_cast<std::size_t>(mesh.joint) < skeleton_.jointCount()) {
    Json& parent = nodes_[static_cast<std::size_t>(mesh.joint)];
    if (!parent.contains("children")) parent["children"] = Json::array();
    parent["children"].push_back(index);
  } else {
    sceneNodes_.push_back(index);
  }
}

std::vector<std::string> Writer::morphNames(const Mesh& mesh) const {
  std::vector<std::string> names;
  for (int t : mesh.morphTargets)
    names.push_back(t >= 0 && static_cast<std::size_t>(t) < asset_.morphTargets.size()
                        ? asset_.morphTargets[static_cast<std::size_t>(t)]
                        : "morph_" + std::to_string(t));
  return names;
}

}  // namespace marionette::gltf_writer_detail
