// Typed parameters of a behavior request, one small struct per controller.
// The middleware takes values (a target as a point or a character, an influence
// as an enum, angles in radians); it knows nothing of how BML spells them. The
// BML realizer reads BML attributes into these (bml/behavior_mapping.hpp); an
// engine fills them directly:
//
//   BehaviorRequest look;
//   look.kind = BehaviorKind::Gaze;
//   look.parameters = GazeParameters{.target = BehaviorTarget::at({0.0f, 1.6f, 2.0f}),
//                                    .influence = GazeInfluence::Head};
//
// Values outside a parameter's range are replaced by its default, with a note in
// BehaviorResult::message (the request is still realized); a value that makes
// the request impossible (no target, a point that is not finite) fails it.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "marionette/speech/audio_clip.hpp"
#include "marionette/speech/speech_backend.hpp"

namespace marionette {

// What a gaze or a pointing aims at, or where a locomotion goes: a world point
// (metres) or a character of the scene, optionally one of its joints (without a
// joint, the behavior picks one: the head for a gaze, the chest for a pointing).
struct BehaviorTarget {
  std::optional<glm::vec3> point{};  // set: the world point
  std::string character{};           // else this character
  std::string joint{};               // and this joint of it ("" = the behavior's choice)

  [[nodiscard]] static BehaviorTarget at(const glm::vec3& world) { return {world, {}, {}}; }
  [[nodiscard]] static BehaviorTarget of(std::string name, std::string jointName = {}) {
    return {std::nullopt, std::move(name), std::move(jointName)};
  }
  [[nodiscard]] bool empty() const noexcept { return !point && character.empty(); }
};

// Head movements (kind Head; the catalogue with angles and shapes: head_motion.hpp).
// Orient is a held direction (Greta's head signals: UP, DOWN_ASIDE_RIGHT, TILT_LEFT, ...):
// the head turns by `orientDegrees` by ready, holds it until relax, returns by end.
enum class HeadLexeme : std::uint8_t { Nod, Shake, Tilt, Toss, Wiggle, Waggle, Orient };
struct HeadParameters {
  static constexpr float kMinAmount = -1.0f, kMaxAmount = 1.0f, kDefaultAmount = 0.5f;
  HeadLexeme lexeme = HeadLexeme::Nod;
  float amount = kDefaultAmount;  // of the lexeme's peak angle; negative reverses it
  // Orient: degrees at amount 1 about the character's +X (down), +Y (to its left), +Z (roll to its right).
  glm::vec3 orientDegrees{0.0f};
};

// Face expressions (kinds FaceLexeme, FaceFacs, Face, FaceShift): a name the
// character's profile maps to morphs ("SMILE", or "AU12" for a FACS unit).
struct FaceParameters {
  static constexpr float kMinAmount = 0.0f, kMaxAmount = 1.0f, kDefaultAmount = 1.0f;
  std::string expression{};  // matched against the profile's face table as given (upper case there)
  float amount = kDefaultAmount;
};

// How much of the body turns to gaze (kinds Gaze, GazeShift; headDirectionShift uses Neck).
enum class GazeInfluence : std::uint8_t { Eyes, Head, Neck, Shoulder, Waist, Whole };
struct GazeParameters {
  static constexpr float kMaxOffsetRadians = 3.14159265f;
  BehaviorTarget target{};
  GazeInfluence influence = GazeInfluence::Neck;
  // Look this far beside the target (radians; yaw > 0 to the character's left,
  // pitch > 0 down), each within +-kMaxOffsetRadians.
  float offsetYaw = 0.0f, offsetPitch = 0.0f;
};

// Which arm points (kind Pointing).
enum class PointingArms : std::uint8_t {
  Nearest,  // the arm on the target's side, chosen at the first frame and kept
  Left, Right, Both,
};
struct PointingParameters {
  BehaviorTarget target{};  // may stay empty when the request plays a clip: the clip alone then
  PointingArms arms = PointingArms::Nearest;
};

// How a locomotion goes (kind Locomotion).
enum class LocomotionManner : std::uint8_t {
  Walk, Run,
  Stroll,  // half the walk speed
  Sprint,  // 1.3 x the run speed
};
struct LocomotionParameters {
  static constexpr std::size_t kMaxWaypoints = 1000;
  static constexpr float kMinSpeed = 0.05f, kMaxSpeed = 12.0f;  // m/s: faster than any human gait
  static constexpr float kMaxProximity = 100.0f;                 // m
  // Where to go: waypoints on the ground (world x, z; the last is the
  // destination; at most kMaxWaypoints), or else a character (its place is
  // followed every frame; point and joint are not used here).
  std::vector<glm::vec2> waypoints{};
  std::string targetCharacter{};
  LocomotionManner manner = LocomotionManner::Walk;
  std::optional<float> speed{};          // m/s, overrides the manner's speed
  std::optional<float> facing{};         // world heading on arrival, radians (0 faces +Z, pi/2 faces +X)
  std::optional<float> proximity{};      // stop this far from the destination, m (default: 0 for a point,
                                         // LocomotionSettings::characterProximity for a character)
};

// Speech (kind Speech): text, marks at character offsets, voice and rate
// (speech::SpeechRequest). A mark past the end of the text is dropped with a note;
// wordsPerMinute outside [1, 10000] is the voice's default, with a note.
using SpeechParameters = speech::SpeechRequest;

// A gesture without a clip (kind Gesture; behavior/procedural_gesture.hpp): its lexeme,
// which hands (Nearest: the lexeme's own), and for DEICTIC / POINT a target to point at.
struct GestureParameters {
  std::string lexeme{};  // matched case-insensitively
  PointingArms hands = PointingArms::Nearest;
  BehaviorTarget target{};
};

// Rapid eye movements (kind Saccade; behavior/saccade.hpp): a model that runs until another
// saccade request finishes it (Talk, Listen, Think: Lee, Badler and Badler's "Eyes Alive"
// statistics), or one saccade (None: `magnitudeDegrees` toward `directionDegrees`, 0 = the
// character's right, 90 = up), or `finish`: stop the running models.
enum class SaccadeMode : std::uint8_t { None, Talk, Listen, Think };
struct SaccadeParameters {
  static constexpr float kMaxMagnitudeDegrees = 30.0f;
  SaccadeMode mode = SaccadeMode::None;
  bool finish = false;
  float directionDegrees = 0.0f;
  float magnitudeDegrees = 0.0f;
};

// Idle life (kinds BlinkEmitter, BreathingEmitter; behavior/idle_life.hpp): emitters that run
// until a later request of their kind replaces them; `stop` ends the running one (blended out).
// Blink onsets are a renewal process: the interval between two onsets is log-normal with mean
// `meanIntervalSeconds` and coefficient of variation `variation` (docs/controllers.md, "Idle
// life", says where the defaults come from). `seed` 0: from the character and the request id.
struct BlinkParameters {
  static constexpr float kDefaultMeanInterval = 3.5f;  // s: 17 blinks a minute at rest
  static constexpr float kDefaultVariation = 0.6f;
  static constexpr float kMinMeanInterval = 0.5f, kMaxMeanInterval = 600.0f;
  static constexpr float kMaxVariation = 1.5f;
  float meanIntervalSeconds = kDefaultMeanInterval;
  float variation = kDefaultVariation;
  float amount = 1.0f;  // of the blink morphs' full closure, in [0, 1]
  bool stop = false;
  std::uint64_t seed = 0;
};
// Breathing: the chest pitches back and the shoulders rise by `amplitudeDegrees` at the top of
// each breath, `breathsPerMinute` times a minute; each breath's period varies uniformly by
// +-`periodRangeSeconds` (AsapRealizer's `range`).
struct BreathingParameters {
  static constexpr float kDefaultRate = 15.0f;  // breaths a minute: an adult at rest
  static constexpr float kMinRate = 2.0f, kMaxRate = 60.0f;
  static constexpr float kDefaultAmplitudeDegrees = 1.5f, kMaxAmplitudeDegrees = 8.0f;
  float breathsPerMinute = kDefaultRate;
  float periodRangeSeconds = 0.0f;
  float amplitudeDegrees = kDefaultAmplitudeDegrees;
  bool stop = false;
  std::uint64_t seed = 0;
};
// A sound (kind Audio): the decoded clip and the file it came from, handed to the engine
// when the request is added (SceneListener::onAudio). A null or empty clip is an error.
struct AudioParameters {
  std::shared_ptr<const speech::AudioClip> clip{};
  std::string file{};
};
// A reach (kind Reach; behavior/reach.hpp): the hand goes to the target by ready, holds it
// until relax and is back by end. The action is SmartBody's sbm:action; none grasps or
// carries the object here (the hand reaches it, that is all).
enum class ReachAction : std::uint8_t { Touch, PickUp, PutDown };
struct ReachParameters {
  BehaviorTarget target{};
  PointingArms arm = PointingArms::Nearest;  // Nearest: the arm on the target's side; Both is not a reach
  ReachAction action = ReachAction::Touch;
};

// The parameters of one request: none (postures, clips and waits need only their clip
// and times), or the struct of its kind's controller.
using BehaviorParameters = std::variant<std::monostate, HeadParameters, FaceParameters, GazeParameters,
                                        PointingParameters, LocomotionParameters, SpeechParameters, GestureParameters,
                                        SaccadeParameters, BlinkParameters, BreathingParameters, AudioParameters,
                                        ReachParameters>;

}  // namespace marionette
