#include "marionette/animation/clip.hpp"

#include <algorithm>
#include <cmath>

namespace marionette {

namespace {
template <class T>
std::string checkTrack(const Track<T>& t, const char* what, std::size_t joint, std::size_t width) {
  const std::size_t per = t.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::string where = std::string(what) + " track of joint " + std::to_string(joint);
  if (t.values.size() != t.times.size() * per * width)
    return where + ": " + std::to_string(t.values.size()) + " values for " +
           std::to_string(t.times.size()) + " keys";
  for (std::size_t k = 0; k < t.times.size(); ++k) {
    if (!std::isfinite(t.times[k])) return where + ": key " + std::to_string(k) + " time is not finite";
    if (k > 0 && !(t.times[k] > t.times[k - 1]))
      return where + ": key times not strictly increasing at key " + std::to_string(k);
  }
  return {};
}
}  // namespace

std::string Clip::validate(std::size_t jointCount) const {
  int last = -1;
  for (const JointTrack& jt : tracks) {
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= jointCount)
      return "clip '" + name + "': track for joint " + std::to_string(jt.joint) + " outside the skeleton (" +
             std::to_string(jointCount) + " joints)";
    if (jt.joint <= last) return "clip '" + name + "': tracks not sorted by joint or duplicated";
    last = jt.joint;
    std::string e;
    if (!(e = checkTrack(jt.translation, "translation", jt.joint, 1)).empty() ||
        !(e = checkTrack(jt.rotation, "rotation", jt.joint, 1)).empty() ||
        !(e = checkTrack(jt.scale, "scale", jt.joint, 1)).empty())
      return "clip '" + name + "': " + e;
  }
  for (const MorphTrack& m : morphTracks) {
    const std::size_t per = m.interpolation == Interpolation::CubicSpline ? 3 : 1;
    if (m.weights.size() != m.times.size() * per * m.targets.size())
      return "clip '" + name + "': morph track has " + std::to_string(m.weights.size()) + " weights for " +
             std::to_string(m.times.size()) + " keys of " + std::to_string(m.targets.size()) + " targets";
  }
  if (!std::isfinite(duration) || duration < 0.0f) return "clip '" + name + "': bad duration";
  for (std::size_t i = 0; i < events.size(); ++i) {
    const ClipEvent& e = events[i];
    if (e.name.empty()) return "clip '" + name + "': event " + std::to_string(i) + " has no name";
    if (!std::isfinite(e.time) || e.time < 0.0f || e.time > duration)
      return "clip '" + name + "': event " + std::to_string(i) + " ('" + e.name + "') is not within the clip's [0, " +
             std::to_string(duration) + "] s";
  }
  return {};
}

void Clip::updateDuration() noexcept {
  float d = 0.0f;
  auto last = [&](const std::vector<float>& times) {
    if (!times.empty()) d = std::max(d, times.back());
  };
  for (const JointTrack& jt : tracks) {
    last(jt.translation.times);
    last(jt.rotation.times);
    last(jt.scale.times);
  }
  for (const MorphTrack& m : morphTracks) last(m.times);
  duration = d;
}

}  // namespace marionette
