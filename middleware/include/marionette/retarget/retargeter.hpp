// Retargeting: a motion made for one skeleton drives another, through the two
// skeletons' joint maps (joint_map.hpp). Bound once at command time; applied per
// frame without allocation, or to a whole clip offline.
//
// Method (all rotations are the joints' true model-space rotations, rootTransform
// and mirrored (negative-scale) joints included):
//  - Rest-pose compensation in model space. For a canonical bone mapped on both
//    sides, the source's model-space change from its rest, D = Qs * inverse(QsRest),
//    is applied to the target's rest: Qt = A * D * inverse(A) * QtRest. So joint axes,
//    bone roll and rest shape (T-pose, A-pose, arms down) may differ: only the
//    change from rest is transferred. A is the yaw (about model +Y) that turns the
//    source's rest facing into the target's (from the hips' left-right axis), so a
//    character facing -Z plays a +Z motion in its own frame.
//  - Chains (spine, neck, fingers) with different joint counts: each joint of a
//    chain stands for the bone from it to the next joint (the last one to the
//    joint after the chain: the neck, the head). A target bone takes the source's
//    change D at the middle of that bone, as a fraction of the chain's rest length;
//    between the source's bone middles D is slerped, beyond the first / last it is
//    clamped. Equal chains map joint to joint exactly.
//  - Target joints without a source (unmapped, or mapped on one side only) keep
//    their rest local rotation; all target translations and scales stay at rest,
//    except the hips' translation.
//  - Hips translation: the source's hips displacement from a reference (its rest
//    hips, or RetargetOptions::sourceHipsReference), turned by A, with the
//    horizontal part scaled by the leg-length ratio (stride follows legs) and the
//    vertical part by the hip-height ratio (hip height above the feet at rest),
//    added to the target's rest hips.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/retarget/joint_map.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::retarget {

struct RetargetOptions {
  bool translateHips = true;   // false: the target's hips stay at their rest translation
  bool alignFacing = true;     // false: A = identity (both rests taken to face the same way)
  // Scale factors of the hips displacement; unset: leg-length ratio (horizontal),
  // hip-height ratio (vertical), 1 when a side lacks legs.
  std::optional<float> horizontalScale;
  std::optional<float> verticalScale;
  // Source model-space hips position that corresponds to the target's rest hips.
  // Unset: the source's rest hips. BVH files often keep the rest hips at the
  // origin while the motion stands at hip height; pass a standing frame's hips then.
  std::optional<glm::vec3> sourceHipsReference;
  // Later step (not implemented yet): two-bone IK on feet and hands after the
  // rotation transfer, pinning feet in contact (animation/foot_contacts.hpp). When
  // true, bind() adds a note saying it is ignored.
  bool limbIk = false;
};

// Per-frame working memory of apply(): one model rotation per source and target joint.
struct RetargetScratch {
  std::vector<glm::quat> source;
  std::vector<glm::quat> target;
};

class Retargeter {
 public:
  Retargeter() = default;

  // Command time. Never throws for bad data: a skeleton that fails validate(), or
  // joint maps with out-of-range indices, give a binding that writes the target's
  // rest pose, with a note saying why.
  [[nodiscard]] static Retargeter bind(const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                                       const JointMap& targetMap, const RetargetOptions& options = {});

  // Per frame: target local pose from the source local pose. No allocation, no
  // exceptions, never NaN (non-finite inputs fall back to rest). Spans shorter
  // than the skeletons' joint counts write the target's rest pose (when it fits).
  // This overload uses the binding's own scratch: one thread at a time per binding.
  void apply(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal) const noexcept;
  // Same with caller scratch (sized by makeScratch()): a shared binding on many threads.
  void apply(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal,
             RetargetScratch& scratch) const noexcept;
  [[nodiscard]] RetargetScratch makeScratch() const;

  // Offline: the whole clip, sampled at its own key times (sampleRate <= 0: the union
  // of all its tracks' key times) or at `sampleRate` frames per second from 0 to its
  // duration, into a clip for the target skeleton: linear rotation tracks for every
  // target joint the source drives, a translation track for the hips. Morph tracks
  // are dropped (different characters, different morphs).
  [[nodiscard]] Clip retargetClip(const Clip& sourceClip, float sampleRate = 0.0f) const;

  // What bind() found: canonical bones and chains mapped on one side only, chains
  // of different lengths, degenerate rest data, the scale factors chosen.
  [[nodiscard]] const std::vector<std::string>& notes() const noexcept { return notes_; }
  [[nodiscard]] bool valid() const noexcept { return valid_; }
  [[nodiscard]] std::size_t sourceJointCount() const noexcept { return sourceParents_.size(); }
  [[nodiscard]] std::size_t targetJointCount() const noexcept { return target_.size(); }
  [[nodiscard]] glm::quat facingAlignment() const noexcept { return align_; }
  [[nodiscard]] float horizontalScale() const noexcept { return hScale_; }
  [[nodiscard]] float verticalScale() const noexcept { return vScale_; }
  // Target joints whose rotation follows the source.
  [[nodiscard]] std::vector<int> drivenJoints() const;

 private:
  struct TargetJoint {
    int parent = -1;
    int srcA = -1, srcB = -1;  // source joints whose D drives this one; srcA < 0: rest
    float weight = 0.0f;       // slerp weight from srcA to srcB
    glm::vec3 flip{1.0f};      // signs of the vector part: model rotation <-> local rotation under mirrors
    glm::quat restModel{1.0f, 0.0f, 0.0f, 0.0f};
    Transform rest;
  };
  struct SourceJoint {
    int parent = -1;
    glm::vec3 flip{1.0f};
    glm::quat pre{1.0f, 0.0f, 0.0f, 0.0f};  // inverse(QsRest) * inverse(A), for mapped joints
    bool used = false;                      // some target joint reads its D
  };

  void applyImpl(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal,
                 RetargetScratch& scratch) const noexcept;

  std::vector<int> sourceParents_;
  std::vector<SourceJoint> source_;
  std::vector<TargetJoint> target_;
  std::vector<int> hipsPath_;  // source hips and its ancestors, root first
  std::vector<Transform> sourceRest_;
  glm::quat sourceRoot_{1.0f, 0.0f, 0.0f, 0.0f}, targetRoot_{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 sourceRootFlip_{1.0f}, targetRootFlip_{1.0f};
  glm::mat4 sourceRootTransform_{1.0f};
  glm::quat align_{1.0f, 0.0f, 0.0f, 0.0f};
  float hScale_ = 1.0f, vScale_ = 1.0f;
  bool translateHips_ = false;
  int sourceHips_ = -1, targetHips_ = -1;
  glm::vec3 sourceHipsRef_{0.0f}, targetHipsRest_{0.0f};
  glm::mat4 targetHipsParentInverse_{1.0f};  // model -> the hips' parent space (its ancestors stay at rest)
  std::vector<std::string> notes_;
  bool valid_ = false;
  mutable RetargetScratch scratch_;
};

}  // namespace marionette::retarget
