#include "marionette/animation/animation_clip.hpp"

#include <algorithm>
#include <utility>

namespace marionette {

std::shared_ptr<const AnimationClip> makeAnimationClip(Clip clip, const Skeleton& skeleton, const AnimationClipOptions& options,
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

}  // namespace marionette
