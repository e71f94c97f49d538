#include "tracked_camera.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <opencv2/core/utility.hpp>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"

namespace marionette::ar {

std::unique_ptr<TrackedCamera> TrackedCamera::create(const ArTracker& settings, int frameWidth, int frameHeight,
                                                     std::string& error) {
  Diagnostics d;
  auto camera = readCameraModel(settings.camera, d);
  auto firstError = [&]() {
    for (const Diagnostic& item : d.items)
      if (item.severity == Severity::Error) return item.format();
    return std::string("the tracker could not be made");
  };
  if (!camera) {
    error = firstError();
    return nullptr;
  }
  if (camera->width != frameWidth || camera->height != frameHeight) {
    // A calibration at another resolution of the same sensor (same aspect) still holds, scaled.
    if (std::abs(static_cast<double>(camera->width) * frameHeight - static_cast<double>(camera->height) * frameWidth) >
        0.01 * static_cast<double>(camera->width) * frameHeight) {
      error = settings.camera + ": calibrated for " + std::to_string(camera->width) + "x" +
              std::to_string(camera->height) + " but the background frames are " + std::to_string(frameWidth) + "x" +
              std::to_string(frameHeight) + " (another aspect ratio)";
      return nullptr;
    }
    *camera = camera->scaledTo(frameWidth, frameHeight);
  }
  // One thread, as the figures in docs/tracking.md are measured, and deterministic: the
  // renderer's frame loop is the only thread that tracks.
  cv::setNumThreads(1);
  std::unique_ptr<TrackedCamera> t(new TrackedCamera());
  t->settings_ = settings;
  if (settings.kind == ArTracker::Kind::AprilTag) {
    AprilTagSettings s;
    s.tagSize = settings.tagSize;
    t->tracker_ = AprilTagTracker::create(*camera, s, d);
  } else if (!settings.map.empty()) {
    auto map = readPlanarMap(settings.map, d);
    if (map) t->tracker_ = MarkerlessTracker::fromMap(*camera, std::move(*map), settings.map, {}, d);
  } else {
    t->tracker_ = MarkerlessTracker::fromTarget(*camera, settings.target, settings.width, {}, d);
  }
  if (!t->tracker_) {
    error = firstError();
    return nullptr;
  }
  t->ms_.reserve(1 << 16);
  return t;
}

TrackedCamera::~TrackedCamera() = default;

void TrackedCamera::update(const ImageView& frame, double seconds) noexcept {
  const auto start = std::chrono::steady_clock::now();
  last_ = tracker_->update(frame, seconds);
  if (ms_.size() < ms_.capacity())
    ms_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  ++frames_;
  if (last_.state != TrackingState::Lost) {
    held_ = last_;
    everPosed_ = true;
    lastPoseTime_ = seconds;
    ++tracked_;
  }
}

bool TrackedCamera::hasPose(double seconds) const noexcept {
  return everPosed_ && (last_.state != TrackingState::Lost || seconds - lastPoseTime_ <= settings_.holdSeconds);
}

bool TrackedCamera::charactersVisible(double seconds) const noexcept {
  return hasPose(seconds) || (everPosed_ && !settings_.hideWhenLost);
}

glm::mat4 TrackedCamera::view() const noexcept { return glm::mat4(glm::inverse(held_.cameraToWorld)); }

glm::mat4 TrackedCamera::projection(int viewportWidth, int viewportHeight, float nearZ, float farZ) const noexcept {
  const CameraModel& c = tracker_->camera();
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

double TrackedCamera::medianMilliseconds() const {
  if (ms_.empty()) return 0;
  std::vector<double> v = ms_;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace marionette::ar
