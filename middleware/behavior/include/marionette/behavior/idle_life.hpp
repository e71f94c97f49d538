// Idle life (issue 45; AsapRealizer's bmlt:blinkemitter and bmlt:breathingemitter): a blink
// emitter on the character's blink morphs and a breathing emitter on its chest and shoulders,
// each running until a later request of its kind replaces or stops it. docs/controllers.md
// ("Idle life") gives the interval law, the shapes and the sources of the defaults.
//
// Blinks: onsets form a renewal process whose intervals are log-normal (mean, coefficient of
// variation), never shorter than a blink and a short refractory gap. A blink closes the lids
// in 80 ms, holds 20 ms and opens in 160 ms; on the morphs it takes the larger of itself and
// what the face already set (a face that closes the eyes is not closed twice; one that half
// closes them blinks to fully closed and back to its half). It moves no joint: the gaze and
// the saccades keep the eyes.
// Breathing: each breath rises over 42 % of its period and falls over the rest (smoothstep
// both ways: no corner at the top or bottom); the chest pitches back and the clavicles lift by
// the amplitude, the neck and the upper arms turned back so that the head and the arms keep
// their direction (the gaze, pointing and gestures, run later, see the same aims).
// Deterministic: the draws come from a seed (the character's name and the request id), and
// each frame only advances the state to the scene time. Per frame: no allocation, noexcept.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

inline constexpr double kBlinkCloseSeconds = 0.08, kBlinkHoldSeconds = 0.02, kBlinkOpenSeconds = 0.16;
inline constexpr double kBlinkSeconds = kBlinkCloseSeconds + kBlinkHoldSeconds + kBlinkOpenSeconds;
inline constexpr double kBlinkRefractorySeconds = 0.1;  // the shortest gap between two blinks
inline constexpr double kBreathInhaleShare = 0.42;      // of a breath's period
inline constexpr double kBreathingBlendSeconds = 1.0;   // a breathing emitter blends in (and over another) this long

struct BlinkState {
  std::vector<std::pair<int, float>> morphs;  // (morph target, weight at a full blink)
  std::vector<std::pair<int, float>> lids;    // (upper eyelid joint, radians closed at a full blink)
  float amount = 1.0f;
  double mu = 0.0, sigma = 0.0;  // of the log-normal interval (log seconds)
  double onset = 0.0;            // the present blink's onset, or the next one's
  std::uint64_t random = 0;      // splitmix64 state
  bool stopped = false;          // a stop request: moves nothing
};

struct BreathingState {
  int chest[2] = {-1, -1};  // the top spine joint and the one below it
  float chestShare[2] = {1.0f, 0.0f};
  int neck = -1;                                         // turned back: the head keeps its direction
  int clavicle[2] = {-1, -1}, upperArm[2] = {-1, -1};   // left, right; -1: none
  int frame = -1;                                        // the axes turn with this joint (the spine's root)
  glm::quat frameRest{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 chestAxis{-1.0f, 0.0f, 0.0f};                // model frame at rest: + pitches the chest back
  glm::vec3 liftAxis[2] = {glm::vec3(0.0f), glm::vec3(0.0f)};  // + lifts the shoulder
  float amplitude = 0.0f;                                // radians
  double period = 4.0, range = 0.0;                      // seconds
  double cycleStart = 0.0, cycleEnd = 0.0;               // the present breath
  std::uint64_t random = 0;
  bool stopped = false;
};

// A seed from text (FNV-1a): the character's name and the request id give each character its
// own blinks and breaths, the same every run.
[[nodiscard]] std::uint64_t idleLifeSeed(std::string_view text) noexcept;

// Binds a blink emitter (BlinkParameters). Empty when it can be performed, else why not: the
// lids are the profile's face table's CLOSE_EYES, BLINK, AU45 (FACS's blink) or AU43, else what
// the FACS table shows AU45 or AU43 by (rig/facs.hpp: morphs, or upper eyelid joints). Values
// out of range are replaced, with `warning` naming them. `seed`: used when the parameters give none.
[[nodiscard]] std::string bindBlink(const BehaviorRequest& request, const Rig& rig, std::uint64_t seed, BlinkState& state,
                                    std::string& warning);
// The lids' closure at `clock` in [0, 1], advancing the onsets to it.
[[nodiscard]] float advanceBlink(BlinkState& state, double clock) noexcept;
// One frame: advances and raises each blink morph to at least closure x weight (in [0, 1]), and
// closes each eyelid joint to at least that share of its blink angle, beyond the `lidsClosed`
// radians a face expression has already turned the lids by (the two never add up).
void applyBlink(BlinkState& state, double clock, float weight, std::span<float> morphWeights, const Rig& rig,
                std::span<Transform> pose, float lidsClosed) noexcept;

// Binds a breathing emitter (BreathingParameters): empty, or why not (no spine joint).
[[nodiscard]] std::string bindBreathing(const BehaviorRequest& request, const Rig& rig, std::uint64_t seed,
                                        BreathingState& state, std::string& warning);
// The breath's rise at `clock` in [0, 1], advancing the breaths to it.
[[nodiscard]] float advanceBreathing(BreathingState& state, double clock) noexcept;
// One frame: advances and adds the breath, times `weight`, to the pose.
void applyBreathing(BreathingState& state, double clock, float weight, const Skeleton& skeleton,
                    std::span<Transform> pose) noexcept;

}  // namespace marionette
