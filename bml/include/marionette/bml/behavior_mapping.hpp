// From a scheduled BML behavior to the middleware's BehaviorRequest: its kind,
// body channels, sync times on the scene clock, typed parameters, and the rig clip
// that realizes it when the character has one named by its lexeme.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/bml/behavior_parameters.hpp"
#include "marionette/bml/scheduler.hpp"
#include "marionette/scene/character.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette::bml {

// Body channels a behavior drives (gesture/pointing mode LEFT_HAND / RIGHT_HAND
// take one hand, otherwise both). Face behaviors and wait: none.
[[nodiscard]] BodyChannel channelsOf(const Behavior& behavior);

// The rig clip that realizes a behavior: for gesture and pointing the clip the
// character profile's gesture library gives the lexeme, else the clip named by
// the lexeme; for head its lexeme, for posture and postureShift its lexeme or
// SmartBody posture name; names matched exactly, else ignoring case. nullptr
// when there is none (a head then moves procedurally).
[[nodiscard]] std::shared_ptr<const AnimationClip> clipFor(const Behavior& behavior, const Rig& rig);

// A behavior's natural duration on a rig: the length of its clip (one
// repetition), for the scheduler's SchedulerOptions::defaultDuration.
// Postures loop, so they keep the built-in default.
[[nodiscard]] std::optional<double> naturalDuration(const Behavior& behavior, const Rig& rig);
// The same for a character: a locomotion lasts as long as the walk from where
// the character stands takes (Character::estimateLocomotion); the rest as on its rig.
[[nodiscard]] std::optional<double> naturalDuration(const Behavior& behavior, const Character& character);

// A <speech>'s timing as the character's speech service says it (synthesized
// once, cached for the realization), for SchedulerOptions::speechTiming; nullopt
// when it cannot be said (the request then fails with the reason when realized).
[[nodiscard]] std::optional<SpeechTiming> speechTiming(const Behavior& behavior, const Character& character);
// Starts saying a <speech> on the character's speech service's thread (what the
// realizer does before it schedules a block); null for another behavior or outside a scene.
[[nodiscard]] std::shared_ptr<const speech::SpeechService::Preparation> prepareSpeechTiming(const Behavior& behavior,
                                                                                          const Character& character);

// The request for one scheduled behavior of a block that starts at `blockStart`
// (scene seconds). Its id is "blockId:behaviorId"; its parameters are read from
// the behavior's attributes (behavior_parameters.hpp), unless a clip of the rig
// realizes it alone. `error`: why the parameters make it impossible (the request
// still joins the timeline, unrealized, so its timing and feedback run; the
// realizer reports `error` in place of the character's own reason); `warning`:
// attribute values replaced by defaults.
struct MappedRequest {
  BehaviorRequest request;
  std::string error;
  std::string warning;
};
[[nodiscard]] MappedRequest toRequest(const Behavior& behavior, const ScheduledBehavior& scheduled,
                                        const std::string& blockId, double blockStart, const Rig& rig);

// SmartBody's <blend name="STATE" x= y= z=>: the blend space of the character's profile
// named STATE at the point (x, y). `error` when the rig has no such space (naming those it
// has); `warning` for a value that is not a number (0 used), a z (ignored: spaces have 1 or
// 2 parameters) or a y given to a 1D space. Empty x or y (SmartBody's "leave it") read as 0.
struct SmartBodyBlend {
  std::string name;
  float x = 0.0f, y = 0.0f;
  std::string error, warning;
};
[[nodiscard]] SmartBodyBlend readSmartBodyBlend(const Behavior& behavior, const Rig& rig);

}  // namespace marionette::bml
