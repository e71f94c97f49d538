// How far a camera pose can be trusted: a live tracker's verdict per frame, and the state
// column of a recorded pose track (pose_track.hpp). One enum from the tracker to the badge.
#pragma once
#include <cstdint>
#include <string_view>

namespace marionette::ar {

enum class TrackingState : std::uint8_t {
  Lost,      // no pose to draw
  Limited,   // a checked pose from fewer or looser features, or extrapolated briefly from confirmed ones
  Tracking,  // a confirmed pose: strong evidence, consistent with the camera's motion
};
[[nodiscard]] std::string_view trackingStateName(TrackingState state) noexcept;  // "TRACKING", "LIMITED", "LOST"

}  // namespace marionette::ar
