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
  out->pose = skeleton.restPose;
  applyCompactClipConstants(out->compact, out->pose);  // none when the clip stays float
  return out;
}

namespace {

// A cursor sized for the float clip has a hint for each compact track too (a float
// track makes at most three of them); the compact sampler keeps its own hints there.
std::uint32_t* hintsIn(SamplingCursor* c, const Clip& floats, const CompactClip& compact) noexcept {
  return c && c->clip == &floats && c->keys.size() >= compact.tracks.size() ? c->keys.data() : nullptr;
}

// The in-place root tracks over `out`, when the clip travels and is played in place.
void sampleInPlaceRoot(const AnimationClip& clip, float time, std::span<Transform> out, SamplingCursor* rootCursor) noexcept {
  if (!clip.compact.empty())
    sampleCompactClipTracks(clip.compactInPlaceRoot, time, out, hintsIn(rootCursor, clip.inPlaceRoot, clip.compactInPlaceRoot));
  else
    sampleClipTracks(clip.inPlaceRoot, time, out, rootCursor);
}

}  // namespace

void sampleAnimationClip(const AnimationClip& clip, float time, bool inPlace, std::span<const Transform> rest,
                         std::span<Transform> out, SamplingCursor* cursor, SamplingCursor* rootCursor) noexcept {
  const std::span<Transform> sampled = out.first(std::min(rest.size(), out.size()));
  if (!clip.compact.empty())
    sampleCompactClip(clip.compact, time, rest, out, hintsIn(cursor, clip.clip, clip.compact));
  else
    sampleClip(clip.clip, time, rest, out, cursor);
  if (inPlace && !clip.rootMotion.empty()) sampleInPlaceRoot(clip, time, sampled, rootCursor);
}

void sampleAnimationClip(const AnimationClip& clip, float time, bool inPlace, std::span<Transform> out, SamplingCursor* cursor,
                         SamplingCursor* rootCursor) noexcept {
  const std::span<Transform> sampled = out.first(std::min(clip.pose.size(), out.size()));
  if (!clip.compact.empty()) {
    std::copy(clip.pose.begin(), clip.pose.begin() + static_cast<std::ptrdiff_t>(sampled.size()), sampled.begin());
    sampleCompactClipAnimated(clip.compact, time, sampled, hintsIn(cursor, clip.clip, clip.compact));
  } else {
    sampleClip(clip.clip, time, clip.pose, out, cursor);
  }
  if (inPlace && !clip.rootMotion.empty()) sampleInPlaceRoot(clip, time, sampled, rootCursor);
}

}  // namespace marionette
