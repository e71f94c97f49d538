// The environment light estimated from the AR camera's own frames (issue 44): 9 SH radiance
// coefficients (RGB, prt::sh_lighting's convention: index l(l+1)+m, +Y polar axis) built from
// the pixels the camera sees along each ray, frame after frame (docs/ar-renderer.md,
// "Light estimated from the camera"; its accuracy: docs/accuracy.md).
//
// Per frame (addFrame): a sparse grid of the image (32 x 24 samples by default, each the mean of
// a 4 x 4 set of pixels of its block) is decoded from sRGB to linear, divided by the frame's
// exposure, and each sample's ray is turned into a world direction by the pose. The samples
// land in a lat-long grid of 32 x 16 cells (environment_map.hpp's mapping), each cell holding
// its newest radiance, how much of it was seen and when. The estimate is then the grid, with
// its unseen part completed by the prior, projected onto 9 SH coefficients with the exact
// per-cell integrals of prt::pixelBasisIntegrals.
//
// Units: the estimate's radiance is the camera's linear pixel value (sRGB-decoded, 0..1 for
// 0..255) at exposure 1, i.e. the camera's linear value divided by the exposure given with the
// frame. The exposure is relative: any fixed reference (e.g. exposure time x gain of the first
// frame) works, as long as every frame uses the same one. Give 1 for a camera with a locked
// exposure. The white balance must stay the same over the frames (a locked one, or
// GrayWorld in cameraMatchedRadiance).
//
// The prior (unseen directions). Light is stratified by elevation far more than by azimuth (sky
// above, walls and horizon around, floor or ground below), so an unseen cell takes the mean of
// the seen cells of its own row (same elevation band, weighted by the solid angle seen); a row
// that is less than 10 % seen takes the mean of the nearest row that is (the zenith cap, which a
// hand-held camera rarely sees, continues the highest band seen; the nadir the lowest). A cell
// seen in part is its seen radiance over the part seen and the row's prior over the rest.
// Nothing seen: the estimate is zero and `valid` is false.
//
// Temporal behaviour. A cell seen again moves toward the new observation by
// alpha = s * (1 - exp(-dt / noiseTimeConstant)), dt the time since the cell was last seen
// (0.1 s: alpha = 0.28 at 30 fps, a mean over about 6 frames, against sensor noise) and s the
// share of the cell this view sees against the most any view saw (1 for a still camera); when
// the observation differs from the cell by more than changeThreshold (25 %, relative, any
// channel, over a floor of darkNoiseFloor) the cell takes it at once (alpha = s): a lamp
// switched off is followed in the next frame that sees it. Cells out of view keep their last
// value (no expiry: a change out of view is not seen).
//
// Clipped highlights. A pixel with any channel >= saturationLevel (250) is clipped; its channels
// at or above that level count clippedFactor (2) times their value, a guess for a highlight of
// unknown strength. A clipped observation only says "at least": it does not replace a cell
// that an observation at a darker exposure measured (a higher clip level) at a value at least
// that bound; so with an auto-exposing camera a window seen unclipped while the camera looked
// at it stays measured when a darker view clips it. The share of the seen sphere whose cells
// hold clipped samples is reported.
//
// Per frame: no allocation (the grid is fixed-size arrays inside the object), no exceptions,
// deterministic (one thread, a fixed order). Bad input is rejected with a reason and changes
// nothing. Cost: about 0.13 ms per 640x480 frame on one core (docs/accuracy.md).
#pragma once
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "marionette/prt/sh_lighting.hpp"
#include "marionette_ar/background_source.hpp"

namespace marionette::ar {

// RGB8 pixels, rows from the top, `strideBytes` from one row to the next (0: width * 3).
struct CameraImageView {
  const std::uint8_t* rgb = nullptr;
  int width = 0;
  int height = 0;
  std::size_t strideBytes = 0;

  [[nodiscard]] static CameraImageView of(const BackgroundFrame& frame) noexcept {
    return {frame.rgb.data(), frame.width, frame.height, static_cast<std::size_t>(frame.width) * 3};
  }
};

// Pinhole intrinsics in pixels, OpenCV's convention: the centre of the top-left pixel is (0, 0),
// x to the right, y down. Lens distortion is not modelled (a sample lands a few degrees off
// at most near the corners of a typical webcam: far below an 11.25-degree cell).
struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;

  // A centred pinhole with square pixels and this vertical field of view (degrees), as the
  // renderer's CameraPose has.
  [[nodiscard]] static PinholeIntrinsics fromFovY(int width, int height, double fovYDegrees) noexcept;
};

struct CameraLightFrame {
  CameraImageView image;
  // Camera-to-world (world +Y up; the camera looks along its -Z with +Y up, OpenGL). None when
  // tracking is lost: the frame is not used. Only the rotation matters (distant light).
  std::optional<glm::dmat4> cameraToWorld;
  PinholeIntrinsics intrinsics;
  double timeSeconds = 0;  // scene or capture time; a time before the last frame's counts as dt = 0
  double exposure = 1;     // linear camera value per unit of the estimate's radiance (> 0)
};

enum class LightFrameResult {
  Accepted,
  NoPose,          // cameraToWorld is empty (tracking lost)
  EmptyImage,      // no pixels, width or height <= 0, a stride shorter than a row
  BadIntrinsics,   // a focal length not finite or <= 0, the principal point not finite or outside the image
  BadPose,         // a non-finite element, or a rotation part that is not orthonormal (1e-3) with det +1
  BadTime,         // not finite
  BadExposure,     // not finite or <= 0
};
[[nodiscard]] const char* lightFrameResultName(LightFrameResult result) noexcept;

struct CameraLightSettings {
  int samplesX = 32, samplesY = 24;  // the sample grid over the image, 1..64 each
  // A k x k set of pixels averaged per sample, 1..8. (Every pixel of the block was tried: the
  // accuracy table's figures were the same, at five times the cost: docs/accuracy.md.)
  int pixelsPerSample = 4;
  double noiseTimeConstant = 0.1;    // seconds, > 0
  double changeThreshold = 0.25;     // relative change that replaces a cell at once
  double darkNoiseFloor = 0.02;      // camera linear units at the frame's exposure (about sRGB code 40)
  int saturationLevel = 250;         // a channel at or above it is clipped, 1..255
  double clippedFactor = 2.0;        // clipped channels count this times their value, >= 1
  double minRowCoverage = 0.10;      // a row less seen than this takes its prior from the nearest row that is
};

struct CameraLightEstimate {
  prt::ShCoefficients radiance;  // 3 bands; zero until a frame is accepted (see Units above)
  double seenFraction = 0;       // share of the sphere's solid angle seen so far, 0..1
  double clippedFraction = 0;    // share of the seen solid angle whose cells hold clipped samples
  long framesAccepted = 0;
  bool valid = false;            // at least one frame accepted
};

class CameraLightEstimator {
 public:
  static constexpr int kColumns = 32, kRows = 16;  // the direction grid (11.25 degrees a cell)
  static constexpr int kCells = kColumns * kRows;

  explicit CameraLightEstimator(const CameraLightSettings& settings = {});

  // One frame: Accepted (the estimate is updated), or the reason it was ignored (nothing changed).
  LightFrameResult addFrame(const CameraLightFrame& frame) noexcept;
  [[nodiscard]] const CameraLightEstimate& estimate() const noexcept { return estimate_; }
  // Forgets every observation (a new scene).
  void reset() noexcept;

  // The grid, for tests and debugging: column c covers u in [c/32, (c+1)/32] of
  // environment_map.hpp's mapping, row r the polar angle [r, r+1] * 11.25 degrees from +Y.
  struct Cell {
    glm::vec3 radiance{0.0f};  // the newest (smoothed) observation
    float coverage = 0;        // the most of the cell one frame has seen, 0..1
    float clipped = 0;         // share of the stored observation that was clipped
    float clipLevel = 0;       // the radiance at which that observation clipped
    double lastSeen = 0;
  };
  [[nodiscard]] const Cell& cell(int column, int row) const noexcept { return cells_[row * kColumns + column]; }
  // The completed radiance of a cell (its observation and the prior), as the projection uses it.
  [[nodiscard]] glm::dvec3 completedRadiance(int column, int row) const noexcept {
    return completed_[row * kColumns + column];
  }

 private:
  struct FrameCell {
    glm::vec3 sum{0.0f};      // solid-angle-weighted linear radiance, clipped channels extrapolated
    glm::vec3 lower{0.0f};    // the same with clipped channels at their clipped value (a lower bound)
    float weight = 0;         // solid angle seen (sr)
    float clippedWeight = 0;  // solid angle of clipped pixels
  };
  void updateCells(double time, double exposure) noexcept;
  void complete() noexcept;
  void project() noexcept;

  CameraLightSettings settings_;
  std::array<float, 256> linear_{};                  // sRGB code -> linear
  std::array<double, kRows> cellSolidAngle_{};       // per row
  std::array<prt::ShBasis, kCells> cellIntegrals_{};  // the 9 basis integrals per cell
  std::array<Cell, kCells> cells_{};
  std::array<FrameCell, kCells> frame_{};
  std::array<glm::dvec3, kCells> completed_{};
  std::array<int, 64 * 8> columnPixels_{}, rowPixels_{};
  CameraLightEstimate estimate_;
};

// The main light direction of radiance (or irradiance) coefficients: the unit direction of the
// band-1 vector of their luminance (Rec. 709 weights), world space; zero when that vector is zero.
[[nodiscard]] glm::dvec3 mainLightDirection(const prt::ShCoefficients& coefficients) noexcept;

// How the estimate's colour reaches the character.
enum class WhiteBalance {
  Camera,     // as the camera recorded it: right for a camera whose white balance was fixed over
              // the frames; the character takes the colour cast of the real objects around it
  GrayWorld,  // per-channel gains that make the sphere's mean radiance (the DC term) neutral at
              // the same luminance, each gain within [1/4, 4]: for a camera whose white balance
              // was not fixed, or frames that are not white-balanced at all
};

// The exposure and white-balance match. The result is radiance SH in the renderer's linear units
// for a renderer exposure of 1: lit by it, a white (albedo 1) Lambertian surface with normal n
// shades to E(n) / pi (E from prt::irradiance), which is the linear value (sRGB-decoded pixel /
// 255) the camera would record for a white matte card facing n at the exposure `exposure`
// (the current frame's, in the units given to addFrame), before any tone map. So the character
// follows the camera's brightness and colour; a renderer that tone maps (Reinhard, lighting.glsl)
// makes it darker than the camera by that curve. Non-finite or non-positive exposure: 1.
[[nodiscard]] prt::ShCoefficients cameraMatchedRadiance(const prt::ShCoefficients& estimate, double exposure,
                                                        WhiteBalance whiteBalance = WhiteBalance::Camera) noexcept;

}  // namespace marionette::ar
