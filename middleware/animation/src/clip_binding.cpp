#include "marionette/animation/clip_binding.hpp"

#include <algorithm>
#include <utility>

namespace marionette {

Clip bindClipByName(const Clip& clip, const Skeleton& from, const Skeleton& to, int* unmatched) {
  Clip out;
  out.name = clip.name;
  out.duration = clip.duration;
  out.morphTracks = clip.morphTracks;
  out.events = clip.events;
  int missing = 0;
  for (const JointTrack& jt : clip.tracks) {
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= from.jointCount()) {
      ++missing;
      continue;
    }
    int target = to.findJoint(from.names[jt.joint]);
    if (target < 0) {
      ++missing;
      continue;
    }
    JointTrack copy = jt;
    copy.joint = target;
    out.tracks.push_back(std::move(copy));
  }
  std::sort(out.tracks.begin(), out.tracks.end(),
            [](const JointTrack& a, const JointTrack& b) { return a.joint < b.joint; });
  if (unmatched) *unmatched = missing;
  return out;
}

}  // namespace marionette
