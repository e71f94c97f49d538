#include "replayed_camera.hpp"

namespace marionette::ar {

std::unique_ptr<ReplayedCamera> ReplayedCamera::create(const ArPoseReplay& settings, int frameWidth, int frameHeight,
                                                       Diagnostics& diagnostics) {
  auto track = readPoseTrack(settings.poses, diagnostics);
  if (!track) {
    if (diagnostics.ok()) diagnostics.error(settings.poses, "cannot read the poses");
    return nullptr;
  }
  std::optional<CameraModel> camera;
  if (frameWidth > 0 && frameHeight > 0) {
    camera = calibrationForFrames(settings.camera, frameWidth, frameHeight, diagnostics);
  } else {  // no camera frames: the calibration's own image is what covers the viewport
    camera = readCameraModel(settings.camera, diagnostics);
    if (!camera && diagnostics.ok()) diagnostics.error(settings.camera, "cannot read the calibration");
  }
  if (!camera) return nullptr;
  return std::unique_ptr<ReplayedCamera>(new ReplayedCamera(std::move(*track), *camera, settings));
}

void ReplayedCamera::update(std::int64_t frame, double seconds) noexcept {
  const RecordedPose* row = frame >= 0 ? track_.atFrame(frame) : &track_.atTime(seconds);
  state_ = row ? row->state : TrackingState::Lost;
  ++frames_;
  const bool posed = state_ != TrackingState::Lost;
  posed_ += posed ? 1 : 0;
  hold_.update(posed, posed ? row->cameraToWorld : glm::dmat4(1.0), seconds,
               posed ? PoseQuality{state_ == TrackingState::Limited, row->positionSigmaM, row->rotationSigmaDeg}
                     : PoseQuality{});
}

}  // namespace marionette::ar
