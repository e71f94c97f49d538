// Private to the glTF importer: what every stage of the import shares — the
// parsed model, the raw JSON (for extras and the VRM extensions tinygltf keeps
// only as generic values), the options and the diagnostics sink — plus the
// validated node hierarchy.
#pragma once
#include <tiny_gltf.h>

#include <filesystem>
#include <string>
#include <vector>

#include "gltf_json.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/io/import.hpp"
#include "model_folder.hpp"

namespace marionette::gltf_detail {

using io_detail::insideFolder;

struct Context {
  const tinygltf::Model& model;
  const Json& json;
  const std::string& file;
  const ImportOptions& options;
  Diagnostics& diagnostics;

  void error(std::string message) const { diagnostics.error(file, std::move(message)); }
  void warning(std::string message) const { diagnostics.warning(file, std::move(message)); }

  template <class T>
  static bool inRange(int index, const std::vector<T>& v) {
    return index >= 0 && static_cast<std::size_t>(index) < v.size();
  }

  [[nodiscard]] std::string animationName(std::size_t i) const {
    const std::string& n = model.animations[i].name;
    return n.empty() ? "animation_" + std::to_string(i) : n;
  }
  [[nodiscard]] std::string meshName(std::size_t i) const {
    const std::string& n = model.meshes[i].name;
    return n.empty() ? "mesh_" + std::to_string(i) : n;
  }
  [[nodiscard]] std::string nodeName(std::size_t i) const {
    const std::string& n = model.nodes[i].name;
    return n.empty() ? "node_" + std::to_string(i) : n;
  }
  // "node 5 'Hips'" — index and name, for messages.
  [[nodiscard]] std::string nodeLabel(std::size_t i) const {
    return "node " + std::to_string(i) + " '" + nodeName(i) + "'";
  }
};

// The node hierarchy after validation (a forest: one parent at most, no cycles).
// Transforms are in file units; ImportOptions::extraScale is applied later.
struct NodeGraph {
  std::vector<int> parent;             // -1 for a root
  std::vector<Transform> local;        // local TRS (a `matrix` decomposed)
  std::vector<glm::mat4> localMatrix;  // exact local matrix (as written when given as `matrix`)
  std::vector<glm::mat4> world;        // scene-space matrix

  // Product of the local matrices strictly below `ancestor` down to and
  // including `node`; identity when node == ancestor.
  [[nodiscard]] glm::mat4 relative(int ancestor, int node) const {
    glm::mat4 m(1.0f);
    for (int n = node; n != ancestor && n >= 0; n = parent[n]) m = localMatrix[n] * m;
    return m;
  }
};

}  // namespace marionette::gltf_detail
