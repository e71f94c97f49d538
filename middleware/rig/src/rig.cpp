#include "marionette/rig/rig.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "marionette/animation/clip_binding.hpp"
#include "marionette/speech/lipsync.hpp"

namespace marionette {

namespace {

// RigJoints::eyeHeight from the rest pose (model frame); 1.6 m when the skeleton says nothing.
float restEyeHeight(const std::vector<glm::mat4>& rest, const RigJoints& j) {
  const auto heightOf = [&](int joint) {
    return joint >= 0 && static_cast<std::size_t>(joint) < rest.size() ? rest[static_cast<std::size_t>(joint)][3].y : NAN;
  };
  float h = NAN;
  if (j.leftEye >= 0 && j.rightEye >= 0) h = 0.5f * (heightOf(j.leftEye) + heightOf(j.rightEye));
  if (!std::isfinite(h)) h = heightOf(j.head);
  if (!std::isfinite(h) && !rest.empty()) {
    float top = rest.front()[3].y;
    for (const glm::mat4& m : rest) top = std::max(top, m[3].y);
    h = 0.94f * top;
  }
  return std::isfinite(h) && h > 0.0f ? h : 1.6f;
}

}  // namespace

Rig::Rig(const Asset& asset, const RigSettings& settings)
    : sourcePath_(asset.sourcePath),
      skeleton_(asset.skeleton),
      morphTargets_(asset.morphTargets),
      settings_(settings),
      paletteBasis_(PaletteBasis::of(skeleton_.inverseBind)) {
  clips_.reserve(asset.clips.size());
  for (const Clip& c : asset.clips) clips_.push_back(makeAnimationClip(c, skeleton_, settings_));
  setProfile(guessCharacterProfile(asset));
}

void Rig::setProfile(CharacterProfile profile) {
  profile_ = std::move(profile);
  const Skeleton& s = skeleton_;
  auto joint = [&](const std::string& name) { return name.empty() ? -1 : s.findJoint(name); };
  joints_ = RigJoints{};
  joints_.hips = joint(profile_.hips);
  joints_.neck = joint(profile_.neck);
  joints_.head = joint(profile_.head);
  joints_.leftEye = joint(profile_.leftEye);
  joints_.rightEye = joint(profile_.rightEye);
  joints_.jaw = joint(profile_.jaw);
  for (const std::string& name : profile_.spine)
    if (int j = joint(name); j >= 0) joints_.spine.push_back(j);
  auto limb = [&](const Limb& l) { return RigJoints::LimbJoints{joint(l.upper), joint(l.lower), joint(l.end)}; };
  joints_.leftLeg = limb(profile_.leftLeg);
  joints_.rightLeg = limb(profile_.rightLeg);
  joints_.leftArm = limb(profile_.leftArm);
  joints_.rightArm = limb(profile_.rightArm);
  joints_.leftToe = joint(profile_.leftToe);
  joints_.rightToe = joint(profile_.rightToe);
  const auto& morphs = morphTargets_;
  // Morph names to (index, amount); names the asset lacks are left out.
  auto resolveMorphs = [&](const std::vector<FaceMorph>& list) {
    std::vector<std::pair<int, float>> resolved;
    for (const FaceMorph& m : list) {
      auto it = std::find(morphs.begin(), morphs.end(), m.morph);
      if (it != morphs.end()) resolved.emplace_back(static_cast<int>(it - morphs.begin()), std::clamp(m.amount, 0.0f, 1.0f));
    }
    return resolved;
  };
  for (const auto& [expression, list] : profile_.face)
    if (auto resolved = resolveMorphs(list); !resolved.empty()) joints_.face.emplace(expression, std::move(resolved));
  for (const auto& [key, mapping] : profile_.facs) {
    RigJoints::FacsUnit unit{resolveMorphs(mapping.morphs), {}, mapping.source};
    for (const FacsJointMove& move : mapping.joints)
      if (const int j = joint(move.joint); j >= 0) unit.joints.push_back({j, move.rule});
    if (!unit.morphs.empty() || !unit.joints.empty()) joints_.facs.emplace(key, std::move(unit));
  }
  for (const auto& [channelName, list] : profile_.visemes) {
    const std::optional<int> channel = speech::lipChannelFromName(channelName);
    for (const auto& [morph, amount] : resolveMorphs(list))
      if (channel) joints_.visemes.push_back({*channel, morph, amount});
  }
  joints_.jawOpenByMorph = std::any_of(joints_.visemes.begin(), joints_.visemes.end(), [](const RigJoints::LipMorph& m) {
    return m.channel == speech::kJawOpenChannel;
  });
  // Left minus right at rest, from whichever pair the profile has, made level.
  const std::vector<glm::mat4> rest = s.restModelMatrices();
  const std::pair<int, int> pairs[] = {{joints_.leftArm.upper, joints_.rightArm.upper},
                                       {joints_.leftLeg.upper, joints_.rightLeg.upper},
                                       {joints_.leftEye, joints_.rightEye}};
  joints_.eyeHeight = restEyeHeight(rest, joints_);
  for (const auto& [left, right] : pairs) {
    if (left < 0 || right < 0 || static_cast<std::size_t>(std::max(left, right)) >= rest.size()) continue;
    glm::vec3 axis = glm::vec3(rest[static_cast<std::size_t>(left)][3]) - glm::vec3(rest[static_cast<std::size_t>(right)][3]);
    axis.y = 0.0f;
    if (glm::length(axis) > 1e-6f && std::isfinite(glm::length(axis))) {
      joints_.leftAxis = glm::normalize(axis);
      break;
    }
  }
  {  // the feet or the profile's events may have changed: found again when next asked for
    std::lock_guard lock(events_.mutex);
    events_.clips.resize(clips_.size());
    for (ClipEvents& e : events_.clips) e.current = false;
  }
  makeProfileBlendSpaces();
}

std::shared_ptr<const AnimationClip> Rig::findClip(std::string_view name) const noexcept {
  for (const auto& c : clips_)
    if (c->clip.name == name) return c;
  return nullptr;
}

int Rig::addClip(const Clip& clip, const Skeleton& clipSkeleton, std::string name) {
  int unmatched = 0;
  Clip bound = bindClipByName(clip, clipSkeleton, skeleton_, &unmatched);
  if (!name.empty()) bound.name = std::move(name);
  clips_.push_back(makeAnimationClip(std::move(bound), skeleton_, settings_));
  std::lock_guard lock(events_.mutex);
  events_.clips.resize(clips_.size());  // the new clip's events: when first asked for
  return unmatched;
}

}  // namespace marionette
