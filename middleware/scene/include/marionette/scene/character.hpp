// A character: a rig, a world placement, clip layers, and the TransformBuffer
// it writes every frame. Created and owned by a Scene.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/behavior_timeline.hpp"
#include "marionette/behavior/locomotion.hpp"
#include "marionette/scene/listener.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/scene/transform_buffer.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

class Scene;

struct PlayOptions {
  float weight = 1.0f;               // target weight (blend is relative; see blendPoses)
  float speed = 1.0f;                // playback rate; 0 holds, negative plays backwards
  WrapMode wrap = WrapMode::Loop;    // Clamp holds the last frame
  double startTime = 0.0;            // clip-local time to start at
  float fadeIn = 0.0f;               // seconds to reach `weight` (0: at once)
  bool additive = false;             // play as a delta against the clip's first frame
  bool rootMotion = false;           // move the character by the clip's root motion
  std::vector<float> jointMask{};    // optional per-joint weights in [0,1]; empty = whole body
};

// Per-frame working memory that characters share: the scene owns one, sized to
// its largest skeleton, so blending N layers on 1000 characters touches one
// scratch pose (hot in cache) instead of N poses per character.
struct FrameScratch {
  std::vector<Transform> pose;
  BlendAccumulator accumulator;
  void reserve(std::size_t joints);  // grows only
};

// Where a locomotion request stands (Character::locomotionStatus).
struct LocomotionStatus {
  enum class State : std::uint8_t { Unknown, Pending, Moving, Done, Superseded } state = State::Unknown;
  double doneTime = -1.0;  // character clock at arrival (and final facing), for State::Done
};

// What became of a behavior request (Character::addBehavior).
struct BehaviorResult {
  bool added = false;     // on the timeline: it has a channel, a weight envelope, an owner
  bool realized = false;  // some controller moves the body for it
  std::string message;    // why not added, or why not realized; empty when both hold
};

// The behavior controllers, in the order a frame runs them (DESIGN.md): clip behaviors
// (postures) over the layers, locomotion, upper-body clips (gestures), gaze, head movements
// added on top of it, saccades, procedural gestures and pointing (after the gaze has turned
// the torso, so the arms move from where it ends up), face expressions, speech. One list:
// each frame's passes and the stats below are indexed by it.
enum class Controller : std::uint8_t {
  ClipBehaviors, Locomotion, UpperBodyClips, Gaze, Head, Saccade, Gesture, Pointing, Face, Speech
};
inline constexpr std::size_t kControllerCount = static_cast<std::size_t>(Controller::Speech) + 1;
[[nodiscard]] std::string_view controllerName(Controller controller) noexcept;  // "clip behaviors", ...

struct CharacterStats {
  double lastUpdateMicros = 0.0;  // wall time of the last update (when stats are on)
  int activeLayers = 0;           // clip layers that exist now
  bool sampledDirect = false;     // the last frame took the one-clip fast path
  // Per controller: whether it has run at least once (controllers exist only while a
  // behavior uses them) and its wall time in the last frame (while the scene's stats are on).
  std::array<bool, kControllerCount> controllerUsed{};
  std::array<double, kControllerCount> controllerMicros{};
  [[nodiscard]] bool used(Controller c) const noexcept { return controllerUsed[static_cast<std::size_t>(c)]; }
  [[nodiscard]] double micros(Controller c) const noexcept { return controllerMicros[static_cast<std::size_t>(c)]; }
};

class Character {
 public:
  static constexpr int kMaxLayers = 8;

  Character(std::string name, std::shared_ptr<const Rig> rig);

  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  [[nodiscard]] const Rig& rig() const noexcept { return *rig_; }
  [[nodiscard]] const Skeleton& skeleton() const noexcept { return rig_->skeleton(); }
  [[nodiscard]] const TransformBuffer& transformBuffer() const noexcept { return buffer_; }
  [[nodiscard]] TransformBuffer& transformBuffer() noexcept { return buffer_; }
  [[nodiscard]] std::span<const Transform> localPose() const noexcept { return pose_; }
  [[nodiscard]] const CharacterStats& stats() const noexcept { return stats_; }

  // World placement: position in metres, heading in radians about +Y (0 faces +Z).
  void setPosition(const glm::vec3& p) noexcept;
  void setHeading(float radians) noexcept;
  [[nodiscard]] glm::vec3 position() const noexcept { return position_; }
  [[nodiscard]] float heading() const noexcept { return heading_; }
  [[nodiscard]] glm::mat4 worldMatrix() const noexcept;

  // Starts a clip on a layer (0..kMaxLayers-1), replacing what played there.
  // Returns false (and logs through the scene) for a bad layer or a null clip.
  bool play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options = {});
  bool play(int layer, std::string_view clipName, const PlayOptions& options = {});
  void stop(int layer, float fadeOut = 0.0f);
  [[nodiscard]] int layerCount() const noexcept;  // layers in use
  [[nodiscard]] double layerTime(int layer) const noexcept;

  // Timed behavior requests (see behavior_request.hpp); the C++ API an engine
  // uses without BML, and what the BML realizer calls. A request naming a clip
  // is played by the clip controller: blended over the clip layers on the joints
  // the clip animates, time-warped onto [start, end] (or looping), weighted by
  // the request's envelope. Head requests (NOD, SHAKE, TILT) and face requests
  // (lexemes, FACS units, through the rig's profile) are procedural. Gaze,
  // pointing and locomotion have their controllers; speech is said by the scene's
  // speech service (time it with prepareSpeech; a line not prepared before is said
  // inline, see prepareSpeechInBackground). BehaviorResult::realized says
  // whether a controller moves the body; `message` says why not, or notes a
  // replaced bad parameter.
  // Command time: may allocate.
  BehaviorResult addBehavior(BehaviorRequest request);
  // Ends requests now, blending them out over `blendOut` seconds. A speech cut off
  // before its end is reported to the listeners (onSpeechStopped: stop its audio).
  bool cancelBehavior(std::string_view id, double blendOut);
  std::size_t cancelBehaviors(std::string_view idPrefix, double blendOut);
  [[nodiscard]] const BehaviorTimeline& behaviors() const noexcept { return behaviors_; }
  // The character's clock: the scene's time for a character in a scene.
  [[nodiscard]] double time() const noexcept { return clock_; }
  // Locomotion: speed presets, turn speed, acceleration (before or after requests).
  void setLocomotionSettings(const LocomotionSettings& settings) noexcept;
  [[nodiscard]] const LocomotionSettings& locomotionSettings() const noexcept { return locomotionSettings_; }
  // The locomotion controller; null until the character got a locomotion request.
  [[nodiscard]] const LocomotionController* locomotion() const noexcept { return locomotion_.get(); }
  [[nodiscard]] LocomotionStatus locomotionStatus(std::string_view id) const noexcept;
  // Seconds a locomotion request with these parameters would take from where the
  // character stands now (for scheduling its sync points); nullopt when it cannot
  // be performed. Command time.
  [[nodiscard]] std::optional<double> estimateLocomotion(const BehaviorRequest& request) const;
  // The character's gait set (walk and run clips analysed), made on first use.
  // Command time only: not to be called from update() (threads would race on it).
  [[nodiscard]] const LocomotionSet& locomotionSet() const;
  // The spoken line a speech request would play (said now by the scene's speech
  // service, or taken from its cache): the BML realizer schedules word marks with
  // it. Null when it cannot be said (`error` says why). Command time.
  [[nodiscard]] std::shared_ptr<const speech::SpokenLine> prepareSpeech(const BehaviorRequest& request,
                                                                        std::string& error) const;
  // The same, said on the speech service's worker thread: returns at once (null outside
  // a scene). Once it is ready, prepareSpeech and a speech request added with
  // addBehavior take the line from the cache without waiting. Command time.
  [[nodiscard]] std::shared_ptr<const speech::SpeechService::Preparation> prepareSpeechInBackground(
      const BehaviorRequest& request) const;
  // Gaze tracking and limits (time constant, speed limits, per-joint limits).
  void setGazeSettings(const GazeSettings& settings) noexcept { gazeSettings_ = settings; }
  [[nodiscard]] const GazeSettings& gazeSettings() const noexcept { return gazeSettings_; }
  void setPointingSettings(const PointingSettings& settings) noexcept { pointingSettings_ = settings; }
  [[nodiscard]] const PointingSettings& pointingSettings() const noexcept { return pointingSettings_; }

  // Advances the layers by dt seconds and writes the transform buffer. Per-frame:
  // no allocation, no exceptions. dt must be finite and >= 0 (Scene checks).
  void update(double dt) noexcept;

 private:
  friend class Scene;
  struct Layer {
    std::shared_ptr<const AnimationClip> clip;
    PlayOptions options;
    double time = 0.0;        // clip-local time, unwrapped (loops keep counting)
    float clipTime = 0.0f;    // `time` wrapped or clamped into the clip, once per frame
    float weight = 0.0f;      // current weight (fades)
    float fadeRate = 0.0f;    // weight per second, signed
    bool stopping = false;
    SamplingCursor cursor, rootCursor;
    std::vector<Transform> reference;  // first frame, for additive layers
  };
  void notify(ChangeKind kind, std::string_view what) const;
  // Reads what this character's behaviors need from other characters (targets'
  // placement and joints, as the last frame left them). Scene::update calls it for
  // every character before updating any, so update() itself reads no other
  // character: the result does not depend on update order or threads.
  void resolveExternalTargets() noexcept;
  void sampleLayer(Layer& layer, std::span<Transform> out) noexcept;
  void blendLayers() noexcept;
  // An entry a controller runs on this frame, and its weight now (the frame's one walk).
  struct ActiveEntry {
    std::uint32_t index = 0;  // into behaviors_.entries() as the walk found them
    float weight = 0.0f;
    std::uint64_t order = 0;  // the entry's timeline order: finds it again if a listener moved it
  };
  [[nodiscard]] std::vector<ActiveEntry>& pass(Controller c) noexcept { return passes_[static_cast<std::size_t>(c)]; }
  void applyBehaviors(float dt) noexcept;
  bool applyBehaviorClips(std::span<const ActiveEntry> pass) noexcept;  // true if a clip behavior contributed
  bool applyLocomotion(float dt) noexcept;
  [[nodiscard]] std::vector<float> upperBodyMask() const;
  [[nodiscard]] TargetJointFinder targetJointFinder(bool chest) const;
  // Command-time binding of a request to its controller (addBehavior's table), each:
  // empty when realized, else why not; `warning` notes a parameter that was replaced.
  void bindClipEntry(BehaviorTimeline::Entry& entry, std::shared_ptr<const AnimationClip> clip);
  [[nodiscard]] std::string bindLocomotionEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindGazeEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindHeadDirectionEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindHeadEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindFaceEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindPointingEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindGestureEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindSaccadeEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindSpeechEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindWaitEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  void ensureScratch();
  void reserveBehaviorPasses();
  [[nodiscard]] std::vector<std::string> speechStoppedBy(std::string_view id, bool prefix) const;
  void notifySpeechStopped(const std::vector<std::string>& ids) const;
  bool applySpeechEntries() noexcept;
  [[nodiscard]] std::string bindLocomotion(const BehaviorRequest& request, std::shared_ptr<LocomotionPlan>& plan,
                                           std::string& warning) const;
  void applyRootMotion(const Layer& layer, double t0, double t1, float weight, glm::vec3& move,
                       float& turn) const noexcept;

  std::string name_;
  std::shared_ptr<const Rig> rig_;
  Scene* scene_ = nullptr;
  glm::vec3 position_{0.0f};
  float heading_ = 0.0f;
  std::array<Layer, kMaxLayers> layers_;
  std::vector<Transform> pose_;
  BehaviorTimeline behaviors_;
  std::array<std::vector<ActiveEntry>, kControllerCount> passes_;  // reserved at addBehavior, filled each frame
  GazeSettings gazeSettings_;
  PointingSettings pointingSettings_;
  LocomotionSettings locomotionSettings_;
  mutable std::shared_ptr<const LocomotionSet> locomotionSet_;  // made on first use (command time)
  std::unique_ptr<LocomotionController> locomotion_;
  std::uint64_t locomotionOrder_ = 0;  // timeline order of the request it follows; 0 = none yet
  std::vector<float> morphScratch_;  // one per morph target, for weighted clip morphs
  double clock_ = 0.0;
  FrameScratch* scratch_ = nullptr;             // the scene's, or ownScratch_ when standalone
  std::unique_ptr<FrameScratch> ownScratch_;
  TransformBuffer buffer_;
  CharacterStats stats_;
};

}  // namespace marionette
