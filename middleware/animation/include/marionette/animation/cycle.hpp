// Clip cycles: a time range cut out of a clip, and the loop a gait clip needs.
// A walk cut at arbitrary times from a longer take pops where it loops; the
// search below finds, within a range, the sub-range whose end pose best matches
// its start pose, and closeLoop() spreads what is left over the cycle and turns
// it to face +Z (what the locomotion expects of a walk clip). Command time only
// (allocates).
#pragma once
#include <span>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

// The clip from `start` to `end` (seconds, clamped to [0, duration]) resampled
// at `rate` frames per second (both ends included), with times from 0: linear
// tracks for each property the clip animates. Morph tracks are dropped.
[[nodiscard]] Clip cutClip(const Clip& clip, const Skeleton& skeleton, float start, float end, float rate);

struct LoopSearchOptions {
  float minDuration = 0.8f;   // s: about one gait cycle of a human walk ...
  float maxDuration = 2.6f;   // s: ... to two
  float step = 1.0f / 120.0f; // s between the candidate start and end times
  int rootJoint = -1;         // the travelling joint; -1: pickRootMotionJoint
};

// How well a sub-range loops. The residual compares the pose at `end` with the
// pose at `start`: every animated joint's local rotation, the root's model
// rotation with its yaw removed (the root may turn and travel); the root's
// height is compared separately.
struct LoopMatch {
  bool found = false;
  float start = 0.0f, end = 0.0f;  // seconds of the searched clip
  float residual = 0.0f;           // radians, RMS over the animated joints
  float worstJoint = 0.0f;         // radians, the largest single joint difference
  int worstJointIndex = -1;
  float rootHeight = 0.0f;         // model units, end minus start
  float turn = 0.0f;               // radians, the root's yaw from start to end
};

// The sub-range of [from, to] (seconds) with a duration in [minDuration,
// maxDuration] whose end pose best matches its start pose (smallest residual).
// found = false when the range is shorter than minDuration or nothing is animated.
[[nodiscard]] LoopMatch findBestLoop(const Clip& clip, const Skeleton& skeleton, float from, float to,
                                     const LoopSearchOptions& options = {});

// Makes a cut cycle (times from 0, linear tracks, e.g. cutClip's) loop and face
// +Z: each joint's local rotation (the root's: without its yaw) and the root's
// height are corrected by a share of the end-to-start difference growing
// linearly with time, so the last key matches the first; then the root is turned
// about +Y so that its facing at time 0 is its rest facing and moved so that it
// starts over its rest place (x, z). `rootJoint` < 0: pickRootMotionJoint.
// Returns the yaw it turned the clip by (radians).
float closeLoop(Clip& clip, const Skeleton& skeleton, int rootJoint = -1);

// Moves the root's translation track up or down (model +Y) so that the feet come
// down to where the rest pose has them: over the clip (sampled at 120 Hz), the
// lowest height of each of `feet` (ankles, toes) above its rest height, the
// smallest of these, is taken out. A retargeted walk whose legs bend differently
// floated or sank by that much. Returns the shift (model units); 0 without feet
// or a root translation track.
float groundClip(Clip& clip, const Skeleton& skeleton, std::span<const int> feet, int rootJoint = -1);

}  // namespace marionette
