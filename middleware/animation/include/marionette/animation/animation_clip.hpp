// AnimationClip: a clip prepared to play on one skeleton: optimized, with its
// root motion extracted and the in-place copies of the tracks that travel.
// What a Rig holds per clip and what clip layers and behaviors play.
#pragma once
#include <memory>

#include "marionette/animation/clip.hpp"
#include "marionette/animation/clip_optimizer.hpp"
#include "marionette/animation/root_motion.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct AnimationClip {
  Clip clip;              // bound to the rig's skeleton; optimized unless the options say not
  ClipOptimizeStats optimization;  // what the load-time optimizer removed, and the error it allowed
  RootMotion rootMotion;  // empty when the clip has no root translation
  // What plays the clip in place, sampled over it: the root joint's track with
  // the root motion removed, and the tracks of the joints carried with the root
  // (RootMotion::carried, extractRootMotion's rule) with the same motion removed.
  Clip inPlaceRoot;
};

// How clips are prepared when they are loaded (a Rig's RigOptions).
struct AnimationClipOptions {
  bool optimizeClips = true;       // drop constant rest-pose tracks (see clip_optimizer.hpp)
  ClipOptimizeOptions tolerances;  // what "constant" means
};

// Optimizes the clip (unless told not to) and extracts its root motion
// (pickRootMotionJoint, or `rootJoint`) alongside it; the clip's own tracks
// are kept as authored (the in-place ones are AnimationClip::inPlaceRoot).
[[nodiscard]] std::shared_ptr<const AnimationClip> makeAnimationClip(Clip clip, const Skeleton& skeleton,
                                                                      const AnimationClipOptions& options = {},
                                                                      int rootJoint = -1);

}  // namespace marionette
