// Foot contacts of a locomotion clip: when, as a phase of the cycle, a foot is
// on the ground (low and not sliding), found once at load time by sampling the
// clip; and, per frame, whether a phase is in contact and how much foot IK
// should hold the foot there.
#pragma once
#include <span>
#include <vector>

#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct AnimationClip;  // marionette/animation/animation_clip.hpp

// A contact as normalized phases of the cycle, each in [0, 1). It wraps when
// begin > end (a contact across the clip's loop point). A foot that never
// lifts gives {0, 1}.
struct ContactInterval {
  float begin = 0.0f, end = 0.0f;
};

// Lengths and speeds are for a human-sized character (legs about 0.9 m): for
// another size, scale heightAboveLowest and maxSpeed by its leg length / 0.9 m
// (RobotExpressive is about 3 m tall in its model units: 1.7).
struct FootContactOptions {
  float heightAboveLowest = 0.05f;  // m: a foot in contact is at most this far above its lowest point in the clip
  float maxSpeed = 0.5f;            // m/s, horizontal, in the ground frame
  float minDuration = 0.05f;        // s: shorter contacts, and shorter gaps inside one, are noise
  int samplesPerSecond = 240;
  // In-place clips only: maxSpeed plus this fraction of the ground speed. Their
  // ground frame is an estimate, and their stance feet often do not move at one
  // speed (RobotExpressive's Walking: 0.8 to 6.8 units/s for a mean of 4.5).
  float inPlaceSpeedAllowance = 0.5f;
};

// The options for a character whose leg (hip to ankle) is `legLength` long:
// heightAboveLowest and maxSpeed scaled by legLength / 0.9 m. `base` unchanged
// when legLength is not a positive finite number.
[[nodiscard]] FootContactOptions footContactOptionsForLeg(float legLength, FootContactOptions base = {}) noexcept;

// The contact intervals of `footJoint` (model space, +Y up) over one cycle of
// `clip`, in phase order. The clip is taken as a loop.
//
// Speed in the ground frame: a clip with root motion is sampled as authored
// (clip.clip keeps the root's travel), so a planted foot stands still. A clip in
// place (no root motion, or a net travel per cycle under a fifth of the foot's
// stride relative to the root) has its ground moving under the character: the
// ground's velocity is taken as the foot's median horizontal velocity over its
// lowest 30 % of frames (stance, when it is on the ground and carried backward),
// and the foot's speed is measured relative to it, with inPlaceSpeedAllowance.
//
// Empty when the clip has no duration, the foot is out of range, or every
// sample is non-finite (NaN keys give no NaN out). Load-time: allocates.
[[nodiscard]] std::vector<ContactInterval> detectFootContacts(const AnimationClip& clip, const Skeleton& skeleton,
                                                              int footJoint, const FootContactOptions& settings = {});

// True when `phase` (wrapped into [0, 1)) lies in one of the intervals.
[[nodiscard]] bool inContact(std::span<const ContactInterval> contacts, float phase) noexcept;

// 1 inside a contact; outside, a smoothstep ramp from 1 at the contact's ends to
// 0 at `blendPhase` from them (so IK holding the foot eases in before touchdown
// and out after lift-off); 0 elsewhere. blendPhase <= 0 gives 0 or 1. Never NaN
// (a NaN phase gives 0).
[[nodiscard]] float contactWeight(std::span<const ContactInterval> contacts, float phase, float blendPhase) noexcept;

}  // namespace marionette
