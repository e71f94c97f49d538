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
  if (options.compactClips) {
    out->compact = compactClip(out->clip, skeleton, options.compaction, &out->compaction);
    // Both forms or neither: a layer samples the clip and its in-place root tracks alike.
    if (!out->compact.empty() && !out->inPlaceRoot.tracks.empty()) {
      out->compactInPlaceRoot = compactClip(out->inPlaceRoot, skeleton, options.compaction, &out->compactionInPlaceRoot);
      if (out->compactInPlaceRoot.empty()) out->compact = {};
    }
  }
  return out;
}

void sampleAnimationClip(const AnimationClip& clip, float time, bool inPlace, std::span<const Transform> rest,
                         std::span<Transform> out, SamplingCursor* cursor, SamplingCursor* rootCursor) noexcept {
  const bool travels = inPlace && !clip.rootMotion.empty();
  if (!clip.compact.empty()) {
    // A cursor sized for the float clip has a hint for each compact track too (a float
    // track makes at most three of them); the compact sampler keeps its own hints there.
    const auto hints = [](SamplingCursor* c, const Clip& floats, const CompactClip& compact) -> std::uint32_t* {
      return c && c->clip == &floats && c->keys.size() >= compact.tracks.size() ? c->keys.data() : nullptr;
    };
    sampleCompactClip(clip.compact, time, rest, out, hints(cursor, clip.clip, clip.compact));
    if (travels)
      sampleCompactClipTracks(clip.compactInPlaceRoot, time, out.first(std::min(rest.size(), out.size())),
                              hints(rootCursor, clip.inPlaceRoot, clip.compactInPlaceRoot));
    return;
  }
  sampleClip(clip.clip, time, rest, out, cursor);
  if (travels) sampleClipTracks(clip.inPlaceRoot, time, out.first(std::min(rest.size(), out.size())), rootCursor);
}

}  // namespace marionette
