// How far a camera pose can be trusted: a live tracker's verdict per frame, and the state
// column of a recorded pose track (pose_track.hpp). One enum from the tracker to the badge.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace marionette::ar {

enum class TrackingState : std::uint8_t {
  Lost,      // no pose to draw
  Limited,   // a checked pose from fewer or looser features, or extrapolated briefly from confirmed ones
  Tracking,  // a confirmed pose: strong evidence, consistent with the camera's motion
};
[[nodiscard]] std::string_view trackingStateName(TrackingState state) noexcept;  // "TRACKING", "LIMITED", "LOST"
[[nodiscard]] std::optional<TrackingState> trackingStateFromName(std::string_view name) noexcept;  // exact case
[[nodiscard]] std::string trackingStateNames();  // "TRACKING, LIMITED or LOST", for messages

}  // namespace marionette::ar
