// Private to the glTF importer: the node hierarchy and the skeleton built from it.
#pragma once
#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_inverse.hpp>
#include <map>
#include <queue>
#include <set>
#include <tuple>
#include <vector>

#include "gltf_accessor.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::gltf_detail {

// ---- node hierarchy ------------------------------------------------------------

inline float maxDifference(const glm::mat4& a, const glm::mat4& b) {
  float d = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) d = std::max(d, std::fabs(a[c][r] - b[c][r]));
  return d;
}

// Reads a node's local transform; false (with an error) when malformed.
inline bool nodeTransform(const Context& ctx, std::size_t i, Transform& t, glm::mat4& m) {
  const tinygltf::Node& n = ctx.model.nodes[i];
  auto bad = [&](const char* what, std::size_t expected, const std::vector<double>& v) {
    if (v.empty()) return false;
    if (v.size() == expected && allFinite(v)) return false;
    ctx.error(ctx.nodeLabel(i) + " " + what + " must be " + std::to_string(expected) + " finite numbers");
    return true;
  };
  if (bad("translation", 3, n.translation) || bad("rotation", 4, n.rotation) || bad("scale", 3, n.scale) ||
      bad("matrix", 16, n.matrix))
    return false;
  if (!n.matrix.empty()) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(n.matrix[static_cast<std::size_t>(c * 4 + r)]);
    t = decompose(m);
    return true;
  }
  t = Transform{};
  if (!n.translation.empty())
    t.translation = glm::vec3(static_cast<float>(n.translation[0]), static_cast<float>(n.translation[1]),
                              static_cast<float>(n.translation[2]));
  if (!n.rotation.empty())  // glTF stores x, y, z, w; glm::quat takes w, x, y, z
    t.rotation = safeNormalize(glm::quat(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                                         static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2])));
  if (!n.scale.empty())
    t.scale = glm::vec3(static_cast<float>(n.scale[0]), static_cast<float>(n.scale[1]), static_cast<float>(n.scale[2]));
  m = t.matrix();
  return true;
}

// Parents from the children lists, rejecting out-of-range children, nodes with two
// parents and cycles (glTF requires the nodes to form disjoint strict trees).
inline bool findParents(const Context& ctx, std::vector<int>& parent) {
  const auto& nodes = ctx.model.nodes;
  parent.assign(nodes.size(), -1);
  bool ok = true;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (int c : nodes[i].children) {
      if (!Context::inRange(c, nodes)) {
        ctx.error(ctx.nodeLabel(i) + " has child " + std::to_string(c) + ", which does not exist (the file has " +
                  std::to_string(nodes.size()) + " nodes)");
        ok = false;
      } else if (parent[static_cast<std::size_t>(c)] != -1) {
        ctx.error(ctx.nodeLabel(static_cast<std::size_t>(c)) + " is a child of both node " +
                  std::to_string(parent[static_cast<std::size_t>(c)]) + " and node " + std::to_string(i) +
                  "; a node may have only one parent");
        ok = false;
      } else {
        parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
      }
    }
  }
  if (!ok) return false;
  // With one parent per node, a cycle shows as a walk upwards that never ends.
  std::vector<char> state(nodes.size(), 0);  // 0 unseen, 1 on the current walk, 2 known to reach a root
  for (std::size_t start = 0; start < nodes.size(); ++start) {
    std::vector<int> walk;
    int n = static_cast<int>(start);
    while (n >= 0 && state[static_cast<std::size_t>(n)] == 0) {
      state[static_cast<std::size_t>(n)] = 1;
      walk.push_back(n);
      n = parent[static_cast<std::size_t>(n)];
    }
    if (n >= 0 && state[static_cast<std::size_t>(n)] == 1) {
      // The cycle is the part of the walk from n on; list it child -> parent.
      std::string loop;
      for (auto it = std::find(walk.begin(), walk.end(), n); it != walk.end(); ++it)
        loop += ctx.nodeLabel(static_cast<std::size_t>(*it)) + " -> ";
      ctx.error("the node hierarchy has a cycle (child -> parent): " + loop +
                ctx.nodeLabel(static_cast<std::size_t>(n)));
      return false;
    }
    for (int w : walk) state[static_cast<std::size_t>(w)] = 2;
  }
  return true;
}

inline bool buildNodeGraph(const Context& ctx, NodeGraph& g) {
  const std::size_t count = ctx.model.nodes.size();
  if (count > limits::kMaxJoints) {  // every node may become a joint
    ctx.error("the file has " + std::to_string(count) + " nodes, more than the " + std::to_string(limits::kMaxJoints) +
              " a skeleton may have (limits::kMaxJoints)");
    return false;
  }
  if (!findParents(ctx, g.parent)) return false;
  g.local.assign(count, Transform{});
  g.localMatrix.assign(count, glm::mat4(1.0f));
  g.world.assign(count, glm::mat4(1.0f));
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) ok = nodeTransform(ctx, i, g.local[i], g.localMatrix[i]) && ok;
  if (!ok) return false;
  // World matrices, parents first: walk up to the nearest computed ancestor.
  std::vector<char> done(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<int> chain;
    for (int n = static_cast<int>(i); n >= 0 && !done[static_cast<std::size_t>(n)];
         n = g.parent[static_cast<std::size_t>(n)])
      chain.push_back(n);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const auto n = static_cast<std::size_t>(*it);
      const int p = g.parent[n];
      g.world[n] = p < 0 ? g.localMatrix[n] : g.world[static_cast<std::size_t>(p)] * g.localMatrix[n];
      done[n] = 1;
    }
  }
  return true;
}

// ---- skeleton --------------------------------------------------------------------

struct SkeletonMap {
  std::vector<int> nodeToJoint;  // -1 when the node is not a joint
  std::vector<int> jointToNode;
  std::vector<glm::mat4> rawInverseBind;  // per joint, file units (before extraScale)
};

class SkeletonBuilder {
 public:
  SkeletonBuilder(const Context& ctx, const AccessorReader& reader, const NodeGraph& graph)
      : ctx_(ctx), reader_(reader), graph_(graph) {}

  bool build(Skeleton& skeleton, SkeletonMap& map) {
    const std::size_t count = ctx_.model.nodes.size();
    rank_.assign(count, -1);
    tier_.assign(count, 1);
    inverseBind_.assign(count, glm::mat4(1.0f));
    skinJoint_.assign(count, 0);
    if (!collectSkinJoints()) return false;
    if (std::none_of(skinJoint_.begin(), skinJoint_.end(), [](char c) { return c != 0; }))
      collectSceneNodes();
    else
      addIntermediateNodes();
    emit(skeleton, map);
    return true;
  }

 private:
  const Context& ctx_;
  const AccessorReader& reader_;
  const NodeGraph& graph_;
  std::vector<int> rank_;  // preferred position; -1 when the node is not in the skeleton
  std::vector<int> tier_;  // tie-break: 0 for intermediate nodes, which must precede their joint
  std::vector<glm::mat4> inverseBind_;
  std::vector<char> skinJoint_;

  // Skin `s`'s inverse bind matrices, 16 floats per joint; empty when absent (identity).
  bool readInverseBinds(std::size_t s, std::vector<float>& matrices) const {
    const tinygltf::Skin& skin = ctx_.model.skins[s];
    if (skin.inverseBindMatrices < 0) return true;
    auto data = reader_.floats(skin.inverseBindMatrices, "skin " + std::to_string(s) + " inverse bind matrices",
                               {TINYGLTF_TYPE_MAT4});
    if (!data) return false;
    if (data->count < skin.joints.size()) {
      ctx_.error("skin " + std::to_string(s) + " has " + std::to_string(skin.joints.size()) + " joints but only " +
                 std::to_string(data->count) + " inverse bind matrices");
      return false;
    }
    matrices = std::move(data->values);
    return true;
  }

  // The union of all skins' joints, in the order they are first listed.
  bool collectSkinJoints() {
    int next = 0;
    for (std::size_t s = 0; s < ctx_.model.skins.size(); ++s) {
      const tinygltf::Skin& skin = ctx_.model.skins[s];
      std::vector<float> matrices;
      if (!readInverseBinds(s, matrices)) return false;
      bool differs = false;
      for (std::size_t k = 0; k < skin.joints.size(); ++k) {
        const int node = skin.joints[k];
        if (!Context::inRange(node, ctx_.model.nodes)) {
          ctx_.error("skin " + std::to_string(s) + " joint " + std::to_string(k) + " refers to node " +
                     std::to_string(node) + ", which does not exist");
          return false;
        }
        glm::mat4 m(1.0f);
        if (!matrices.empty())
          for (int e = 0; e < 16; ++e) m[e / 4][e % 4] = matrices[k * 16 + static_cast<std::size_t>(e)];
        const auto n = static_cast<std::size_t>(node);
        if (rank_[n] < 0) {
          rank_[n] = next++;
          inverseBind_[n] = m;
          skinJoint_[n] = 1;
        } else {
          differs = differs || maxDifference(inverseBind_[n], m) > 1e-3f;
        }
      }
      if (differs)
        ctx_.warning("skin " + std::to_string(s) +
                     " gives some joints other inverse bind matrices than an earlier skin; the first are used");
    }
    return true;
  }

  // A skin joint whose parent is not a joint but which has a joint further up
  // gets the nodes in between as (non-skinned) joints, so the chain stays connected.
  void addIntermediateNodes() {
    for (std::size_t j = 0; j < skinJoint_.size(); ++j) {
      if (!skinJoint_[j]) continue;
      std::vector<int> path;
      int p = graph_.parent[j];
      while (p >= 0 && !skinJoint_[static_cast<std::size_t>(p)]) {
        path.push_back(p);
        p = graph_.parent[static_cast<std::size_t>(p)];
      }
      if (p < 0) continue;  // j is a top joint; what lies above goes into rootTransform
      for (int n : path) {
        auto& r = rank_[static_cast<std::size_t>(n)];
        r = r < 0 ? rank_[j] : std::min(r, rank_[j]);
        tier_[static_cast<std::size_t>(n)] = 0;
      }
    }
  }

  // No skin: the whole node tree of the default scene (or of every root).
  void collectSceneNodes() {
    std::vector<int> roots;
    const auto& scenes = ctx_.model.scenes;
    if (Context::inRange(ctx_.model.defaultScene, scenes)) {
      roots = scenes[static_cast<std::size_t>(ctx_.model.defaultScene)].nodes;
    } else {
      for (std::size_t i = 0; i < graph_.parent.size(); ++i)
        if (graph_.parent[i] < 0) roots.push_back(static_cast<int>(i));
    }
    std::vector<int> stack;
    for (int r : roots)
      if (Context::inRange(r, ctx_.model.nodes)) stack.push_back(r);
    while (!stack.empty()) {
      const auto n = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      if (rank_[n] >= 0) continue;
      rank_[n] = static_cast<int>(n);
      for (int c : ctx_.model.nodes[n].children) stack.push_back(c);
    }
  }

  bool included(int node) const { return node >= 0 && rank_[static_cast<std::size_t>(node)] >= 0; }

  // Parent-before-child order that keeps the preferred (file) order where the
  // hierarchy allows: Kahn's algorithm always taking the lowest-ranked ready node.
  std::vector<int> order() const {
    using Key = std::tuple<int, int, int>;  // rank, tier, node
    std::priority_queue<Key, std::vector<Key>, std::greater<Key>> ready;
    auto push = [&](int n) {
      const auto u = static_cast<std::size_t>(n);
      ready.emplace(rank_[u], tier_[u], n);
    };
    for (std::size_t n = 0; n < rank_.size(); ++n)
      if (rank_[n] >= 0 && !included(graph_.parent[n])) push(static_cast<int>(n));
    std::vector<int> out;
    while (!ready.empty()) {
      const int n = std::get<2>(ready.top());
      ready.pop();
      out.push_back(n);
      for (int c : ctx_.model.nodes[static_cast<std::size_t>(n)].children)
        if (included(c)) push(c);
    }
    return out;
  }

  static glm::mat4 scaledTranslation(glm::mat4 m, float s) {
    m[3] = glm::vec4(glm::vec3(m[3]) * s, m[3].w);
    return m;
  }

  void emit(Skeleton& skeleton, SkeletonMap& map) {
    const float s = ctx_.options.extraScale;
    map.nodeToJoint.assign(rank_.size(), -1);
    skeleton = Skeleton{};
    bool haveRoot = false;
    glm::mat4 rootRaw(1.0f);
    for (int n : order()) {
      const auto u = static_cast<std::size_t>(n);
      const int p = graph_.parent[u];
      const int parentJoint = included(p) ? map.nodeToJoint[static_cast<std::size_t>(p)] : -1;
      Transform rest = graph_.local[u];
      if (parentJoint < 0) rest = rootRest(u, haveRoot, rootRaw);
      rest.translation *= s;
      map.nodeToJoint[u] = skeleton.addJoint(ctx_.nodeName(u), parentJoint, rest, scaledTranslation(inverseBind_[u], s),
                                             skinJoint_[u] != 0);
      map.jointToNode.push_back(n);
      map.rawInverseBind.push_back(inverseBind_[u]);
    }
    skeleton.rootTransform = scaledTranslation(rootRaw, s);
    makeNamesUnique(skeleton, map);
  }

  // Everything above the first root becomes rootTransform. A later root under a
  // different parent space gets the difference baked into its rest pose.
  Transform rootRest(std::size_t node, bool& haveRoot, glm::mat4& rootRaw) const {
    const int p = graph_.parent[node];
    const glm::mat4 parentWorld = p < 0 ? glm::mat4(1.0f) : graph_.world[static_cast<std::size_t>(p)];
    if (!haveRoot) {
      haveRoot = true;
      rootRaw = parentWorld;
      return graph_.local[node];
    }
    if (maxDifference(parentWorld, rootRaw) < 1e-6f) return graph_.local[node];
    const glm::mat4 inv = glm::inverse(rootRaw);
    const glm::mat4 baked = inv * parentWorld * graph_.localMatrix[node];
    if (!isFinite(baked)) {
      ctx_.warning(ctx_.nodeLabel(node) +
                   ": cannot express its parent space relative to the skeleton root; kept as is");
      return graph_.local[node];
    }
    return decompose(baked);
  }

  // Joint names must be unique for look-ups by name; a repeated name gets the
  // node index appended.
  void makeNamesUnique(Skeleton& skeleton, const SkeletonMap& map) const {
    std::set<std::string> seen(skeleton.names.begin(), skeleton.names.end());
    if (seen.size() == skeleton.names.size()) return;
    seen.clear();
    for (std::size_t j = 0; j < skeleton.names.size(); ++j) {
      std::string& name = skeleton.names[j];
      if (seen.insert(name).second) continue;
      const std::string renamed = name + "_node" + std::to_string(map.jointToNode[j]);
      ctx_.warning("joint name '" + name + "' is used more than once; " +
                   ctx_.nodeLabel(static_cast<std::size_t>(map.jointToNode[j])) + " is renamed '" + renamed + "'");
      name = renamed;
      seen.insert(name);
    }
  }
};

}  // namespace marionette::gltf_detail
