// What a tracked camera and a replayed one (tracked_camera.hpp, replayed_camera.hpp) share: the
// calibration fitted to the background's frames, the OpenGL projection of it for a viewport the
// frames cover, and the pose held after a loss (pose_hold.hpp).
#pragma once
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>

#include "marionette_ar/pose_hold.hpp"  // PoseHold: what both draw with
#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar {

// Reads the calibration YAML and scales it to frames of frameWidth x frameHeight (a calibration
// at another resolution of the same sensor still holds); another aspect ratio is an error
// naming the file. Errors (and the reader's warnings) go to `diagnostics`, naming the file and
// the field.
[[nodiscard]] std::optional<CameraModel> calibrationForFrames(const std::string& file, int frameWidth, int frameHeight,
                                                              Diagnostics& diagnostics);

// The OpenGL projection of `camera` for a viewport its frames cover: scaled to fill it, the
// longer side cropped, as BackgroundRenderer::drawImage draws the frame.
[[nodiscard]] glm::mat4 viewportProjection(const CameraModel& camera, int viewportWidth, int viewportHeight,
                                           float nearZ, float farZ) noexcept;

}  // namespace marionette::ar
