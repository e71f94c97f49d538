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
                                                     Diagnostics& diagnostics) {
  auto camera = calibrationForFrames(settings.camera, frameWidth, frameHeight, diagnostics);
  if (!camera) return nullptr;
  Diagnostics& d = diagnostics;
  // One thread, as the figures in docs/tracking.md are measured, and deterministic: the
  // renderer's frame loop is the only thread that tracks.
  cv::setNumThreads(1);
  std::unique_ptr<TrackedCamera> t(new TrackedCamera(settings));
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
    const std::string& file = settings.kind == ArTracker::Kind::AprilTag ? settings.camera
                              : settings.map.empty()                     ? settings.target
                                                                         : settings.map;
    if (d.ok()) d.error(file, "the tracker could not be made");
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
  hold_.update(last_.state != TrackingState::Lost, last_.cameraToWorld, seconds,
               {last_.state == TrackingState::Limited, last_.positionSigmaM, last_.rotationSigmaDeg});
  if (last_.state != TrackingState::Lost) ++tracked_;
}

double TrackedCamera::medianMilliseconds() const {
  if (ms_.empty()) return 0;
  std::vector<double> v = ms_;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace marionette::ar
