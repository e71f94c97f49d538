#include "marionette/behavior/spatial_target.hpp"

#include <cmath>

#include "marionette/core/number_list.hpp"

namespace marionette {

std::string parseSpatialTarget(std::string_view text, std::string_view what, const TargetJointFinder& findJoint,
                               SpatialTarget& target) {
  const std::string w(what);
  if (text.empty()) return "a " + w + " needs a target: \"x y z\" in metres, a character, or character:joint";
  const std::string quoted = w + " target '" + std::string(text.substr(0, 80)) + "'";
  if (const auto v = parseNumberList(text); v && v->size() == 3) {
    const glm::vec3 p((*v)[0], (*v)[1], (*v)[2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return quoted + " is not finite (NaN or infinite); the " + w + " was not started";
    target.point = p;
    return {};
  }
  const std::size_t colon = text.find(':');
  target.character = std::string(text.substr(0, colon));
  target.joint = colon == std::string_view::npos ? std::string() : std::string(text.substr(colon + 1));
  const int index = findJoint(target.character, target.joint);
  if (index == -2) return quoted + ": the scene has no character '" + target.character + "'";
  if (index < 0 && !target.joint.empty())
    return quoted + ": character '" + target.character + "' has no joint '" + target.joint + "'";
  target.jointIndex = index;
  return {};
}

}  // namespace marionette
