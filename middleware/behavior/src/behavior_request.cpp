#include "marionette/behavior/behavior_request.hpp"
#include "marionette/core/enum_names.hpp"

#include <array>

namespace marionette {

namespace {
constexpr std::array<std::string_view, 21> kKindNames = {
    "posture",   "postureShift", "locomotion", "gaze", "gazeShift", "head",    "headDirectionShift", "faceLexeme",
    "faceFacs", "face",         "faceShift",  "gesture", "pointing", "speech", "wait",               "clip",
    "saccade",   "blinkemitter", "breathingemitter", "audiofile", "reach"};
}  // namespace

std::string_view toString(BehaviorKind kind) noexcept {
  const auto i = static_cast<std::size_t>(kind);
  return i < kKindNames.size() ? kKindNames[i] : std::string_view("unknown");
}

std::optional<BehaviorKind> behaviorKindFromName(std::string_view name) noexcept {
  return valueOfIndexedName<BehaviorKind>(name, kKindNames);
}

BodyChannel defaultChannels(BehaviorKind kind) noexcept {
  switch (kind) {
    case BehaviorKind::Posture:
    case BehaviorKind::PostureShift: return BodyChannel::Posture;
    case BehaviorKind::Locomotion: return BodyChannel::Locomotion;
    case BehaviorKind::Gaze:
    case BehaviorKind::GazeShift: return BodyChannel::Gaze;
    case BehaviorKind::Head:
    case BehaviorKind::HeadDirectionShift: return BodyChannel::Head;
    case BehaviorKind::Gesture:
    case BehaviorKind::Pointing:
    case BehaviorKind::Reach: return BodyChannel::Hands;  // a reach's bind narrows it to its arm
    case BehaviorKind::Speech: return BodyChannel::Voice;
    case BehaviorKind::Saccade: return BodyChannel::Eyes;
    case BehaviorKind::BlinkEmitter: return BodyChannel::Blink;
    case BehaviorKind::BreathingEmitter: return BodyChannel::Breath;
    case BehaviorKind::Clip: return BodyChannel::Posture;  // a whole-body clip stands in for the posture
    default: return BodyChannel::None;  // face behaviors combine; wait and audio drive nothing
  }
}

std::string channelNames(BodyChannel channels) {
  static constexpr std::array<std::pair<BodyChannel, std::string_view>, 9> kNames = {{
      {BodyChannel::Posture, "posture"},
      {BodyChannel::Locomotion, "locomotion"},
      {BodyChannel::Hands, "hands"},  // before the single hands, so both read "hands"
      {BodyChannel::Head, "head"},
      {BodyChannel::Gaze, "gaze"},
      {BodyChannel::Voice, "voice"},
      {BodyChannel::Eyes, "eyes"},
      {BodyChannel::Blink, "blink"},
      {BodyChannel::Breath, "breath"},
  }};
  std::string out;
  auto append = [&](std::string_view s) {
    if (!out.empty()) out += '+';
    out += s;
  };
  for (auto [bits, name] : kNames) {
    if (bits == BodyChannel::Hands) {
      if ((channels & BodyChannel::Hands) == BodyChannel::Hands) append(name);
      else if (any(channels & BodyChannel::LeftHand)) append("leftHand");
      else if (any(channels & BodyChannel::RightHand)) append("rightHand");
    } else if (any(channels & bits)) {
      append(name);
    }
  }
  return out;
}

BodyChannel channelFromName(std::string_view name) noexcept {
  if (name == "leftHand") return BodyChannel::LeftHand;
  if (name == "rightHand") return BodyChannel::RightHand;
  for (BodyChannel bits : {BodyChannel::Posture, BodyChannel::Locomotion, BodyChannel::Hands, BodyChannel::Head,
                           BodyChannel::Gaze, BodyChannel::Voice, BodyChannel::Eyes, BodyChannel::Blink,
                           BodyChannel::Breath})
    if (channelNames(bits) == name) return bits;
  return BodyChannel::None;
}

std::optional<double> BehaviorRequest::time(std::string_view sync) const noexcept {
  for (const BehaviorSync& s : syncs)
    if (s.name == sync) return s.time;
  return std::nullopt;
}

}  // namespace marionette
