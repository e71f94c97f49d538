// Synthetic camera frames with exact ground truth: a planar target (a photo) lying on a
// textured floor, seen through a CameraModel (lens distortion included) from any
// camera-to-world pose, then degraded by motion blur, gain, noise and JPEG.
//
// Conventions are tracker.hpp's: metric world, +Y up, the target in the plane Y = 0 centred
// at the origin, its image's +u along +X and +v along +Z; target pixel (u, v) of a W x H
// image Wm metres wide is at X = (u + 0.5 - W/2) Wm/W, Z = (v + 0.5 - H/2) Wm/W. Poses are
// camera-to-world with OpenGL camera axes (looking along -Z, +Y up).
//
// Rendering: every output pixel is 2x2 supersampled. A sample's ray (the lens model
// inverted exactly, so a world point lands where cv::projectPoints puts it) meets the ground
// plane through the pose's plane homography K [r1 r3 t]; the hit is shaded from the target
// or the tiled floor texture, trilinearly from a Gaussian pyramid chosen by the sample's
// footprint (no shimmer at grazing angles; the floor fades to its mean colour toward the
// horizon). Rays that miss the plane in front of the camera see the sky colour.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <opencv2/core.hpp>

#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar::synthetic {

struct PlanarScene {
  cv::Mat target;             // RGB8 (or grey 8-bit) photo lying on the floor
  double targetWidth = 0.3;   // metres, along +X
  cv::Mat floor;              // RGB8 (or grey) texture tiled on the floor; empty: flat grey 128
  double floorMetresPerPixel = 0.002;
};

// Applied in this order after the geometric rendering: blur, gain, noise, JPEG.
struct FrameEffects {
  double motionBlurPx = 0;        // length of a normalized line kernel, pixels (<= 1: none)
  double motionBlurAngleDeg = 0;  // 0 along +x (image right), 90 along +y (image down)
  double noiseSigma = 0;          // additive Gaussian, 8-bit levels
  int jpegQuality = 0;            // 1..100; 0 = no JPEG round trip
  double gainEv = 0;              // pixel values times 2^gainEv, saturated
  // The occluder: an opaque, flat-coloured (kOccluderRgb) rectangle lying kOccluderHeight
  // above the target plane (so it has parallax, like a hand held over the target). It spans
  // the target's full depth (Z) and occluderFraction of its width (X), so it covers that share
  // of the target's area wherever it is; it sweeps along +X from the target's -X edge
  // (phase 0) to its +X edge (phase 1). 0: no occluder.
  double occluderFraction = 0;
  double occluderPhase = 0;
  std::uint32_t noiseSeed = 1;    // cv::RNG seed: the same seed gives the same noise
};

inline constexpr double kOccluderHeight = 0.003;  // metres above Y = 0
inline const cv::Vec3b kOccluderRgb{196, 138, 104};
inline const cv::Vec3b kSkyRgb{172, 196, 228};
inline const cv::Vec3b kInvalidLensRgb{0, 0, 0};  // pixels the lens model cannot invert

class SequenceRenderer {
 public:
  // Throws std::invalid_argument for an empty or non-8-bit target, a width <= 0, a camera
  // with a problem(), or an unusable floor.
  SequenceRenderer(PlanarScene scene, CameraModel camera);

  // outRgb becomes CV_8UC3, camera.width x camera.height, RGB order.
  void render(const glm::dmat4& cameraToWorld, const FrameEffects& fx, cv::Mat& outRgb) const;

  // Share of the target's area (a 96 x ~72 grid of points over it) that is in front of the
  // camera and projects inside the image through the lens. The occluder does not count.
  [[nodiscard]] double visibleTargetFraction(const glm::dmat4& cameraToWorld) const;

  [[nodiscard]] const CameraModel& camera() const noexcept { return camera_; }
  [[nodiscard]] double targetWidth() const noexcept { return scene_.targetWidth; }
  [[nodiscard]] double targetDepth() const noexcept;  // extent along Z, metres
  // World position of target pixel (u, v) (fractional; pixel centres at integers).
  [[nodiscard]] glm::dvec3 targetPixelToWorld(double u, double v) const noexcept;

 private:
  struct Pyramid {
    std::vector<cv::Mat> levels;  // CV_32FC3; level l+1 = pyrDown(level l)
    cv::Vec3f mean;
  };
  PlanarScene scene_;
  CameraModel camera_;
  Pyramid target_, floor_;
  double floorPeriodX_ = 0, floorPeriodZ_ = 0;  // metres one floor tile covers
  double maxUndistortedRadius_ = 0;  // normalized radius where the radial model folds back
  // Per supersample, row-major: the undistorted normalized ray (x, y) of the OpenCV camera;
  // NaN where the lens model has no inverse.
  std::vector<cv::Vec2d> rays_;

  void shade(const glm::dmat4& cameraToWorld, const FrameEffects& fx, cv::Mat& supersampled) const;
};

// Camera-to-world (OpenGL camera axes) of a camera at `eye` looking at `target`, with `up`
// pointing up in the image. When `up` is parallel to the view direction, world -Z (then +X)
// is used instead.
[[nodiscard]] glm::dmat4 lookAtCameraToWorld(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up);

// The OpenCV pose (world -> OpenCV camera rotation and translation) of a camera-to-world.
void worldToOpenCvCamera(const glm::dmat4& cameraToWorld, glm::dmat3& rotation, glm::dvec3& translation);

// Where `p` appears in the image: cv::projectPoints with the camera's distortion. For a
// point behind the camera the result is meaningless (check the depth yourself).
[[nodiscard]] glm::dvec2 projectWorldPoint(const CameraModel& camera, const glm::dmat4& cameraToWorld, glm::dvec3 p);

}  // namespace marionette::ar::synthetic
