#include "calibrated_view.hpp"

#include <algorithm>
#include <cmath>

namespace marionette::ar {

std::optional<CameraModel> calibrationForFrames(const std::string& file, int frameWidth, int frameHeight,
                                                Diagnostics& diagnostics) {
  auto camera = readCameraModel(file, diagnostics);
  if (!camera) {
    if (diagnostics.ok()) diagnostics.error(file, "cannot read the calibration");
    return std::nullopt;
  }
  if (camera->width != frameWidth || camera->height != frameHeight) {
    if (std::abs(static_cast<double>(camera->width) * frameHeight - static_cast<double>(camera->height) * frameWidth) >
        0.01 * static_cast<double>(camera->width) * frameHeight) {
      diagnostics.error(file, "calibrated for " + std::to_string(camera->width) + "x" + std::to_string(camera->height) +
                                  " but the background frames are " + std::to_string(frameWidth) + "x" +
                                  std::to_string(frameHeight) + " (another aspect ratio)");
      return std::nullopt;
    }
    *camera = camera->scaledTo(frameWidth, frameHeight);
  }
  return camera;
}

glm::mat4 viewportProjection(const CameraModel& c, int viewportWidth, int viewportHeight, float nearZ,
                             float farZ) noexcept {
  const double s = std::max(static_cast<double>(viewportWidth) / c.width, static_cast<double>(viewportHeight) / c.height);
  CameraModel v = c;
  v.width = viewportWidth;
  v.height = viewportHeight;
  v.fx = c.fx * s;
  v.fy = c.fy * s;
  v.cx = (c.cx + 0.5) * s + 0.5 * (viewportWidth - s * c.width) - 0.5;
  v.cy = (c.cy + 0.5) * s + 0.5 * (viewportHeight - s * c.height) - 0.5;
  return v.glProjection(nearZ, farZ);
}

}  // namespace marionette::ar
