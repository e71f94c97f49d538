// Rig: what many characters made from one asset share (read-only once shared): the
// skeleton, the morph-target names and a library of clips bound to that skeleton, with
// their root motion, plus the profile resolved to joints. Copied out of the imported
// Asset at construction; the rig keeps no reference to it, so the meshes, materials and
// images stay with whoever draws them (the renderer is given the asset, not the rig).
// One copy of the data for 1000 characters.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/animation/animation_clip.hpp"
#include "marionette/animation/blend_space.hpp"
#include "marionette/animation/animation_events.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/asset/asset.hpp"
#include "marionette/rig/character_profile.hpp"

namespace marionette {

// What a rig does to the clips it loads: kept for its lifetime (the clips added
// later are prepared the same), handed to each makeAnimationClip call.
using RigSettings = AnimationClipOptions;

// The profile resolved to indices once, for the controllers' per-frame use.
struct RigJoints {
  int hips = -1, neck = -1, head = -1, leftEye = -1, rightEye = -1, jaw = -1;
  std::vector<int> spine;
  struct LimbJoints {
    int upper = -1, lower = -1, end = -1;  // as CharacterProfile's Limb
  };
  LimbJoints leftLeg, rightLeg, leftArm, rightArm;
  int leftToe = -1, rightToe = -1;
  // Face expression name -> (morph target index, amount).
  std::map<std::string, std::vector<std::pair<int, float>>, std::less<>> face;
  // FACS key ("AU12_L") -> what shows it when `face` has no such key (CharacterProfile::facs).
  struct FacsJoint {
    int joint = -1;
    FacsJointRule rule;
  };
  struct FacsUnit {
    std::vector<std::pair<int, float>> morphs;
    std::vector<FacsJoint> joints;
    std::string source;
  };
  std::map<std::string, FacsUnit, std::less<>> facs;
  // Lip-sync channel (speech/lipsync.hpp index) -> morph target, at full channel weight.
  struct LipMorph {
    int channel = 0, morph = 0;
    float amount = 1.0f;
  };
  std::vector<LipMorph> visemes;
  bool jawOpenByMorph = false;     // a morph shows the jaw-open channel: the jaw joint is left alone
  glm::vec3 leftAxis{1.0f, 0.0f, 0.0f};  // model frame, level: the character's left (arms, legs or eyes at rest)
  // Model-frame height of the eyes at rest: the eye joints', else the head's, else 94 % of the
  // highest joint's; what another character looks at when it names this one without a joint.
  float eyeHeight = 1.6f;
};

class Rig {
 public:
  // Copies the skeleton and the morph-target names and compiles the asset's clips;
  // the profile is guessed from the asset (guessCharacterProfile).
  explicit Rig(const Asset& asset, const RigSettings& settings = {});

  [[nodiscard]] const Skeleton& skeleton() const noexcept { return skeleton_; }
  // The character's morph-target order (Asset::morphTargets): the transform buffer's weights.
  [[nodiscard]] const std::vector<std::string>& morphTargets() const noexcept { return morphTargets_; }
  // The file the asset came from (Asset::sourcePath), for messages.
  [[nodiscard]] const std::string& sourcePath() const noexcept { return sourcePath_; }
  [[nodiscard]] const std::vector<std::shared_ptr<const AnimationClip>>& clips() const noexcept { return clips_; }
  [[nodiscard]] std::shared_ptr<const AnimationClip> findClip(std::string_view name) const noexcept;
  // The skeleton's inverse binds laid out for the per-frame palette (pose.hpp).
  [[nodiscard]] const PaletteBasis& paletteBasis() const noexcept { return paletteBasis_; }

  // What the controllers know about the asset: guessed at construction
  // (guessCharacterProfile) unless replaced, e.g. by loadCharacterProfile's.
  // Set profiles before sharing the rig between characters.
  [[nodiscard]] const CharacterProfile& profile() const noexcept { return profile_; }
  [[nodiscard]] const RigJoints& joints() const noexcept { return joints_; }
  void setProfile(CharacterProfile profile);

  // Adds a clip from another file of the same skeleton naming (bound by joint
  // name). Returns the number of its tracks that found no joint.
  int addClip(const Clip& clip, const Skeleton& clipSkeleton, std::string name = {});

  // Blend spaces (animation/blend_space.hpp): the profile's, made by setProfile with the
  // rig's clips (a space that cannot be made is left out, with a line in profile().notes),
  // and those added from code. Add before sharing the rig between characters.
  [[nodiscard]] const std::vector<std::shared_ptr<const BlendSpace>>& blendSpaces() const noexcept { return blendSpaces_; }
  [[nodiscard]] std::shared_ptr<const BlendSpace> findBlendSpace(std::string_view name) const noexcept;
  // A space from a definition: its clips by name from this rig, the feet (and their contact
  // thresholds, scaled by the leg's length) from the profile's legs. Null with `error` saying
  // why (blend_space.hpp: unknown clips, duplicate points, a degenerate 2D layout, ...).
  [[nodiscard]] std::shared_ptr<const BlendSpace> makeBlendSpace(const BlendSpaceDefinition& definition,
                                                                 std::string& error) const;
  // Adds a space, replacing one of the same name. False (nothing added) for null.
  bool addBlendSpace(std::shared_ptr<const BlendSpace> space);

  // The animation events of one of the rig's clips (animation_events.hpp): its feet's
  // contacts (the profile's leg ends) and its markers (Clip::events, then the profile's
  // "events" for its name). Found the first time a clip's events are asked for (a layer
  // starting to play it: command time), not at load: a rig whose events nobody asks for pays
  // no foot-contact analysis. Safe from several threads (a shared rig). Null for a clip that
  // is not the rig's.
  [[nodiscard]] std::shared_ptr<const AnimationEventTrack> events(const AnimationClip& clip) const noexcept;

 private:
  std::string sourcePath_;
  Skeleton skeleton_;
  std::vector<std::string> morphTargets_;
  RigSettings settings_;
  std::vector<std::shared_ptr<const AnimationClip>> clips_;
  PaletteBasis paletteBasis_;
  CharacterProfile profile_;
  RigJoints joints_;
  std::vector<std::shared_ptr<const BlendSpace>> blendSpaces_;
  void makeProfileBlendSpaces();  // rig_blend_spaces.cpp
  // Per clip, as clips_: its events, and the foot contacts found for them with the feet
  // and leg lengths they were found for (a setProfile naming the same feet reuses them).
  struct ClipEvents {
    std::shared_ptr<const AnimationEventTrack> track;
    bool current = false;  // track made for the present profile (setProfile clears it)
    int foot[2] = {-1, -1};
    float leg[2] = {0.0f, 0.0f};
    std::vector<ContactInterval> contacts[2];
  };
  // Made on first use under a lock: characters on several threads may share the rig. A copy
  // of the rig copies what was found.
  struct EventCache {
    EventCache() = default;
    EventCache(const EventCache& other) {
      std::lock_guard lock(other.mutex);
      clips = other.clips;
    }
    EventCache& operator=(const EventCache& other) {
      if (this != &other) {
        std::scoped_lock lock(mutex, other.mutex);
        clips = other.clips;
      }
      return *this;
    }
    mutable std::mutex mutex;
    std::vector<ClipEvents> clips;
  };
  mutable EventCache events_;
  void updateEvents(std::size_t clip) const;  // rig_events.cpp; events_.mutex held
};

}  // namespace marionette
