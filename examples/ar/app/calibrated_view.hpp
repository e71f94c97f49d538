// What a tracked camera and a replayed one (tracked_camera.hpp, replayed_camera.hpp) share: the
// calibration fitted to the background's frames, the OpenGL projection of it for a viewport the
// frames cover, and the pose held after a loss.
#pragma once
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>

#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar {

// Reads the calibration YAML and scales it to frames of frameWidth x frameHeight (a calibration
// at another resolution of the same sensor still holds); another aspect ratio is an error
// naming the file. Errors go to `error`, naming the file and the field.
[[nodiscard]] std::optional<CameraModel> calibrationForFrames(const std::string& file, int frameWidth, int frameHeight,
                                                              std::string& error);

// The OpenGL projection of `camera` for a viewport its frames cover: scaled to fill it, the
// longer side cropped, as BackgroundRenderer::drawImage draws the frame.
[[nodiscard]] glm::mat4 viewportProjection(const CameraModel& camera, int viewportWidth, int viewportHeight,
                                           float nearZ, float farZ) noexcept;

// The last pose, held for holdSeconds after a loss; then the characters hide unless
// hideWhenLost is false. Before any pose there is none to draw with.
class PoseHold {
 public:
  PoseHold(double holdSeconds, bool hideWhenLost) : holdSeconds_(holdSeconds), hideWhenLost_(hideWhenLost) {}
  // A frame at `seconds`: with a pose (camera-to-world) or lost (`pose` ignored).
  void update(bool posed, const glm::dmat4& pose, double seconds) noexcept {
    posedNow_ = posed;
    if (!posed) return;
    held_ = pose;
    everPosed_ = true;
    lastPoseTime_ = seconds;
  }
  [[nodiscard]] bool hasPose(double seconds) const noexcept {
    return everPosed_ && (posedNow_ || seconds - lastPoseTime_ <= holdSeconds_);
  }
  [[nodiscard]] bool charactersVisible(double seconds) const noexcept {
    return hasPose(seconds) || (everPosed_ && !hideWhenLost_);
  }
  [[nodiscard]] glm::dmat4 viewInDouble() const noexcept { return glm::inverse(held_); }
  [[nodiscard]] glm::mat4 view() const noexcept { return glm::mat4(viewInDouble()); }

 private:
  double holdSeconds_;
  bool hideWhenLost_;
  glm::dmat4 held_{1.0};
  bool everPosed_ = false, posedNow_ = false;
  double lastPoseTime_ = -1e300;
};

}  // namespace marionette::ar
