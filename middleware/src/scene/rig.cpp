#include "marionette/scene/rig.hpp"

#include <algorithm>

#include "marionette/io/import.hpp"

namespace marionette {

std::shared_ptr<const AnimationClip> makeAnimationClip(Clip clip, const Skeleton& skeleton, const RigOptions& options,
                                                       int rootJoint) {
  auto out = std::make_shared<AnimationClip>();
  if (options.optimizeClips) out->optimization = optimizeClip(clip, skeleton, options.tolerances);
  Clip work = clip;
  out->rootMotion = extractRootMotion(work, skeleton, rootJoint);
  if (!out->rootMotion.empty()) {
    auto it = std::find_if(work.tracks.begin(), work.tracks.end(),
                           [&](const JointTrack& t) { return t.joint == out->rootMotion.joint; });
    out->inPlaceRoot.name = clip.name;
    out->inPlaceRoot.duration = clip.duration;
    out->inPlaceRoot.tracks.push_back(*it);
  }
  out->clip = std::move(clip);
  return out;
}

Rig::Rig(std::shared_ptr<const Asset> asset, const RigOptions& options) : asset_(std::move(asset)), options_(options) {
  clips_.reserve(asset_->clips.size());
  for (const Clip& c : asset_->clips) clips_.push_back(makeAnimationClip(c, asset_->skeleton, options_));
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
