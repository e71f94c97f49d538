// Retargeting: a motion made for one skeleton drives another, through the two
// skeletons' joint maps (joint_map.hpp). Bound once at command time; applied per
// frame without allocation, or to a whole clip offline.
//
// Method (all rotations are the joints' true model-space rotations, rootTransform
// and mirrored (negative-scale) joints included):
//  - Rest-pose compensation in model space. For a canonical bone mapped on both
//    sides, the source's model-space change from its rest, D = Qs * inverse(QsRest),
//    is applied to the target's rest, after C, the minimal rotation that turns the
//    target's rest bone direction (to its mapped child: upper arm to lower arm,
//    ...) onto the source's: Qt = A * D * inverse(A) * C * QtRest. So joint axes
//    and bone roll may differ (only the change from rest is transferred), and so
//    may rest shapes (T-pose, A-pose, arms down): a target bone points where the
//    source's points. A is the yaw (about model +Y) that turns the source's rest
//    facing into the target's (from the hips' left-right axis), so a character
//    facing -Z plays a +Z motion in its own frame. Bones without a mapped child
//    on both sides (hips, head, hands without fingers) take C = identity.
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
//    vertical part by the hip-height ratio (the hip joints, where the legs attach,
//    above the feet at rest),
//    added to the target's rest hips.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/rig/joint_map.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette::retarget {

// Contact preservation: proportions that differ make a planted foot slide,
// since the target's foot follows its own (longer or shorter) leg. When the
// source's foot (or hand) is in contact, the target's is held where it was when
// the contact began (horizontally; its height follows the motion), by two-bone
// IK on the leg (arm); the foot keeps the source's orientation. On release the
// held offset eases out over blendTime.
// Contact: the source foot is at most contactHeight leg lengths above its rest
// height and moves at most contactSpeed leg lengths per second horizontally; a
// hand: it moves at most handContactSpeed leg lengths per second (any height).
struct RetargetIk {
  bool feet = false;
  bool hands = false;
  float contactHeight = 0.1f;
  float contactSpeed = 0.5f;
  float handContactSpeed = 0.1f;
  float blendTime = 0.15f;  // s
};

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
  // Limb IK with contact preservation (see RetargetIk); off by default.
  RetargetIk ik;
};

// Per-frame working memory of apply(): one model rotation per source and target joint.
// Also the contact state of one motion stream (a character): keep one scratch per
// character when IK is on, and reset() it when the motion jumps.
struct RetargetScratch {
  std::vector<glm::quat> source;
  std::vector<glm::quat> target;
  std::vector<glm::mat4> sourceModel;  // IK only
  std::vector<glm::mat4> targetModel;  // IK only
  struct Effector {
    bool inContact = false;
    bool havePrevious = false;
    glm::vec3 previousSource{0.0f};  // source effector, model space, last frame
    glm::vec3 held{0.0f};            // target effector at contact start
    glm::vec2 offset{0.0f};          // horizontal correction at release, eased out
    float sinceRelease = 1e30f;      // s
  };
  std::array<Effector, 4> effectors;  // left foot, right foot, left hand, right hand
  void reset() noexcept { effectors = {}; }
};

class Retargeter {
 public:
  Retargeter() = default;

  // Command time. Never throws for bad data: a skeleton that fails validate(), or
  // joint maps with out-of-range indices, give a binding that writes the target's
  // rest pose, with a note saying why.
  [[nodiscard]] static Retargeter bind(const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                                       const JointMap& targetMap, const RetargetOptions& options = {});

  // Per frame: target local pose from the source local pose, through the caller's scratch
  // (sized by makeScratch(); one per stream, so one binding serves many threads). No
  // allocation, no exceptions, never NaN (non-finite inputs fall back to rest). Spans (or a
  // scratch) shorter than the skeletons' joint counts write the target's rest pose (when it
  // fits). `dt` is the time since the previous frame of this stream (contact speeds);
  // dt <= 0 (a jump, or the first frame) releases all contacts at once.
  void apply(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal, RetargetScratch& scratch,
             float dt = 0.0f) const noexcept;
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
    glm::quat restModel{1.0f, 0.0f, 0.0f, 0.0f};  // C * QtRest
    glm::quat direct{1.0f, 0.0f, 0.0f, 0.0f};     // one source joint: pre(srcA) * restModel, so Qt = A * Qs * direct
    glm::quat restFlipped{1.0f, 0.0f, 0.0f, 0.0f};
    bool needsModel = true;  // its model rotation is read (a driven joint below it, or IK)
    Transform rest;
  };
  struct SourceJoint {
    int parent = -1;
    glm::vec3 flip{1.0f};
    glm::quat pre{1.0f, 0.0f, 0.0f, 0.0f};  // inverse(QsRest) * inverse(A), for mapped joints
    bool used = false;                      // some target joint reads its D
    bool needed = false;                    // used, or an ancestor of a used joint
  };

  void applyImpl(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal, RetargetScratch& scratch,
                 float dt) const noexcept;

  // bind()'s steps, in the order it takes them (retarget_binding.cpp). RestFrames:
  // both skeletons' rest model rotations and matrices; RestShapes: the rest-shape
  // rotations C gathered while the joints are paired.
  struct RestFrames;
  struct RestShapes;
  [[nodiscard]] static bool checkBindInputs(Retargeter& r, const Skeleton& source, const JointMap& sourceMap,
                                            const Skeleton& target, const JointMap& targetMap);
  [[nodiscard]] static RestFrames bindRestFrames(Retargeter& r, const Skeleton& source, const Skeleton& target);
  static void bindFacing(Retargeter& r, const JointMap& sourceMap, const JointMap& targetMap, const RestFrames& frames);
  static void bindJointRests(Retargeter& r, const Skeleton& source, const RestFrames& frames);
  static void driveJoint(Retargeter& r, int t, int a, int b, float w);
  static void pairBones(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                        const JointMap& targetMap, const RestFrames& frames, RestShapes& shapes);
  static void pairChains(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                         const JointMap& targetMap, const RestFrames& frames, RestShapes& shapes);
  static void applyRestShapes(Retargeter& r, const RestFrames& frames, RestShapes& shapes);
  static void bindHips(Retargeter& r, const Skeleton& source, const JointMap& sourceMap, const Skeleton& target,
                       const JointMap& targetMap, const RestFrames& frames, const RetargetOptions& options);
  static void bindDetachedEnds(Retargeter& r, const Skeleton& target, const JointMap& targetMap,
                               const RestFrames& frames);
  static void foldPerFrameShortcuts(Retargeter& r);
  void bindIk(const Skeleton& source, const JointMap& sourceMap, const Skeleton& target, const JointMap& targetMap,
              const std::vector<glm::mat4>& sourceRestModel, const RetargetIk& ik);
  void applyIk(std::span<const Transform> sourceLocal, std::span<Transform> targetLocal, RetargetScratch& scratch,
               float dt) const noexcept;

  // One IK effector: a two-bone limb of the target, the source joint whose
  // contacts it copies, and the target end joint whose model rotation is restored.
  struct IkEffector {
    LimbIk limb;
    int sourceEnd = -1;
    bool foot = false;
  };

  std::vector<int> sourceParents_;
  std::vector<SourceJoint> source_;
  std::vector<TargetJoint> target_;
  std::vector<int> hipsPath_;  // source hips and its ancestors, root first
  std::vector<Transform> sourceRest_;
  glm::quat sourceRoot_{1.0f, 0.0f, 0.0f, 0.0f}, targetRoot_{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 sourceRootFlip_{1.0f}, targetRootFlip_{1.0f};
  glm::mat4 sourceRootTransform_{1.0f};
  glm::quat align_{1.0f, 0.0f, 0.0f, 0.0f};
  bool alignIdentity_ = true;
  float hScale_ = 1.0f, vScale_ = 1.0f;
  bool translateHips_ = false;
  int sourceHips_ = -1, targetHips_ = -1;
  glm::vec3 sourceHipsRef_{0.0f}, targetHipsRest_{0.0f};
  glm::mat4 targetHipsParentInverse_{1.0f};  // model -> the hips' parent space (its ancestors stay at rest)
  std::vector<std::string> notes_;
  bool valid_ = false;
  // Target feet or hands that do not hang from their limb (RobotExpressive's feet
  // are IK targets under the root): placed every frame at the limb's end.
  struct DetachedEnd {
    int end = -1, lower = -1;
    glm::vec3 offsetInLower{0.0f};
  };
  std::vector<DetachedEnd> detached_;
  void placeDetached(std::span<Transform> targetLocal) const noexcept;
  // IK (empty limbs when off): copies of the skeletons for the solver and FK.
  RetargetIk ik_;
  std::array<IkEffector, 4> effectors_;
  bool anyIk_ = false;
  Skeleton sourceSkeleton_, targetSkeleton_;
  float sourceLegLength_ = 0.0f;
  std::array<float, 2> sourceFootRestY_{};  // where a source foot stands on the ground, model +Y
};

}  // namespace marionette::retarget
