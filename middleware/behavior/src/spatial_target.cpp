#include "marionette/behavior/spatial_target.hpp"

#include <cstdio>

#include "marionette/core/finite.hpp"

namespace marionette {

std::string describeTarget(const BehaviorTarget& target) {
  if (target.point) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g %g %g", static_cast<double>(target.point->x),
                  static_cast<double>(target.point->y), static_cast<double>(target.point->z));
    return buf;
  }
  return target.joint.empty() ? target.character : target.character + ":" + target.joint;
}

std::string resolveSpatialTarget(const BehaviorTarget& target, std::string_view what, const TargetJointFinder& findJoint,
                                 SpatialTarget& out) {
  const std::string w(what);
  if (target.empty()) return "a " + w + " needs a target: a world point, a character, or a character's joint";
  const std::string quoted = w + " target '" + describeTarget(target).substr(0, 80) + "'";
  if (target.point) {
    if (!isFinite(*target.point)) return quoted + " is not finite (NaN or infinite); the " + w + " was not started";
    out.point = *target.point;
    return {};
  }
  out.character = target.character;
  out.joint = target.joint;
  const int index = findJoint(out.character, out.joint);
  if (index == -2) return quoted + ": the scene has no character or object '" + out.character + "'";
  if (index == -3) return quoted + ": '" + out.character + "' is an object (a place), which has no joint '" + out.joint + "'";
  if (index < 0 && !out.joint.empty())
    return quoted + ": character '" + out.character + "' has no joint '" + out.joint + "'";
  out.jointIndex = index;
  return {};
}

}  // namespace marionette
