// A character's behavior timeline: the timed requests it has been given, each
// with its weight envelope over scene time, cancellation with a blend-out
// (BML REPLACE and interrupt), and which request drives a body channel when.
// Requests are added at command time (may allocate); evaluating weights and
// pruning finished requests is per-frame code (no allocation, no exceptions).
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/behavior_request.hpp"
#include "marionette/behavior/gaze.hpp"
#include "marionette/behavior/head_motion.hpp"
#include "marionette/behavior/idle_life.hpp"
#include "marionette/behavior/pointing.hpp"
#include "marionette/behavior/procedural_gesture.hpp"
#include "marionette/behavior/reach.hpp"
#include "marionette/behavior/saccade.hpp"
#include "marionette/behavior/speech_controller.hpp"
#include "marionette/rig/facs.hpp"

namespace marionette {

struct AnimationClip;
struct LocomotionPlan;

// Per-controller state of a request (BehaviorTimeline::Entry::controller). Gaze, pointing
// and speech keep theirs in their own headers (GazeState, PointingState, SpeechState).
struct HeadMotionState {            // head: the catalogue of head_motion.hpp
  HeadLexeme lexeme = HeadLexeme::Nod;
  HeadMove move;                    // its angles and shape
  std::vector<HeadStroke> strokes;  // one per repetition (thinned to what a head can do)
  HeadPhases phases;                // a held move's
  float amount = 1.0f;              // BML amount (made smaller when faster than a head turns)
};
struct FaceExpressionState {                 // faceLexeme, faceFacs, face, faceShift
  std::vector<std::pair<int, float>> morphs;  // (morph target, weight at full expression)
  // Eyelid and brow joints for FACS units the face has no morph for (rig/facs.hpp):
  // an upper lid closes by `value` radians, a brow rises by `value` (model units).
  struct JointMove {
    int joint = -1;
    FacsFacePart part = FacsFacePart::UpperLid;
    float value = 0.0f;
  };
  std::vector<JointMove> joints;
  float amount = 1.0f;                         // BML amount
};
struct LocomotionEntryState {
  std::shared_ptr<const LocomotionPlan> plan;  // where to go
  glm::vec3 resolvedTarget{0.0f};              // a target character's place before this frame
};
// A sound the engine plays: when it stops (the request's end if that comes before the clip's),
// and whether the engine was told it stopped (once: a cut, a cancel).
struct AudioState {
  double playEnd = 0.0;  // scene time
  bool cut = false;      // the request ends before the clip: the engine is told to stop at playEnd
  bool stopped = false;
};
using ControllerState = std::variant<std::monostate, HeadMotionState, FaceExpressionState, GazeState, PointingState,
                                     SpeechState, LocomotionEntryState, GestureState, SaccadeState,
                                     BlinkState, BreathingState, AudioState, ReachState>;

class BehaviorTimeline {
 public:
  // Blend time used when a request has no ready (or attackPeak) / relax sync point: this long,
  // or a quarter of the request's duration if that is shorter A controller may set
  // its own envelope after add() (speech has none: Character::bindSpeechEntry).
  static constexpr double kDefaultBlendSeconds = 0.3;

  struct Entry {
    BehaviorRequest request;
    std::uint64_t order = 0;     // larger = added later = wins conflicts
    double blendInEnd = 0.0;     // weight reaches request.weight here ("ready")
    double blendOutStart = 0.0;  // and starts to fall here ("relax")
    double cancelAt = std::numeric_limits<double>::infinity();
    double cancelBlend = 0.0;    // seconds of blend-out after cancelAt
    // Clip playback, when the request names a clip the rig has (bound by Character).
    std::shared_ptr<const AnimationClip> clip;
    SamplingCursor cursor, rootCursor;
    std::vector<float> mask;     // per joint: 1 where the clip animates it
    bool upperBody = false;      // a gesture's clip: played over posture and locomotion
    // The procedural controller's state, bound by Character::addBehavior: one alternative
    // per controller, monostate for a request that only plays its clip or waits.
    ControllerState controller;
    bool done = false;           // prune()'s mark

    template <class State>
    [[nodiscard]] State* as() noexcept { return std::get_if<State>(&controller); }
    template <class State>
    [[nodiscard]] const State* as() const noexcept { return std::get_if<State>(&controller); }
    [[nodiscard]] bool cancelled() const noexcept { return cancelAt != std::numeric_limits<double>::infinity(); }
    // Time after which the request has no effect (infinite for a persistent one).
    [[nodiscard]] double finishTime() const noexcept;
  };

  // Empty if the request can be added, else what is wrong with it (naming the
  // request and the field): an empty or duplicate id, no sync points, a
  // non-finite time, sync points out of order, a weight outside [0, 1].
  [[nodiscard]] std::string check(const BehaviorRequest& request) const;
  // Adds a request that passed check(). Returns its entry (valid until the next add or prune).
  Entry& add(BehaviorRequest request);

  // Ends a request at scene time `at`, blending it out over `blendOut` seconds.
  // A request that had not started by then is removed at once. False if unknown.
  bool cancel(std::string_view id, double at, double blendOut);
  // Cancels every request whose id starts with `prefix` ("block1:" ends a BML
  // block's behaviors). Returns how many.
  std::size_t cancelPrefix(std::string_view prefix, double at, double blendOut);

  // Weight of an entry at scene time t, in [0, request.weight]: smoothstep in
  // from start to blendInEnd, out from blendOutStart to end (not for persistent
  // requests), times the cancellation blend-out.
  [[nodiscard]] static float weightAt(const Entry& entry, double t) noexcept;

  // The request driving any of `channels` at time t: of those with a weight
  // above zero there, the one added last. nullptr if none.
  [[nodiscard]] const BehaviorRequest* owner(BodyChannel channels, double t) const noexcept;

  // Drops requests that can no longer have an effect at time t: finished, or
  // persistent and fully covered by a later request on all of their channels.
  // Per-frame: no allocation.
  void prune(double t) noexcept;

  [[nodiscard]] std::span<Entry> entries() noexcept { return entries_; }
  [[nodiscard]] std::span<const Entry> entries() const noexcept { return entries_; }
  [[nodiscard]] const Entry* find(std::string_view id) const noexcept;
  [[nodiscard]] bool empty() const noexcept { return entries_.empty(); }

 private:
  std::vector<Entry> entries_;  // in add order (ascending `order`)
  std::uint64_t nextOrder_ = 0;
};

}  // namespace marionette
