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
//
// Exposures (renderExposure): the sharp renders of sub-frames (the camera and the occluders at
// instants spread over the exposure) averaged in float before the effects and the quantization,
// so that motion blur varies across the image as a real camera's does; occluders of any shape
// (a hand and its forearm: a picture with alpha on a plane above the floor) composited over the
// scene with parallax.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <opencv2/core.hpp>

#include "marionette_ar/tracking/camera_model.hpp"
#include "tracking/scene_samples.hpp"

namespace marionette::ar::synthetic {

struct PlanarScene {
  cv::Mat target;             // RGB8 (or grey 8-bit) photo lying on the floor
  double targetWidth = 0.3;   // metres, along +X
  cv::Mat floor;              // RGB8 (or grey) texture tiled on the floor; empty: flat grey 128
  double floorMetresPerPixel = 0.002;
};

// Applied in this order after the geometric rendering: defocus, blur, gain, channel gains,
// noise, JPEG.
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
  // The stress sequences' (stress_scenarios.hpp); the defaults change nothing.
  cv::Vec3d channelGain{1, 1, 1};  // R, G, B multipliers after gainEv (a white balance), saturated
  double defocusPx = 0;            // radius of a disk blur (a defocused lens), pixels; < 0.5: none
};

// An opaque shape between the camera and the floor (a hand and its forearm): a picture with
// alpha lying on a plane anywhere above the floor (Y > 0 wherever alpha > 0, so that it is
// always in front of the floor). Texel (a, b) (centres at integers) is at
//   centre + (a - (cols - 1) / 2) axisU + (b - (rows - 1) / 2) axisV,
// fetched bilinearly (no mip-mapping: made for shapes seen at about their texel size or larger).
struct Occluder {
  cv::Mat texture;  // CV_32FC4: R, G, B premultiplied by alpha (0..255 levels), alpha 0..1
  glm::dvec3 centre{0.0};
  glm::dvec3 axisU{0.001, 0, 0};  // world step of one texel along the columns
  glm::dvec3 axisV{0, 0, 0.001};  // along the rows
};

// An RGBA8 picture (straight alpha) as an Occluder's texture.
[[nodiscard]] cv::Mat premultipliedTexture(const cv::Mat& rgba8);

// One instant of an exposure: the camera and the occluders then.
struct SubFrame {
  glm::dmat4 cameraToWorld{1.0};
  std::vector<Occluder> occluders;
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

  // One exposure: the sub-frames' renders averaged in float, then fx's effects, then rounded.
  // One sub-frame is render() with its occluders (2x2 supersampled). With several, sub-frame k
  // takes one sample a pixel, at position k % 4 of the 2x2 pattern (the average antialiases, at
  // a quarter of the cost per sub-frame): 4, 8, 12 ... sub-frames of a still camera give
  // render()'s picture within rounding. Throws std::invalid_argument without a sub-frame or for
  // an occluder texture that is not CV_32FC4.
  void renderExposure(const std::vector<SubFrame>& subFrames, const FrameEffects& fx, cv::Mat& outRgb) const;
  // The same exposure before fx's effects and the rounding: CV_32FC3, camera-sized, RGB.
  void renderLinear(const std::vector<SubFrame>& subFrames, const FrameEffects& fx, cv::Mat& linear) const;

  // Share of the target's area (a 96 x ~72 grid of points over it) that is in front of the
  // camera and projects inside the image through the lens. The occluder does not count.
  [[nodiscard]] double visibleTargetFraction(const glm::dmat4& cameraToWorld) const;
  // Share of the target's area (the same grid) in view but hidden behind an occluder (alpha
  // above one half on the line of sight): visibleTargetFraction minus this is what shows.
  [[nodiscard]] double occludedTargetFraction(const glm::dmat4& cameraToWorld,
                                              const std::vector<Occluder>& occluders) const;

  // The truth of which pixels show the target and which of those something hides (for the
  // occlusion mask's tests, target_occlusion.hpp): per pixel of the camera image, over the same
  // samples as renderExposure (render()'s 2x2 for one sub-frame; sample k % 4 of sub-frame k for
  // several), the share whose line of sight reaches the target (`onTarget`), and the same share
  // weighted by the opacity in front of the target there (`hidden`: fx's occluder rectangle
  // opaque, Occluders by their alpha, composited as the render composites them). CV_32FC1,
  // camera-sized, 0..1. Renders nothing: what render() and renderExposure() give is unchanged.
  void targetCoverage(const std::vector<SubFrame>& subFrames, const FrameEffects& fx, cv::Mat& onTarget,
                      cv::Mat& hidden) const;

  // Whether the scene samples are taken four at a time (AVX2, scene_samples.hpp) where the CPU
  // can: the same bits either way; the bit-identity test renders both ways.
  void useWideSamples(bool wide) noexcept { wide_ = wide && sceneSamplesWideAvailable(); }
  [[nodiscard]] bool wideSamples() const noexcept { return wide_; }

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
  // NaN where the lens model has no inverse. Without distortion, per column and per row instead.
  std::vector<cv::Vec2d> rays_;
  std::vector<double> columnRays_, rowRays_;
  [[nodiscard]] cv::Vec2d ray(int x, int y) const noexcept;  // supersample (x, y)'s
  // The pyramids as the wide samples read them: the same texels as RGBA, one load each
  // (SampleLevel: bytes where the level's values are whole bytes).
  std::vector<cv::Mat> targetRgba_, floorRgba_;
  std::vector<SampleLevel> targetLevels_, floorLevels_;
  bool wide_ = sceneSamplesWideAvailable();

  struct View;  // one pose's plane mappings (synthetic_sequence.cpp)
  [[nodiscard]] View view(const glm::dmat4& cameraToWorld, const FrameEffects& fx,
                          const std::vector<Occluder>& occluders) const;
  [[nodiscard]] cv::Vec3f sceneSample(const View& v, int x, int y) const;  // supersample (x, y) without occluders
  // With them; `scene`, when given, is sceneSample(v, x, y) already taken.
  [[nodiscard]] cv::Vec3f sample(const View& v, int x, int y, const cv::Vec3f* scene = nullptr) const;
  // Supersamples (x + stride * i, y), i < count, into out: sample()'s colours.
  void samples(const View& v, int x, int stride, int y, int count, cv::Vec3f* out) const;
  // Supersample (x, y): 1 when its ray reaches the target (else 0), and that times the opacity
  // of the occluders in front (targetCoverage).
  void coverageSample(const View& v, int x, int y, float& onTarget, float& hidden) const;
  void shade(const View& v, cv::Mat& supersampled) const;
  // Per sub-frame k, supersample (2x + dx, 2y + dy) of every pixel (x, y) added to a
  // camera-sized sum, (dx, dy) cycling through the 2x2 positions.
  void accumulateExposure(const std::vector<View>& views, cv::Mat& sum) const;
  void finish(cv::Mat& image, const FrameEffects& fx, cv::Mat& outRgb) const;  // the effects, rounding
  // The target's grid points (the visibility grid) that are in view, and the grid's size.
  [[nodiscard]] std::vector<glm::dvec3> targetPointsInView(const glm::dmat4& cameraToWorld, int& gridPoints) const;
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
