// The AR camera when the scene names a tracker: the background's frames feed it, and the
// view and projection come from its pose and the calibrated intrinsics (scaled and cropped
// the way the background image covers the viewport). When LOST, the last pose is held for
// `holdSeconds`, then the characters are hidden unless `hideWhenLost` is false.
#pragma once
#include <memory>
#include <string>

#include <glm/mat4x4.hpp>

#include "ar_scene_file.hpp"
#include "calibrated_view.hpp"
#include "marionette_ar/tracking/tracker.hpp"

namespace marionette::ar {

class TrackedCamera {
 public:
  // Errors (and the readers' warnings) go to `diagnostics`, naming the file (calibration,
  // target, map) or the scene key.
  [[nodiscard]] static std::unique_ptr<TrackedCamera> create(const ArTracker& settings, int frameWidth,
                                                             int frameHeight, Diagnostics& diagnostics);
  ~TrackedCamera();

  // A new background frame (RGB8, rows top to bottom) shown from scene time `seconds`.
  void update(const ImageView& frame, double seconds) noexcept;

  [[nodiscard]] TrackingState state() const noexcept { return last_.state; }
  // Which pixels of the last frame hide the target (target_occlusion.hpp), made on the first call
  // after update(); null from a tracker without one (AprilTag).
  [[nodiscard]] const OcclusionMask* occlusionMask() noexcept { return tracker_->occlusionMask(); }
  [[nodiscard]] const CameraModel& camera() const noexcept { return tracker_->camera(); }
  // A pose to draw with: tracked now, or held after a loss for at most holdSeconds.
  [[nodiscard]] bool hasPose(double seconds) const noexcept { return hold_.hasPose(seconds); }
  [[nodiscard]] bool charactersVisible(double seconds) const noexcept { return hold_.charactersVisible(seconds); }
  [[nodiscard]] float opacity(double seconds) const noexcept { return hold_.opacity(seconds); }
  [[nodiscard]] glm::mat4 view() const noexcept { return hold_.view(); }
  [[nodiscard]] glm::dmat4 viewInDouble() const noexcept { return hold_.viewInDouble(); }  // for measuring
  // OpenGL projection of the calibrated camera for a viewport the frame covers (viewportProjection).
  [[nodiscard]] glm::mat4 projection(int viewportWidth, int viewportHeight, float nearZ, float farZ) const noexcept {
    return viewportProjection(tracker_->camera(), viewportWidth, viewportHeight, nearZ, farZ);
  }
  // The tracker's frame time, median so far (ms; for the renderer's summary line).
  [[nodiscard]] double medianMilliseconds() const;
  [[nodiscard]] long framesTracked() const noexcept { return tracked_; }
  [[nodiscard]] long framesSeen() const noexcept { return frames_; }

 private:
  explicit TrackedCamera(const ArTracker& settings) : hold_(settings.holdSeconds, settings.hideWhenLost) {}
  std::unique_ptr<Tracker> tracker_;
  TrackedPose last_;
  PoseHold hold_;
  long frames_ = 0, tracked_ = 0;
  std::vector<double> ms_;
};

}  // namespace marionette::ar
