// One interface for every camera tracker: frames in, the camera's pose in the world out.
//
// World and camera conventions (the renderer's): the world is metric, +Y up. For a planar
// target (markerless image or AprilTag) the world is the target's plane: its centre at the
// origin, +Y out of its printed face, the target image's right along +X and its down along
// +Z. The pose is camera-to-world with the camera's axes as OpenGL's: looking along -Z, +Y
// up, +X right (OpenCV's camera has Y down and Z forward: flip Y and Z).
//
// Per-frame contract: update() never throws, is deterministic for the same frames and
// settings, and runs on the calling thread (OpenCV's own parallel loops follow
// cv::setNumThreads; marionette-ar sets 1).
#pragma once
#include <array>
#include <cstdint>
#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/gtc/quaternion.hpp>

#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/image_view.hpp"

#include "marionette_ar/tracking_state.hpp"

namespace marionette::ar {

// Every pose that is not Lost has passed the tracker's checks (docs/tracking.md, "Gating"): a
// pose the tracker cannot vouch for is not given at all. Limited says it may be less accurate.

struct TrackedPose {
  TrackingState state = TrackingState::Lost;
  glm::dmat4 cameraToWorld{1.0};  // valid unless Lost
  int inliers = 0;                 // correspondences that support the pose
  double reprojectionErrorPx = 0;  // rms over the inliers
  // The pose's uncertainty (one standard deviation), from the final Gauss-Newton step's
  // normal equations, the noise inflated for correlated feature errors, and grown by the
  // motion model while extrapolating (docs/tracking.md, "Confidence"). 0 when unknown.
  double positionSigmaM = 0;   // camera position: sqrt of the covariance's trace, metres
  double rotationSigmaDeg = 0;  // camera orientation: sqrt of the covariance's trace, degrees
  // The 6x6 covariance, row-major, of (rotation vector in world axes, radians; camera
  // position in world, metres): a small rotation w turns the pose to exp([w]x) R.
  std::array<double, 36> covariance{};

  [[nodiscard]] glm::dvec3 position() const noexcept { return glm::dvec3(cameraToWorld[3]); }
  [[nodiscard]] glm::dquat orientation() const noexcept;  // camera-to-world rotation
};

struct OcclusionMask;  // target_occlusion.hpp

class Tracker {
 public:
  virtual ~Tracker() = default;
  // The pose of the camera that took `frame` at `seconds` (non-decreasing). A frame that is
  // not valid(), or not of camera().width x camera().height, gives Lost (and no throw).
  [[nodiscard]] virtual TrackedPose update(const ImageView& frame, double seconds) noexcept = 0;
  // Forget the motion history (the next frame relocalizes from scratch).
  virtual void reset() noexcept = 0;
  [[nodiscard]] virtual const CameraModel& camera() const noexcept = 0;

  // Which pixels of the target are hidden by something in front of it, for the last update()'s
  // frame and pose (target_occlusion.hpp; docs/tracking.md, "Occlusion over the target"):
  // computed on the first call after an update() and kept until the next (a scene that never
  // asks pays nothing). Every pixel 0 when the last frame had no pose. Null from a tracker that
  // has no occlusion map (hasOcclusionMask() false: AprilTag, which has no image of the target
  // to compare the frame with). The mask stays valid until the next update() or reset().
  [[nodiscard]] virtual bool hasOcclusionMask() const noexcept { return false; }
  [[nodiscard]] virtual const OcclusionMask* occlusionMask() noexcept { return nullptr; }
};

// Conversions between an OpenCV pose (rvec/tvec: world -> OpenCV camera) and camera-to-world
// in the renderer's camera axes.
[[nodiscard]] glm::dmat4 cameraToWorldFromOpenCv(const glm::dmat3& worldToCvCameraRotation,
                                                 const glm::dvec3& worldToCvCameraTranslation) noexcept;

}  // namespace marionette::ar
