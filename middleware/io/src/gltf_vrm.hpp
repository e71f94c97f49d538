// Private to the glTF importer: the VRM humanoid (VRM 0.0 `VRM`, VRM 1.0
// `VRMC_vrm`, VRM Animation `VRMC_vrm_animation`). Read from the raw JSON with
// every type checked: these extensions are outside the core schema check.
#pragma once
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "gltf_skeleton.hpp"
#include "marionette/asset/asset.hpp"

namespace marionette::gltf_detail {

class HumanoidReader {
 public:
  HumanoidReader(const Context& ctx, const Skeleton& skeleton, const SkeletonMap& map,
                 const std::vector<std::vector<int>>& morphs)
      : ctx_(ctx), skeleton_(skeleton), map_(map), morphs_(morphs) {}

  void read(Asset& asset) const {
    const Json* extensions = member(ctx_.json, "extensions");
    if (!extensions) return;
    if (const Json* vrm0 = member(*extensions, "VRM")) {
      asset.hasHumanoid = true;
      readVrm0Bones(*vrm0, asset.humanoid);
      readVrm0Expressions(*vrm0, asset.humanoid);
    }
    if (const Json* vrm1 = member(*extensions, "VRMC_vrm")) {
      asset.hasHumanoid = true;
      readBoneObject(member(*vrm1, "humanoid"), "VRMC_vrm", asset.humanoid);
      readVrm1Expressions(*vrm1, asset.humanoid);
    }
    // A VRM Animation's expression proxies (e.g. node `happy`) and `lookAt` are
    // plain nodes whose tracks stay on them; only the bone map is read here.
    if (const Json* vrma = member(*extensions, "VRMC_vrm_animation")) {
      asset.hasHumanoid = true;
      readBoneObject(member(*vrma, "humanoid"), "VRMC_vrm_animation", asset.humanoid);
    }
  }

 private:
  const Context& ctx_;
  const Skeleton& skeleton_;
  const SkeletonMap& map_;
  const std::vector<std::vector<int>>& morphs_;

  void addBone(const std::string& bone, const Json* node, const char* ext, Humanoid& h) const {
    const auto n = asIndex(node);
    if (bone.empty() || !n || !Context::inRange(static_cast<int>(*n), ctx_.model.nodes)) {
      ctx_.warning(std::string(ext) + " humanoid bone '" + bone + "' has no valid node; ignored");
      return;
    }
    const int joint = map_.nodeToJoint[static_cast<std::size_t>(*n)];
    if (joint < 0) {
      ctx_.warning(std::string(ext) + " humanoid bone '" + bone + "' is " +
                   ctx_.nodeLabel(static_cast<std::size_t>(*n)) + ", which is not a skeleton joint; ignored");
      return;
    }
    h.bones[bone] = skeleton_.names[static_cast<std::size_t>(joint)];
  }

  // VRM 0.0: humanoid.humanBones is an array of {bone, node}.
  void readVrm0Bones(const Json& vrm, Humanoid& h) const {
    const Json* humanoid = member(vrm, "humanoid");
    const Json* bones = humanoid ? member(*humanoid, "humanBones") : nullptr;
    if (!bones || !bones->is_array()) return;
    for (const Json& b : *bones) addBone(asString(member(b, "bone")), member(b, "node"), "VRM", h);
  }

  // VRM 1.0 and VRMA: humanoid.humanBones is an object {boneName: {node}}.
  void readBoneObject(const Json* humanoid, const char* ext, Humanoid& h) const {
    const Json* bones = humanoid ? member(*humanoid, "humanBones") : nullptr;
    if (!bones || !bones->is_object()) return;
    for (auto it = bones->begin(); it != bones->end(); ++it) addBone(it.key(), member(*it, "node"), ext, h);
  }

  // Index into Asset::morphTargets of target `index` of mesh `mesh`, or -1.
  int morphIndex(long long mesh, long long index) const {
    if (mesh < 0 || static_cast<std::size_t>(mesh) >= morphs_.size()) return -1;
    const auto& targets = morphs_[static_cast<std::size_t>(mesh)];
    return index >= 0 && static_cast<std::size_t>(index) < targets.size() ? targets[static_cast<std::size_t>(index)]
                                                                          : -1;
  }

  // Visemes get a format-independent upper-case alias: VRM 0.0 writes the
  // presets "a".."o", VRM 1.0 "aa", "ih", "ou", "ee", "oh"; both become "A".."O".
  static std::string visemeAlias(const std::string& preset) {
    static const std::pair<const char*, const char*> kAliases[] = {{"a", "A"},  {"i", "I"},  {"u", "U"},  {"e", "E"},
                                                                   {"o", "O"},  {"aa", "A"}, {"ih", "I"}, {"ou", "U"},
                                                                   {"ee", "E"}, {"oh", "O"}};
    for (const auto& [from, to] : kAliases)
      if (preset == from) return to;
    return {};
  }

  static void store(Humanoid& h, const std::string& key, const std::vector<std::pair<int, float>>& binds) {
    h.expressions[key] = binds;
    const std::string alias = visemeAlias(key);
    if (!alias.empty() && alias != key) h.expressions[alias] = binds;
  }

  // VRM 0.0: blendShapeMaster.blendShapeGroups [{name, presetName, binds:[{mesh, index, weight 0..100}]}].
  void readVrm0Expressions(const Json& vrm, Humanoid& h) const {
    const Json* master = member(vrm, "blendShapeMaster");
    const Json* groups = master ? member(*master, "blendShapeGroups") : nullptr;
    if (!groups || !groups->is_array()) return;
    for (const Json& g : *groups) {
      std::string key = asString(member(g, "presetName"));
      if (key.empty() || key == "unknown") key = asString(member(g, "name"));
      if (key.empty()) continue;
      std::vector<std::pair<int, float>> binds;
      const Json* list = member(g, "binds");
      for (std::size_t i = 0; list && list->is_array() && i < list->size(); ++i) {
        const Json& b = (*list)[i];
        const int target =
            morphIndex(asIndex(member(b, "mesh")).value_or(-1), asIndex(member(b, "index")).value_or(-1));
        const double weight = asNumber(member(b, "weight")).value_or(100.0);
        if (target < 0 || !std::isfinite(weight)) {
          ctx_.warning("VRM blend shape group '" + key + "' bind " + std::to_string(i) +
                       " refers to no morph target; ignored");
          continue;
        }
        binds.emplace_back(target, static_cast<float>(std::clamp(weight / 100.0, 0.0, 1.0)));
      }
      store(h, key, binds);
    }
  }

  // VRM 1.0: expressions.{preset,custom}.<name>.morphTargetBinds [{node, index, weight 0..1}].
  void readVrm1Expressions(const Json& vrm, Humanoid& h) const {
    const Json* expressions = member(vrm, "expressions");
    if (!expressions) return;
    for (const char* group : {"preset", "custom"}) {
      const Json* entries = member(*expressions, group);
      if (!entries || !entries->is_object()) continue;
      for (auto it = entries->begin(); it != entries->end(); ++it) {
        std::vector<std::pair<int, float>> binds;
        const Json* list = member(*it, "morphTargetBinds");
        for (std::size_t i = 0; list && list->is_array() && i < list->size(); ++i) {
          const Json& b = (*list)[i];
          const auto node = asIndex(member(b, "node"));
          const int mesh = node && Context::inRange(static_cast<int>(*node), ctx_.model.nodes)
                               ? ctx_.model.nodes[static_cast<std::size_t>(*node)].mesh
                               : -1;
          const int target = morphIndex(mesh, asIndex(member(b, "index")).value_or(-1));
          const double weight = asNumber(member(b, "weight")).value_or(1.0);
          if (target < 0 || !std::isfinite(weight)) {
            ctx_.warning("VRMC_vrm expression '" + it.key() + "' bind " + std::to_string(i) +
                         " refers to no morph target; ignored");
            continue;
          }
          binds.emplace_back(target, static_cast<float>(std::clamp(weight, 0.0, 1.0)));
        }
        store(h, it.key(), binds);
      }
    }
  }
};

}  // namespace marionette::gltf_detail
