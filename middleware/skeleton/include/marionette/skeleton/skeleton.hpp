// A skeleton: joints in parent-before-child order (parent index < own index,
// -1 for roots), names, rest pose as local TRS and inverse bind matrices.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/transform.hpp"

namespace marionette {

struct Skeleton {
  std::vector<std::string> names;       // may be synthesized ("joint_7") when the file has none
  std::vector<int> parents;             // -1 for a root; parents[i] < i
  std::vector<Transform> restPose;      // local TRS of each joint at rest
  std::vector<glm::mat4> inverseBind;   // model-from-joint inverse at bind time; identity if not skinned
  std::vector<std::uint8_t> skinned;    // 1 when a mesh is bound to this joint (it has a real inverse bind)
  // Transform of the space the roots live in (nodes above the skeleton in the
  // file, e.g. a Z-up to Y-up rotation or a unit scale). Applied in local-to-model.
  glm::mat4 rootTransform{1.0f};

  [[nodiscard]] std::size_t jointCount() const noexcept { return parents.size(); }
  // Index of the joint with this exact name, or -1.
  [[nodiscard]] int findJoint(std::string_view name) const noexcept;
  // Empty string when valid, else what is wrong (sizes, order, NaN).
  [[nodiscard]] std::string validate() const;
  // Adds a joint at the end; returns its index. `parent` must be < the new index.
  int addJoint(std::string name, int parent, const Transform& rest,
               const glm::mat4& inverseBind = glm::mat4(1.0f), bool isSkinned = false);
  // Model-space rest matrices (rootTransform applied), one per joint.
  [[nodiscard]] std::vector<glm::mat4> restModelMatrices() const;
};

}  // namespace marionette
