// The AR camera when the scene replays a recorded trajectory ("camera": {"poses": "poses.csv",
// "camera": "camera.yml"}): the CSV `marionette-ar track` writes drives the view, the calibrated
// intrinsics the projection (calibrated_view.hpp, as a tracked camera's), and LOST rows act as
// the tracker's LOST: the last pose held for holdSeconds, then the characters hidden unless
// hideWhenLost is false. Track once offline, render many times.
//
// Which row: over a sequence or video background, the row whose `frame` is the background frame
// shown (so the poses follow the frames exactly, loops included; a frame without a row is LOST);
// over any other background, the row of the scene time (PoseTrack::atTime).
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include <glm/mat4x4.hpp>

#include "ar_scene_file.hpp"
#include "calibrated_view.hpp"
#include "marionette_ar/pose_track.hpp"

namespace marionette::ar {

class ReplayedCamera {
 public:
  // frameWidth x frameHeight: the background frames' size, or 0 x 0 without camera frames
  // (then the calibration's own size). Errors go to `diagnostics`, naming the file (CSV line
  // and field, calibration).
  [[nodiscard]] static std::unique_ptr<ReplayedCamera> create(const ArPoseReplay& settings, int frameWidth,
                                                              int frameHeight, Diagnostics& diagnostics);

  // The frame shown: by background frame number (>= 0), or by scene time when frame < 0.
  void update(std::int64_t frame, double seconds) noexcept;

  [[nodiscard]] TrackingState state() const noexcept { return state_; }
  [[nodiscard]] bool hasPose(double seconds) const noexcept { return hold_.hasPose(seconds); }
  [[nodiscard]] bool charactersVisible(double seconds) const noexcept { return hold_.charactersVisible(seconds); }
  [[nodiscard]] float opacity(double seconds) const noexcept { return hold_.opacity(seconds); }
  [[nodiscard]] glm::mat4 view() const noexcept { return hold_.view(); }
  [[nodiscard]] glm::dmat4 viewInDouble() const noexcept { return hold_.viewInDouble(); }  // for measuring
  [[nodiscard]] glm::mat4 projection(int viewportWidth, int viewportHeight, float nearZ, float farZ) const noexcept {
    return viewportProjection(camera_, viewportWidth, viewportHeight, nearZ, farZ);
  }
  [[nodiscard]] long framesSeen() const noexcept { return frames_; }
  [[nodiscard]] long framesPosed() const noexcept { return posed_; }

 private:
  ReplayedCamera(PoseTrack track, CameraModel camera, const ArPoseReplay& settings)
      : track_(std::move(track)), camera_(camera), hold_(settings.holdSeconds, settings.hideWhenLost) {}
  PoseTrack track_;
  CameraModel camera_;
  PoseHold hold_;
  TrackingState state_ = TrackingState::Lost;
  long frames_ = 0, posed_ = 0;
};


}  // namespace marionette::ar
