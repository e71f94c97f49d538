// Character's private state: the clip layers, the behavior timeline and its controllers,
// each frame's passes, and the buffer the frame writes. Character forwards to it; the
// Scene reaches it to attach a character and to run its frame. The member functions are
// defined in character.cpp (layers, placement, the frame) and character_behaviors.cpp
// (binding requests to controllers, running the controllers).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blend_layer.hpp"
#include "frame_scratch.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/scene/character.hpp"
#include "marionette/scene/listener.hpp"

namespace marionette {

// Through the runtime allocator, with the buffers below marked so (core/allocator.hpp).
struct Character::State : RuntimeAllocated {
  State(Character& self, std::string name, std::shared_ptr<const Rig> rig);

  struct Layer : RuntimeAllocated {  // through the runtime allocator, as the state
    std::shared_ptr<const AnimationClip> clip;
    PlayOptions options;
    double time = 0.0;        // clip-local time, unwrapped (loops keep counting)
    float clipTime = 0.0f;    // `time` wrapped or clamped into the clip, once per frame
    float weight = 0.0f;      // current weight (fades)
    float fadeRate = 0.0f;    // weight per second, signed
    bool stopping = false;
    SamplingCursor cursor, rootCursor;
    // The clip's events (the rig's, or its markers alone), and this frame's playhead move
    // (clip time, unwrapped, before clamping) that sendAnimationEvents crosses.
    std::shared_ptr<const AnimationEventTrack> events;
    double eventFrom = 0.0, eventTo = 0.0;
    RuntimeVector<Transform> reference;  // first frame, for additive layers (runtime allocator)
    BlendSpaceLayer blend;  // a blend space instead of a clip (then `clip` is null; time = shared phase)
  };
  // The clip layers, each made the first time something plays on it (command time): a
  // character that plays on one layer holds one Layer, not eight (a Layer is a few hundred
  // bytes; most characters use one or two layers, and 100 characters of one asset should
  // cost little beyond their poses). Layers never move once made, so a listener that plays
  // on another layer during the frame leaves every Layer& valid. Iteration visits the made
  // layers in index order.
  class LayerSlots {
   public:
    [[nodiscard]] Layer* find(int index) const noexcept {
      return index >= 0 && index < kMaxLayers ? slots_[static_cast<std::size_t>(index)].get() : nullptr;
    }
    Layer& ensure(int index) {  // 0 <= index < kMaxLayers, checked by the caller
      auto& slot = slots_[static_cast<std::size_t>(index)];
      if (!slot) slot = std::make_unique<Layer>();
      return *slot;
    }
    template <class Slot, class Value>
    class Iterator {
     public:
      Iterator(Slot* at, Slot* end) : at_(at), end_(end) { skip(); }
      Value& operator*() const noexcept { return **at_; }
      Iterator& operator++() noexcept {
        ++at_;
        skip();
        return *this;
      }
      bool operator!=(const Iterator& o) const noexcept { return at_ != o.at_; }

     private:
      void skip() noexcept {
        while (at_ != end_ && !*at_) ++at_;
      }
      Slot* at_;
      Slot* end_;
    };
    using Slot = std::unique_ptr<Layer>;
    auto begin() noexcept { return Iterator<Slot, Layer>(slots_.data(), slots_.data() + kMaxLayers); }
    auto end() noexcept { return Iterator<Slot, Layer>(slots_.data() + kMaxLayers, slots_.data() + kMaxLayers); }
    auto begin() const noexcept {
      return Iterator<const Slot, const Layer>(slots_.data(), slots_.data() + kMaxLayers);
    }
    auto end() const noexcept {
      return Iterator<const Slot, const Layer>(slots_.data() + kMaxLayers, slots_.data() + kMaxLayers);
    }

   private:
    std::array<Slot, kMaxLayers> slots_;
  };
  // An entry a controller runs on this frame, and its weight now (the frame's one walk).
  struct ActiveEntry {
    std::uint32_t index = 0;  // into behaviors_.entries() as the walk found them
    float weight = 0.0f;
    std::uint64_t order = 0;  // the entry's timeline order: finds it again if a listener moved it
  };

  [[nodiscard]] const Skeleton& skeleton() const noexcept { return rig_->skeleton(); }

  // Placement and layers (character.cpp).
  void setPosition(const glm::vec3& p) noexcept;
  void setHeading(float radians) noexcept;
  [[nodiscard]] glm::mat4 worldMatrix() const noexcept;
  // The options, weight and fade of a layer something starts on (a clip or a blend space).
  static void startLayer(Layer& l, const PlayOptions& options, std::size_t joints);
  // Moves a layer's weight along its fade; true when a stopping layer reached 0 (the caller ends it).
  static bool fadeLayer(Layer& l, double dt) noexcept;
  bool play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options);
  bool play(int layer, std::string_view clipName, const PlayOptions& options);
  void stop(int layer, float fadeOut);
  [[nodiscard]] int layerCount() const noexcept;
  [[nodiscard]] double layerTime(int layer) const noexcept;
  void update(double dt) noexcept;
  void notify(ChangeKind kind, std::string_view what) const;
  void sampleLayer(Layer& layer, std::span<Transform> out) noexcept;
  void blendLayers() noexcept;
  void applyRootMotion(const Layer& layer, double t0, double t1, float weight, glm::vec3& move,
                       float& turn) const noexcept;
  // Blend-space layers (character_blend.cpp).
  bool playBlend(int layer, std::shared_ptr<const BlendSpace> space, const PlayOptions& options, float x, float y);
  bool playBlend(int layer, std::string_view name, const PlayOptions& options, float x, float y);
  bool setBlendParameter(int layer, float x, float y) noexcept;
  bool advanceBlendLayer(Layer& layer, double dt, glm::vec3& move, float& turn) noexcept;  // false: it stopped
  void accumulateBlendLayer(Layer& layer, std::span<Transform> scratch) noexcept;
  // Animation events (character_events.cpp): found at play, sent at the end of update().
  void bindEvents(Layer& layer);
  void sendAnimationEvents(double dt) noexcept;

  // Behaviors (character_behaviors.cpp).
  BehaviorResult addBehavior(BehaviorRequest request);
  // The profile's idleLife (blinking, breathing) as persistent requests from now (Scene::addCharacter).
  void startIdleLife();
  bool cancelBehavior(std::string_view id, double blendOut);
  std::size_t cancelBehaviors(std::string_view idPrefix, double blendOut);
  void setLocomotionSettings(const LocomotionSettings& settings) noexcept;
  [[nodiscard]] LocomotionStatus locomotionStatus(std::string_view id) const noexcept;
  [[nodiscard]] std::optional<double> estimateLocomotion(const BehaviorRequest& request) const;
  [[nodiscard]] const LocomotionSet& locomotionSet() const;
  [[nodiscard]] std::shared_ptr<const speech::SpokenLine> prepareSpeech(const BehaviorRequest& request,
                                                                        Diagnostics& diagnostics) const;
  [[nodiscard]] std::shared_ptr<const speech::SpeechService::Preparation> prepareSpeechInBackground(
      const BehaviorRequest& request) const;
  // Reads what this character's behaviors need from other characters (targets'
  // placement and joints, as the last frame left them). Scene::update calls it for
  // every character before updating any, so update() itself reads no other
  // character: the result does not depend on update order or threads.
  void resolveExternalTargets() noexcept;
  [[nodiscard]] RuntimeVector<ActiveEntry>& pass(Controller c) noexcept { return passes_[static_cast<std::size_t>(c)]; }
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
  [[nodiscard]] std::string bindBlinkEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindBreathingEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindReachEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  void resolveTarget(SpatialTarget& target) const noexcept;  // a character's or object's place now
  [[nodiscard]] std::string bindSpeechEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  [[nodiscard]] std::string bindWaitEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  void ensureScratch();
  void reserveBehaviorPasses();
  [[nodiscard]] std::string bindAudioEntry(BehaviorTimeline::Entry& entry, std::string& warning);
  // Speech and sounds a cancel stops (marking each sound told), and telling the listeners.
  struct StoppedSound {
    std::string id;
    bool audio = false;  // onAudioStopped, else onSpeechStopped
  };
  [[nodiscard]] std::vector<StoppedSound> soundsStoppedBy(std::string_view id, bool prefix);
  void notifySoundsStopped(const std::vector<StoppedSound>& sounds) const;
  bool applySpeechEntries() noexcept;
  [[nodiscard]] std::string bindLocomotion(const BehaviorRequest& request, std::shared_ptr<LocomotionPlan>& plan,
                                           std::string& warning) const;

  Character& self_;  // what listeners are told about
  std::string name_;
  std::shared_ptr<const Rig> rig_;
  Scene* scene_ = nullptr;
  glm::vec3 position_{0.0f};
  float heading_ = 0.0f;
  LayerSlots layers_;
  RuntimeVector<Transform> pose_;  // runtime allocator, as the other per-character buffers
  BehaviorTimeline behaviors_;
  std::array<RuntimeVector<ActiveEntry>, kControllerCount> passes_;  // reserved at addBehavior, filled each frame
  GazeSettings gazeSettings_;
  PointingSettings pointingSettings_;
  ReachSettings reachSettings_;
  LocomotionSettings locomotionSettings_;
  mutable std::shared_ptr<const LocomotionSet> locomotionSet_;  // made on first use (command time)
  std::unique_ptr<LocomotionController> locomotion_;
  std::uint64_t locomotionOrder_ = 0;  // timeline order of the request it follows; 0 = none yet
  RuntimeVector<float> morphScratch_;  // one per morph target, for weighted clip morphs
  double clock_ = 0.0;
  FrameScratch* scratch_ = nullptr;             // the scene's, or ownScratch_ when standalone
  std::unique_ptr<FrameScratch> ownScratch_;
  TransformBuffer buffer_;
  CharacterStats stats_;
  PlacementDelta lastMotion_;  // of the last update()
};

}  // namespace marionette
