#include "marionette/skeleton/skeleton.hpp"

#include "marionette/core/finite.hpp"

#include <cmath>

namespace marionette {

int Skeleton::findJoint(std::string_view name) const noexcept {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}


std::string Skeleton::validate() const {
  const std::size_t n = parents.size();
  if (names.size() != n || restPose.size() != n || inverseBind.size() != n || skinned.size() != n)
    return "skeleton arrays differ in size (names, parents, rest pose, inverse bind, skinned)";
  for (std::size_t i = 0; i < n; ++i) {
    if (parents[i] < -1 || parents[i] >= static_cast<int>(i))
      return "joint '" + names[i] + "' (index " + std::to_string(i) + ") has parent " +
             std::to_string(parents[i]) + "; expected -1 or an index before its own";
    const Transform& t = restPose[i];
    if (!isFinite(t.translation) || !isFinite(t.scale) || !isFinite(t.rotation))
      return "joint '" + names[i] + "' has a non-finite rest pose";
    if (!isFinite(inverseBind[i])) return "joint '" + names[i] + "' has a non-finite inverse bind matrix";
  }
  return {};
}

int Skeleton::addJoint(std::string name, int parent, const Transform& rest, const glm::mat4& ibm,
                       bool isSkinned) {
  names.push_back(std::move(name));
  parents.push_back(parent);
  restPose.push_back(rest);
  inverseBind.push_back(ibm);
  skinned.push_back(isSkinned ? 1 : 0);
  return static_cast<int>(parents.size()) - 1;
}

std::vector<glm::mat4> Skeleton::restModelMatrices() const {
  std::vector<glm::mat4> model(jointCount());
  for (std::size_t i = 0; i < model.size(); ++i) {
    glm::mat4 local = restPose[i].matrix();
    model[i] = parents[i] < 0 ? rootTransform * local : model[parents[i]] * local;
  }
  return model;
}

}  // namespace marionette
