// How good a retargeted motion is, measured against its source (offline, for
// reports and tests; allocates):
//  - end-effector error: hands, feet and head relative to the hips, each side
//    divided by its character's height, the source turned by the facing
//    alignment; mean and max over effectors and frames, as a fraction of height;
//  - segment directions: the angle between each limb and spine segment's direction,
//    source against target (proportion-free), mean, p95 and max in degrees;
//  - foot skating: how fast each side's feet slide during the source's foot
//    contacts, in its own leg lengths per second; the target's over the source's.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/rig/joint_map.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::retarget {

// Rest height: the head joint above the lowest foot or toe joint (model +Y); 0
// when the map lacks them.
[[nodiscard]] float characterHeight(const Skeleton& skeleton, const JointMap& map);
// Rest leg length (hip to knee to ankle, mean of both sides); 0 without legs.
[[nodiscard]] float restLegLength(const Skeleton& skeleton, const JointMap& map);

// RetargetOptions::sourceHipsReference for a clip: the source's rest hips moved
// up or down so that its rest feet stand on the clip's ground (the lowest foot
// or toe joint height over the clip), when the target's rest feet stand on y = 0
// (within a quarter of its hip height), as characters do. BVH files keep the rest
// hips at the origin while the motion stands on y = 0; without this the target
// would sink by the source's hip height. Unset (rest maps to rest) when the
// target's rest floats too (a BVH target), or a map lacks hips or feet.
[[nodiscard]] std::optional<glm::vec3> standingHipsReference(const Skeleton& source, const JointMap& sourceMap,
                                                             const Clip& clip, const Skeleton& target,
                                                             const JointMap& targetMap);

// Every figure says what it covers: the effectors or segments both maps have, and those left
// out. With samples == 0 the figures are over nothing (a report prints "n/a", never 0).
struct EffectorError {
  double mean = 0.0, max = 0.0;  // fraction of character height
  int samples = 0;
  std::vector<Bone> effectors, missing;  // of hands, feet and head: measured, and not
};
// Sampled at `rate` frames per second over the shorter clip. `facing`: the
// retargeter's facingAlignment(), applied to the source.
[[nodiscard]] EffectorError endEffectorError(const Skeleton& source, const JointMap& sourceMap, const Clip& sourceClip,
                                             const Skeleton& target, const JointMap& targetMap, const Clip& targetClip,
                                             const glm::quat& facing, float rate = 60.0f);

// Segment directions, free of proportions: the angle between each body segment's
// direction in the source (turned by `facing`) and in the target, frame by frame. The
// segments: hips to neck (the spine), neck to head, upper arm, forearm, thigh and shin of
// each side, where both maps have both ends. End-effector error divided by height
// mixes proportions in (a head a third of the height reads as a large error while every
// limb points the same way); this does not.
struct SegmentDirectionError {
  double meanDegrees = 0.0, p95Degrees = 0.0, maxDegrees = 0.0;
  int samples = 0;  // segment-frames compared
  // Of the 10 segments ("spine", "neck", "leftUpperArm" for the upper arm, ...): compared,
  // and not (an end missing from a map).
  std::vector<std::string> segments, missing;
};
[[nodiscard]] SegmentDirectionError segmentDirectionError(const Skeleton& source, const JointMap& sourceMap,
                                                          const Clip& sourceClip, const Skeleton& target,
                                                          const JointMap& targetMap, const Clip& targetClip,
                                                          const glm::quat& facing, float rate = 60.0f);

// Foot skating over the source's contacts: frames where a source foot is down
// (at most contactHeight leg lengths above its lowest point in the clip) and
// slow (at most contactSpeed leg lengths per second horizontally). Over those
// frames, the mean horizontal foot speed of each side in its own leg lengths
// per second; ratio = target / source (below 1: the output slides less than
// the source, e.g. with feet IK holding contacts; 0 when the source never slides).
struct SkatingComparison {
  double source = 0.0, target = 0.0, ratio = 0.0;
  double contactFraction = 0.0;  // of foot-frames
  int feet = 0;                  // of the two, compared (both maps have it, with legs to measure by)
  int contacts = 0;              // foot-frames in contact: 0, the figures are over nothing
};
[[nodiscard]] SkatingComparison compareSkating(const Skeleton& source, const JointMap& sourceMap,
                                               const Clip& sourceClip, const Skeleton& target,
                                               const JointMap& targetMap, const Clip& targetClip, float rate = 60.0f,
                                               float contactHeight = 0.1f, float contactSpeed = 0.5f);

}  // namespace marionette::retarget
