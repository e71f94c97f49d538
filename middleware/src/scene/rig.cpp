#include "marionette/scene/rig.hpp"

#include <algorithm>

#include "marionette/io/import.hpp"
#include "marionette/speech/lipsync.hpp"

namespace marionette {

std::shared_ptr<const AnimationClip> makeAnimationClip(Clip clip, const Skeleton& skeleton, const RigOptions& options,
                                                       int rootJoint) {
  auto out = std::make_shared<AnimationClip>();
  if (options.optimizeClips) out->optimization = optimizeClip(clip, skeleton, options.tolerances);
  Clip work = clip;
  out->rootMotion = extractRootMotion(work, skeleton, rootJoint);
  if (!out->rootMotion.empty()) {
    // The root's track and those of the joints the clip moves with the root (IK
    // feet and poles beside it): they lose the same travel and turn, or the feet
    // would stay where the clip put them while the legs go with the body.
    const RootMotion& rm = out->rootMotion;
    out->inPlaceRoot.name = clip.name;
    out->inPlaceRoot.duration = clip.duration;
    for (const JointTrack& t : work.tracks)  // in joint order, as a clip's tracks are
      if (t.joint == rm.joint || std::find(rm.carried.begin(), rm.carried.end(), t.joint) != rm.carried.end())
        out->inPlaceRoot.tracks.push_back(t);
  }
  out->clip = std::move(clip);
  return out;
}

Rig::Rig(std::shared_ptr<const Asset> asset, const RigOptions& options) : asset_(std::move(asset)), options_(options) {
  clips_.reserve(asset_->clips.size());
  for (const Clip& c : asset_->clips) clips_.push_back(makeAnimationClip(c, asset_->skeleton, options_));
  setProfile(guessCharacterProfile(*asset_));
}

void Rig::setProfile(CharacterProfile profile) {
  profile_ = std::move(profile);
  const Skeleton& s = asset_->skeleton;
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
  const auto& morphs = asset_->morphTargets;
  for (const auto& [expression, list] : profile_.face) {
    std::vector<std::pair<int, float>> resolved;
    for (const FaceMorph& m : list) {
      auto it = std::find(morphs.begin(), morphs.end(), m.morph);
      if (it != morphs.end()) resolved.emplace_back(static_cast<int>(it - morphs.begin()), std::clamp(m.amount, 0.0f, 1.0f));
    }
    if (!resolved.empty()) joints_.face.emplace(expression, std::move(resolved));
  }
  for (const auto& [channelName, list] : profile_.visemes) {
    int channel = -1;
    for (int c = 0; c < speech::kLipChannelCount && channel < 0; ++c)
      if (speech::lipChannelName(c) == channelName) channel = c;
    for (const FaceMorph& m : list) {
      auto it = std::find(morphs.begin(), morphs.end(), m.morph);
      if (channel >= 0 && it != morphs.end())
        joints_.visemes.push_back({channel, static_cast<int>(it - morphs.begin()), std::clamp(m.amount, 0.0f, 1.0f)});
    }
  }
}

std::shared_ptr<const AnimationClip> Rig::findClip(std::string_view name) const noexcept {
  for (const auto& c : clips_)
    if (c->clip.name == name) return c;
  return nullptr;
}

int Rig::addClip(const Clip& clip, const Skeleton& clipSkeleton, std::string name) {
  int unmatched = 0;
  Clip bound = bindClipByName(clip, clipSkeleton, asset_->skeleton, &unmatched);
  if (!name.empty()) bound.name = std::move(name);
  clips_.push_back(makeAnimationClip(std::move(bound), asset_->skeleton, options_));
  return unmatched;
}

}  // namespace marionette
