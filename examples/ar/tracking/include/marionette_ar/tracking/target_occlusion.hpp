// Which pixels of a tracked planar target are hidden by something in front of it (a hand, an
// object): an occlusion mask in the frame's pixels at a reduced resolution, for the renderer to
// hide the parts of a character that stand behind it (docs/tracking.md, "Occlusion over the
// target").
//
// What it knows: the reference image of the target (the markerless map's keyframe 0) and the
// pose the tracker drew. Wherever the target should show, the frame is compared with the
// reference warped into the view: where they agree the target is visible, where they do not
// something hides it. Nothing is known off the target (no depth), and a textureless part of the
// target hidden by something of the same grey level cannot be told from the target itself.
//
// How, per mask pixel (scale x scale frame pixels; 4 by default: 160 x 120 for 640 x 480):
//  1. The frame averaged over the pixel's block (grey from RGB by OpenCV's RGB2GRAY weights), and
//     the reference sampled where the pixel's centre ray meets the target (the lens model undone:
//     the mask is in the frame's own, distorted, pixels), trilinearly from the pyramid level that
//     matches the block's footprint, with the share of the block that lies on the target.
//  2. The pose's residual error as a shift field: for each of 3 x 3 parts of the target's image,
//     the shift within +-searchRadius mask pixels (sub-pixel, by a parabola) at which the
//     reference correlates best with the frame; parts without texture, or hidden, take the
//     whole's.
//  3. The frame's blur relative to the reference (motion), from the gradient structure tensors of
//     both over the parts that show the target (each normalised by its trace): the reference is
//     blurred along the direction that lost most energy, by the length that loses as much, when
//     that makes those parts agree better.
//  4. The verdict. Where the reference has texture (its window's standard deviation at least
//     texturedSigma grey levels, in the frame's units), the normalised cross-correlation over the
//     window and over 3 x 3 (gain, bias and contrast cancel): hidden from hiddenNcc down, visible
//     from visibleNcc up, and a pixel whose own value agrees with the reference stays visible
//     unless its window is clearly hidden. Where it is flat (at most flatSigma), intensity alone
//     decides: the pixel against the reference mapped by the gain and bias fitted over the windows
//     that clearly show the target (a least-squares line through their means, refitted without
//     outliers), and texture in the frame where the reference has none. Between the two, a blend.
//     Everywhere, a pixel that disagrees with that mapping by more than a misalignment of a mask
//     pixel explains (a finger across a window that otherwise correlates) is hidden. Frame blocks
//     that are clipped (grey >= 250 or <= 3) are left out; with more than a quarter of the target
//     clipped, nothing is said hidden.
//  5. Pixels without a verdict take their neighbours', a 3 x 3 median, a closing (3 x 3), a
//     feather (a [1 2 1] blur, `featherPasses` times), times the share of the block on the target.
//  A target covering more than maxTargetPixels is worked at twice the scale, and upsampled.
//
// Per frame: no allocation (every buffer is sized at construction), no exception, the same bits
// for the same inputs (nothing is kept from one frame to the next), on the calling thread. Only
// the mask pixels around the target's image are worked on: 1.0 ms for a 640 x 480 frame whose
// target spans a third of its width, 2.1 ms at worst (a quarter of the frame, smeared), and a
// larger target is worked at twice the scale (maxTargetPixels) (docs/tracking.md).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/image_view.hpp"

namespace marionette::ar {

struct PlanarMap;

struct OcclusionSettings {
  int scale = 4;       // frame pixels per mask pixel along each axis, 2 .. 16
  int window = 5;      // side of the comparison window, mask pixels, odd, 3 .. 9
  int searchRadius = 1;  // the pose's residual shift searched, mask pixels, 0 .. 3
  // Textured windows: NCC at or below hiddenNcc is hidden (1), at or above visibleNcc visible (0).
  // The NCC is the window's and the 3 x 3 one's, this share the latter's (finer, noisier).
  double hiddenNcc = 0.4, visibleNcc = 0.7;
  double fineWeight = 0.7;
  // The reference window's standard deviation (frame grey levels): at or below flatSigma the
  // window is judged by intensity alone, at or above texturedSigma by NCC alone.
  double flatSigma = 3.0, texturedSigma = 7.0;
  // The intensity tolerance: meanTolerance grey levels plus meanToleranceShare of the predicted
  // value (the reference's, gain and bias applied). Flat windows: a pixel off its prediction by
  // the tolerance is hidden (by half of it, visible); so is one whose window's standard deviation
  // exceeds the reference's by textureTolerance. Any pixel: off by 0.7 of the tolerance plus its
  // reference gradient (a mask pixel's misalignment), hidden.
  double meanTolerance = 14.0, meanToleranceShare = 0.12;
  double textureTolerance = 8.0;
  bool matchBlur = true;  // step 3 (off: the reference as sampled)
  int featherPasses = 2;  // step 5's soft edge, 0 .. 8
  // Where the target covers more mask pixels than this (5000: 26 % of a 640 x 480 frame at scale
  // 4), the mask is computed at twice the scale (at most 16) and upsampled to this one: the cost
  // stays that of a target a quarter of the size, which still has at least 1250 mask pixels.
  // 0: never.
  int maxTargetPixels = 5000;

  // What is out of range, empty when usable.
  [[nodiscard]] std::string problem() const;
};

// A mask in the frame's pixels: mask pixel (u, v) covers frame pixels [scale u, scale u + scale)
// x [scale v, scale v + scale) (the last row and column may cover fewer). As a texture over the
// frame: frame pixel (x, y) is at texture coordinates ((x + 0.5) / (scale width),
// (y + 0.5) / (scale height)).
struct OcclusionMask {
  int width = 0, height = 0;  // ceil(frame width / scale), ceil(frame height / scale)
  int scale = 4;
  int computedScale = 4;  // the scale the verdicts were made at: scale, or twice it (maxTargetPixels)
  // 255 where the target should show but something hides it, 0 where it shows or where there
  // is no target, values between at edges; width bytes a row, rows top to bottom. Valid until
  // the next update of whatever made it.
  const std::uint8_t* pixels = nullptr;
  // A pose was given and some of the target is in the frame (otherwise every pixel is 0).
  bool targetInView = false;
  double targetPixels = 0;  // mask pixels on the target (the coverage summed)
  double hiddenShare = 0;   // of those, the share hidden (the mask summed over targetPixels)
  // The share of the target's mask pixels whose frame block is clipped (over- or under-exposed:
  // grey >= 250 or <= 3), left out of the comparison. Past a quarter, nothing is said hidden.
  double clippedShare = 0;
  // What the comparison measured: the frame's grey as gain x reference + bias; the blur given to
  // the reference (mask pixels along angleRad, 0 along +x, pi/2 along +y); the whole target's
  // residual shift from the pose (mask pixels: frame pixel p shows what the pose puts at p + shift).
  double gain = 1, bias = 0;
  double blurLength = 0, blurAngleRad = 0;
  double shiftX = 0, shiftY = 0;

  [[nodiscard]] std::uint8_t at(int u, int v) const noexcept {
    return pixels[static_cast<std::ptrdiff_t>(v) * width + u];
  }
};

class TargetOcclusion {
 public:
  // `reference`: the target's grey image (1 channel), whose pixel centres (u, v) lie on the
  // plane at planeToImage^-1 (u, v, 1) (row-major 3 x 3: (X, Z, 1) metres -> pixel, as a
  // PlanarKeyframe's). Null with an error in `diagnostics` for a camera with a problem(), a
  // reference that is not grey or under 16 x 16, a singular mapping or settings out of range.
  [[nodiscard]] static std::unique_ptr<TargetOcclusion> create(const CameraModel& camera, const ImageView& reference,
                                                               const std::array<double, 9>& planeToImage,
                                                               const OcclusionSettings& settings,
                                                               Diagnostics& diagnostics);
  // From a markerless map: its keyframe 0 (the reference image of the target).
  [[nodiscard]] static std::unique_ptr<TargetOcclusion> create(const CameraModel& camera, const PlanarMap& map,
                                                               const OcclusionSettings& settings,
                                                               Diagnostics& diagnostics);
  ~TargetOcclusion();
  TargetOcclusion(const TargetOcclusion&) = delete;
  TargetOcclusion& operator=(const TargetOcclusion&) = delete;

  // The mask of `frame` (grey, RGB or RGBA as the tracker takes it; camera().width x height)
  // seen from `cameraToWorld` (tracker.hpp's conventions: the pose the tracker gave). False,
  // and an empty mask (all 0, targetInView false), for an invalid frame or one of another size,
  // or a pose that is not finite. An empty mask too (true) when the target is out of view.
  bool update(const ImageView& frame, const glm::dmat4& cameraToWorld) noexcept;
  // An empty mask (a frame without a pose).
  void clear() noexcept;
  [[nodiscard]] const OcclusionMask& mask() const noexcept;
  [[nodiscard]] const CameraModel& camera() const noexcept;
  [[nodiscard]] const OcclusionSettings& settings() const noexcept;

 private:
  struct Impl;
  TargetOcclusion(std::unique_ptr<Impl> impl, std::unique_ptr<Impl> coarse) noexcept;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<Impl> coarse_;  // at twice the scale (maxTargetPixels), or none
};

}  // namespace marionette::ar
