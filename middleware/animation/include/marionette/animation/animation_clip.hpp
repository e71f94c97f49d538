// AnimationClip: a clip prepared to play on one skeleton: optimized, with its
// root motion extracted and the in-place copies of the tracks that travel.
// What a Rig holds per clip and what clip layers and behaviors play.
#pragma once
#include <memory>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/animation/clip_optimizer.hpp"
#include "marionette/animation/compact_clip.hpp"
#include "marionette/animation/sampling.hpp"
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
  // What the runtime samples when they are not empty: the keys of `clip` and of
  // `inPlaceRoot` quantized within the error budget (compact_clip.hpp). The float
  // tracks stay for load-time analysis (gait, contacts, retargeting) and as the reference.
  CompactClip compact, compactInPlaceRoot;
  CompactClipStats compaction, compactionInPlaceRoot;
  // The rest pose of the skeleton the clip was made for, with the constant tracks of
  // `compact` applied: what sampling without a rest pose starts from, so that those
  // tracks are written once at load instead of every frame (half of Pab's walk and jog
  // tracks are constant). Derived at load, like a Rig's PaletteBasis: not clip data.
  std::vector<Transform> pose;
};

// How clips are prepared when they are loaded (a Rig's RigSettings).
struct AnimationClipOptions {
  bool optimizeClips = true;       // drop constant rest-pose tracks (see clip_optimizer.hpp)
  ClipOptimizeOptions tolerances;  // what "constant" means
  bool compactClips = true;        // quantize the keys the runtime samples (compact_clip.hpp)
  CompactClipOptions compaction;   // the error budget, and where it is measured
};

// Optimizes the clip (unless told not to) and extracts its root motion
// (pickRootMotionJoint, or `rootJoint`) alongside it; the clip's own tracks
// are kept as authored (the in-place ones are AnimationClip::inPlaceRoot).
[[nodiscard]] std::shared_ptr<const AnimationClip> makeAnimationClip(Clip clip, const Skeleton& skeleton,
                                                                      const AnimationClipOptions& options = {},
                                                                      int rootJoint = -1);

// Samples the clip as the runtime plays it: the compact keys when the clip has them,
// else the float ones; with `inPlace`, the in-place root tracks over them (when the clip
// has root motion). Per-frame code: no allocation; the cursors serve the float form.
void sampleAnimationClip(const AnimationClip& clip, float time, bool inPlace, std::span<const Transform> rest,
                         std::span<Transform> out, SamplingCursor* cursor = nullptr,
                         SamplingCursor* rootCursor = nullptr) noexcept;
// The same with the rest pose of the skeleton the clip was made for (AnimationClip::pose):
// the same bits as passing that skeleton's restPose, faster. What the runtime plays.
void sampleAnimationClip(const AnimationClip& clip, float time, bool inPlace, std::span<Transform> out,
                         SamplingCursor* cursor = nullptr, SamplingCursor* rootCursor = nullptr) noexcept;

}  // namespace marionette
