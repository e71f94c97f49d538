// A timed behavior request: what a character should do, between which scene
// times, on which body channels. The BML realizer makes these from BML blocks;
// an engine can make them directly, without BML:
//
//   BehaviorRequest wave;
//   wave.id = "wave1";
//   wave.kind = BehaviorKind::Gesture;
//   wave.clip = "Wave";                       // a clip of the character's rig
//   wave.syncs = {{"start", t}, {"ready", t + 0.3}, {"relax", t + 1.7}, {"end", t + 2.0}};
//   character.addBehavior(std::move(wave));
//
// Controllers with parameters take them typed (behavior_parameters.hpp):
//
//   BehaviorRequest nod{.id = "nod1", .kind = BehaviorKind::Head,
//                       .syncs = {{"start", t}, {"end", t + 1.0}},
//                       .parameters = HeadParameters{.lexeme = HeadLexeme::Nod, .amount = 0.8f}};
//
// Sync times are on the scene clock (seconds). The weight of a request rises
// from 0 at "start" to 1 at "ready" and falls back to 0 from "relax" to "end"
// (smoothstep); without ready/relax it blends over a short default time.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "marionette/behavior/behavior_parameters.hpp"

namespace marionette {

// What kind of behavior a request is; controllers pick the kinds they realize.
// The names are BML 1.0's element names (toString / behaviorKindFromName).
enum class BehaviorKind : std::uint8_t {
  Posture, PostureShift, Locomotion, Gaze, GazeShift, Head, HeadDirectionShift,
  FaceLexeme, FaceFacs, Face, FaceShift, Gesture, Pointing, Speech, Wait,
  Clip,  // play a clip of the rig, nothing more (no BML element)
  Saccade,  // rapid eye movements: a model's (talk, listen, think) or one (SmartBody's <saccade>)
  BlinkEmitter, BreathingEmitter,  // idle life (AsapRealizer's bmlt:blinkemitter, bmlt:breathingemitter)
  Audio,    // a sound handed to the engine (AsapRealizer's <bmlt:audiofile>); moves nothing
  Reach,    // a hand to a target and back (SmartBody's <sbm:reach>; behavior/reach.hpp)
};
[[nodiscard]] std::string_view toString(BehaviorKind kind) noexcept;
[[nodiscard]] std::optional<BehaviorKind> behaviorKindFromName(std::string_view name) noexcept;
// Whether the kind's controller also runs over a clip that realizes it: a pointing aims
// the arm over its gesture clip; every other clip realizes its behavior alone. The BML
// mapping reads the parameters of such a request and the character binds the controller.
[[nodiscard]] constexpr bool controllerRunsOverClip(BehaviorKind kind) noexcept { return kind == BehaviorKind::Pointing; }

// Body channels, as bits. Requests whose channels overlap conflict while both
// run: the one added later is blended over the earlier one, so it wins at full
// weight and the earlier one shows through while it blends in or out.
// Face channels are not exclusive (lexemes add up): a face request has no bits.
// A BodyChannel holds a set of channels: combine with |, test with any(a & b).
enum class BodyChannel : std::uint32_t {
  None = 0,
  Posture = 1u << 0,
  Locomotion = 1u << 1,
  LeftHand = 1u << 2,
  RightHand = 1u << 3,
  Hands = LeftHand | RightHand,
  Head = 1u << 4,
  Gaze = 1u << 5,
  Voice = 1u << 6,
  Eyes = 1u << 7,  // saccades, over whatever the gaze does
  Blink = 1u << 8,   // the blink emitter, over the face's eyelids
  Breath = 1u << 9,  // the breathing emitter, added on the chest and shoulders
};
[[nodiscard]] constexpr BodyChannel operator|(BodyChannel a, BodyChannel b) noexcept {
  return static_cast<BodyChannel>(static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b));
}
[[nodiscard]] constexpr BodyChannel operator&(BodyChannel a, BodyChannel b) noexcept {
  return static_cast<BodyChannel>(static_cast<std::uint32_t>(a) & static_cast<std::uint32_t>(b));
}
[[nodiscard]] constexpr BodyChannel operator~(BodyChannel c) noexcept {
  return static_cast<BodyChannel>(~static_cast<std::uint32_t>(c));
}
constexpr BodyChannel& operator|=(BodyChannel& a, BodyChannel b) noexcept { return a = a | b; }
constexpr BodyChannel& operator&=(BodyChannel& a, BodyChannel b) noexcept { return a = a & b; }
// Whether the set holds any channel.
[[nodiscard]] constexpr bool any(BodyChannel c) noexcept { return c != BodyChannel::None; }
// The channels a kind drives by default (gestures: both hands).
[[nodiscard]] BodyChannel defaultChannels(BehaviorKind kind) noexcept;
// "posture", "leftHand", "hands", ... joined with '+'; "" for none.
[[nodiscard]] std::string channelNames(BodyChannel channels);
// The channels of one name ("hands" = both hands); None for an unknown name.
[[nodiscard]] BodyChannel channelFromName(std::string_view name) noexcept;

struct BehaviorSync {
  std::string name;  // "start", "ready", "stroke", ... or any name the caller gives
  double time = 0.0; // scene seconds
};

struct BehaviorRequest {
  std::string id{};      // unique among the character's requests (the realizer uses "block:behavior")
  BehaviorKind kind = BehaviorKind::Clip;
  std::optional<BodyChannel> channels{};  // unset: defaultChannels(kind)
  std::vector<BehaviorSync> syncs{};      // in time order; the first is the start, the last the end
  BehaviorParameters parameters{};        // the struct of the kind's controller (behavior_parameters.hpp)
  std::string clip{};    // a clip of the rig to play, time-warped onto [start, end]; "" = none
  bool loop = false;     // play the clip at its own speed, looping, instead of warping it
  bool persistent = false;  // keeps full weight after its end until replaced or cancelled (postureShift)
  float weight = 1.0f;   // peak weight in [0, 1]

  [[nodiscard]] double start() const noexcept { return syncs.empty() ? 0.0 : syncs.front().time; }
  [[nodiscard]] double end() const noexcept { return syncs.empty() ? 0.0 : syncs.back().time; }
  // Time of a sync point by name (case-sensitive), if present.
  [[nodiscard]] std::optional<double> time(std::string_view sync) const noexcept;
  // The parameters as T (HeadParameters, GazeParameters, ...), or null when they are of another type.
  template <class T>
  [[nodiscard]] const T* as() const noexcept { return std::get_if<T>(&parameters); }
  [[nodiscard]] BodyChannel channelBits() const noexcept { return channels ? *channels : defaultChannels(kind); }
};

}  // namespace marionette
