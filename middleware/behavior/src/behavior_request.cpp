#include "marionette/behavior/behavior_request.hpp"
#include "marionette/core/enum_names.hpp"

#include <array>

namespace marionette {

namespace {
constexpr std::array<std::string_view, 17> kKindNames = {
    "posture",   "postureShift", "locomotion", "gaze", "gazeShift", "head",    "headDirectionShift", "faceLexeme",
    "faceFacs", "face",         "faceShift",  "gesture", "pointing", "speech", "wait",               "clip",
    "saccade"};
}  // namespace

std::string_view toString(BehaviorKind kind) noexcept {
  const auto i = static_cast<std::size_t>(kind);
  return i < kKindNames.size() ? kKindNames[i] : std::string_view("unknown");
}

std::optional<BehaviorKind> behaviorKindFromName(std::string_view name) noexcept {
  return valueOfIndexedName<BehaviorKind>(name, kKindNames);
}

std::uint32_t defaultChannels(BehaviorKind kind) noexcept {
  switch (kind) {
    case BehaviorKind::Posture:
    case BehaviorKind::PostureShift: return kChannelPosture;
    case BehaviorKind::Locomotion: return kChannelLocomotion;
    case BehaviorKind::Gaze:
    case BehaviorKind::GazeShift: return kChannelGaze;
    case BehaviorKind::Head:
    case BehaviorKind::HeadDirectionShift: return kChannelHead;
    case BehaviorKind::Gesture:
    case BehaviorKind::Pointing: return kChannelHands;
    case BehaviorKind::Speech: return kChannelVoice;
    case BehaviorKind::Saccade: return kChannelEyes;
    case BehaviorKind::Clip: return kChannelPosture;  // a whole-body clip stands in for the posture
    default: return 0;                                // face behaviors combine; wait drives nothing
  }
}

std::string channelNames(std::uint32_t channels) {
  static constexpr std::array<std::pair<std::uint32_t, std::string_view>, 7> kNames = {{
      {kChannelPosture, "posture"},
      {kChannelLocomotion, "locomotion"},
      {kChannelHands, "hands"},  // before the single hands, so both read "hands"
      {kChannelHead, "head"},
      {kChannelGaze, "gaze"},
      {kChannelVoice, "voice"},
      {kChannelEyes, "eyes"},
  }};
  std::string out;
  auto append = [&](std::string_view s) {
    if (!out.empty()) out += '+';
    out += s;
  };
  for (auto [bits, name] : kNames) {
    if (bits == kChannelHands) {
      if ((channels & kChannelHands) == kChannelHands) append(name);
      else if (channels & kChannelLeftHand) append("leftHand");
      else if (channels & kChannelRightHand) append("rightHand");
    } else if (channels & bits) {
      append(name);
    }
  }
  return out;
}

std::uint32_t channelFromName(std::string_view name) noexcept {
  if (name == "leftHand") return kChannelLeftHand;
  if (name == "rightHand") return kChannelRightHand;
  for (std::uint32_t bits :
       {kChannelPosture, kChannelLocomotion, kChannelHands, kChannelHead, kChannelGaze, kChannelVoice, kChannelEyes})
    if (channelNames(bits) == name) return bits;
  return 0;
}

std::optional<double> BehaviorRequest::time(std::string_view sync) const noexcept {
  for (const BehaviorSync& s : syncs)
    if (s.name == sync) return s.time;
  return std::nullopt;
}

}  // namespace marionette
