// A character: a rig, a world placement, clip layers, timed behaviors, and the
// TransformBuffer it writes every frame. Created and owned by a Scene (or standalone,
// for a tool). A facade: the layers, the controllers and their per-frame passes live
// in the private state (scene/src/character_state.hpp).
#pragma once
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "marionette/behavior/behavior_timeline.hpp"
#include "marionette/behavior/gaze.hpp"
#include "marionette/behavior/locomotion.hpp"
#include "marionette/behavior/pointing.hpp"
#include "marionette/core/allocator.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/scene/character_status.hpp"
#include "marionette/scene/play_options.hpp"
#include "marionette/scene/transform_buffer.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

class Scene;

// Made with new (as a Scene does), the object comes from the runtime allocator (core/allocator.hpp).
class Character : public RuntimeAllocated {
 public:
  static constexpr int kMaxLayers = 8;

  // At rest, at the origin, facing +Z; nothing plays. `rig` must not be null.
  Character(std::string name, std::shared_ptr<const Rig> rig);
  ~Character();
  Character(const Character&) = delete;
  Character& operator=(const Character&) = delete;

  [[nodiscard]] const std::string& name() const noexcept;
  [[nodiscard]] const Rig& rig() const noexcept;
  [[nodiscard]] const Skeleton& skeleton() const noexcept;
  // What the last update() wrote (model matrices, skinning palette, morph weights, world).
  [[nodiscard]] const TransformBuffer& transformBuffer() const noexcept;
  [[nodiscard]] TransformBuffer& transformBuffer() noexcept;
  // The local joint transforms the last update() blended, before local-to-model.
  [[nodiscard]] std::span<const Transform> localPose() const noexcept;
  [[nodiscard]] const CharacterStats& stats() const noexcept;

  // World placement: position in metres, heading in radians about +Y (0 faces +Z).
  // A non-finite value is refused (logged through the scene) and the placement kept.
  void setPosition(const glm::vec3& p) noexcept;
  void setHeading(float radians) noexcept;
  [[nodiscard]] glm::vec3 position() const noexcept;
  [[nodiscard]] float heading() const noexcept;
  [[nodiscard]] glm::mat4 worldMatrix() const noexcept;
  // What the last update() moved the character by (for an engine that moves its own object).
  [[nodiscard]] PlacementDelta lastMotion() const noexcept;

  // Starts a clip on a layer (0..kMaxLayers-1), replacing what played there.
  // Returns false (and logs through the scene) for a bad layer or a null or unknown clip.
  // Command time: may allocate.
  bool play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options = {});
  bool play(int layer, std::string_view clipName, const PlayOptions& options = {});
  // Stops a layer at once, or fading out over `fadeOut` seconds; a free layer is ignored.
  void stop(int layer, float fadeOut = 0.0f);
  [[nodiscard]] int layerCount() const noexcept;            // layers in use
  [[nodiscard]] double layerTime(int layer) const noexcept;  // clip-local, unwrapped; 0 for a bad layer

  // Plays a blend space (animation/blend_space.hpp; made by the rig from its profile's
  // "blendSpaces", or from code) on a layer, replacing what played there, at the parameter
  // point (x, y) (y unused in 1D; clamped into the space). The options are a clip's, except:
  // startTime is the start phase (cycles), speed scales the phase's rate, wrap Clamp holds the
  // cycle's end, additive is refused. layerTime() is then the shared phase in cycles. Root
  // motion (options.rootMotion) is the clips' root motion at their warped times, weighted.
  // Returns false (and logs through the scene) for a bad layer, a null or unknown space.
  // Command time: allocates (what the frame needs, per clip of the space).
  bool playBlend(int layer, std::shared_ptr<const BlendSpace> space, const PlayOptions& options = {}, float x = 0.0f,
                 float y = 0.0f);
  bool playBlend(int layer, std::string_view blendSpaceName, const PlayOptions& options = {}, float x = 0.0f,
                 float y = 0.0f);
  // Moves the parameter point of the blend space on `layer`; the weights change from the
  // next frame, at once (smooth the parameter in the caller for gradual changes). False when
  // the layer plays no blend space or x or y is not finite. No allocation; any thread that
  // owns the character between updates.
  bool setBlendParameter(int layer, float x, float y = 0.0f) noexcept;
  // The blend space on a layer and its sample weights now (null / empty when it plays none).
  [[nodiscard]] const BlendSpace* layerBlendSpace(int layer) const noexcept;
  [[nodiscard]] std::span<const float> layerBlendWeights(int layer) const noexcept;

  // Timed behavior requests (behavior_request.hpp): the C++ API an engine uses without
  // BML, and what the BML realizer calls. A request naming a clip is played by the clip
  // controller, blended over the layers on the joints the clip animates, time-warped onto
  // [start, end] and weighted by the request's envelope. Head and face requests are
  // procedural (face through the rig's profile); gaze, pointing, gestures, saccades and
  // locomotion have their controllers; speech is said by the scene's speech service; a
  // sound (kind Audio) is handed to the listeners (onAudio) as it is added.
  // BehaviorResult::realized says whether a controller moves the body; `message` says why
  // not, or notes a replaced bad parameter. Command time: may allocate.
  BehaviorResult addBehavior(BehaviorRequest request);
  // Ends requests now, blending them out over `blendOut` seconds. A speech cut off before
  // its end is reported to the listeners (onSpeechStopped, onAudioStopped: stop its audio).
  bool cancelBehavior(std::string_view id, double blendOut);
  std::size_t cancelBehaviors(std::string_view idPrefix, double blendOut);
  [[nodiscard]] const BehaviorTimeline& behaviors() const noexcept;
  // The character's clock: the scene's time for a character in a scene.
  [[nodiscard]] double time() const noexcept;

  // Locomotion: speed presets, turn speed, acceleration (before or after requests).
  void setLocomotionSettings(const LocomotionSettings& settings) noexcept;
  [[nodiscard]] const LocomotionSettings& locomotionSettings() const noexcept;
  // The locomotion controller; null until the character got a locomotion request.
  [[nodiscard]] const LocomotionController* locomotion() const noexcept;
  [[nodiscard]] LocomotionStatus locomotionStatus(std::string_view id) const noexcept;
  // Seconds a locomotion request would take from where the character stands now (for
  // scheduling its sync points); nullopt when it cannot be performed. Command time.
  [[nodiscard]] std::optional<double> estimateLocomotion(const BehaviorRequest& request) const;
  // The character's gait set (walk and run clips analysed), made on first use.
  // Command time only: not from update() (threads would race on it).
  [[nodiscard]] const LocomotionSet& locomotionSet() const;

  // The spoken line a speech request would play (said now by the scene's speech service,
  // or taken from its cache): the BML realizer schedules word marks with it. Null when it
  // cannot be said, with a diagnostic naming the request. Command time.
  [[nodiscard]] std::shared_ptr<const speech::SpokenLine> prepareSpeech(const BehaviorRequest& request,
                                                                        Diagnostics& diagnostics) const;
  // The same, said on the speech service's worker thread: returns at once (null outside a
  // scene). Once ready, prepareSpeech and addBehavior take the line from the cache.
  [[nodiscard]] std::shared_ptr<const speech::SpeechService::Preparation> prepareSpeechInBackground(
      const BehaviorRequest& request) const;

  // Gaze tracking and limits (time constant, speed limits, per-joint limits), and pointing's.
  void setGazeSettings(const GazeSettings& settings) noexcept;
  [[nodiscard]] const GazeSettings& gazeSettings() const noexcept;
  void setPointingSettings(const PointingSettings& settings) noexcept;
  [[nodiscard]] const PointingSettings& pointingSettings() const noexcept;

  // Advances the layers and behaviors by dt seconds and writes the transform buffer.
  // Per-frame: no allocation, no exceptions. dt must be finite and >= 0 (Scene checks).
  void update(double dt) noexcept;

 private:
  friend class Scene;
  struct State;  // character_state.hpp
  std::unique_ptr<State> state_;
};

}  // namespace marionette
