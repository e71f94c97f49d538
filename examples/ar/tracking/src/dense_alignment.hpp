// The pose of a planar target from all of its pixels at once, with the frame's motion blur in
// the model: what the markerless tracker measures where a smear defeats KLT on corners.
//
// Why: past 25 px of smear a corner's window holds no texture along the smear and slides along
// it; the fits that survive are loose and 2-20 deg off (docs/tracking.md). A smeared image
// still carries the target's whole layout: its blurred edges and blobs, thousands of pixels
// that all move with one pose. Aligning the keyframe, blurred per pixel along the image's
// measured motion, to the frame uses all of them (the blur-aware direct alignment of Park,
// Lepetit and Woo's ESM-Blur, here with the blur taken from the frame-to-frame motion instead
// of estimated jointly).
//
// How: at each pyramid level from coarse to fine, frame pixels sampled over the target's
// projection; a pixel's model is the mean of the keyframe along its smear, centred (the pose is
// the exposure's middle). The smear is the image motion of the camera's turn over the exposure,
// a rotation estimated with the pose (9 parameters): started from the image's motion since the
// last frame times a guess of the exposure, it settles at the turn the frame's blur shows (the
// exposure is unknown, and a turn speeds up or slows down within a frame). Gain and bias fitted
// by least squares; Gauss-Newton with a Levenberg-Marquardt damping, Huber weights (hands,
// glare). The gradient of the blurred model is the blurred gradient, and its derivative along
// the smear the gradient's first moment along it: each step is one pass over the samples.
#pragma once
#include <array>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "lucas_kanade.hpp"
#include "planar_geometry.hpp"

namespace marionette::ar {

struct DenseAlignmentOptions {
  int coarseLevel = 3;    // of the frame's pyramid: the first level aligned (80 x 60 for 640 x 480)
  int fineLevel = 1;      // the last one
  int iterations = 10;    // Gauss-Newton steps per level at most
  int maxSamples = 2500;  // frame pixels per level (sampled on a grid with a stride to keep to it)
  int maxTaps = 24;       // samples of the keyframe along a pixel's smear (one every 1.5 px up to 34 px)
  double huber = 1.5;     // Huber's threshold, in robust standard deviations of the residual
  // Before the first level's steps, the target's shift is searched this far around the start
  // (pixels of that level; 6 at 80 x 60 is +-48 px, 5 deg at fx 525): Gauss-Newton's basin on
  // a textured target is a pixel or two of the level, the prediction may be off by more.
  int searchRadius = 6;
  // The longest turn over an exposure believed (radians; 0.15 is 9 deg, 270 deg/s over 1/30 s):
  // a step past it is refused (a hand over the target can be explained by a smear of everything).
  double maxSmearTurn = 0.15;
  // The turn over the exposure fitted with the pose (true), or kept as given (false: the pose
  // alone, under the smear the image's measured motion makes).
  bool fitSmear = true;
  // The smear's taps eight samples at a time with AVX2 where the CPU has it (the same bits;
  // false for the scalar loop, which the tests compare it with).
  bool wide = true;
};

// The keyframe: its grey pyramid (level l is level 0 halved l times) and the mapping from the
// plane (X, Z metres) to its level-0 pixels.
struct DenseTarget {
  std::span<const cv::Mat> levels;
  cv::Matx33d planeToImage;
};

struct DenseAlignment {
  PlanarPose pose;
  double zncc = 0;       // model against frame over the samples at the fine level, -1..1
  double sigma = 0;      // robust standard deviation of the residual, grey levels
  int samples = 0;       // at the fine level
  double inlierShare = 0;  // of the samples with a full Huber weight
  double visibleShare = 0;  // of the keyframe's area, seen (in the image) by the samples
  double frameShare = 0;    // of the frame, covered by those samples
  // Agreement by parts: the samples' extent cut into kPartGrid x kPartGrid parts; a part counts
  // when its model varies (texture to judge by) and agrees when its own ZNCC (its own gain and
  // bias) is high. A hand hides some parts and leaves the rest agreeing; a wrong pose
  // misaligns the texture everywhere.
  static constexpr int kPartGrid = 4;
  int parts = 0;             // textured parts with enough samples
  int agreeingParts = 0;     // of them, ZNCC >= kPartAgreement
  double agreeingSpan = 0;   // the agreeing parts' extent over the grid, narrower axis, 0..1
  cv::Vec3d smearTurn;   // the camera's turn over the exposure, as the frame's blur shows it
  double smearPx = 0;    // the mean smear over the samples, level-0 pixels
  int renders = 0;       // of the model (its cost: one pass over the samples and their taps)
  // First order, from the last step's normal equations: sigma^2 H^-1 times the samples that one
  // independent measurement spans (the smear correlates neighbours), then mapped to the world:
  // row-major 6x6 of (rotation vector in world axes, radians; camera position, metres).
  std::array<double, 36> covariance{};
  double positionSigma = 0, rotationSigmaDeg = 0;
  // The same from the agreeing parts' samples alone: what a pose that only those parts support
  // knows (the others' samples, on a hand, add terms to H but no information). False where no
  // part agrees or their normal equations are singular.
  std::array<double, 36> agreeingCovariance{};
  bool haveAgreeingCovariance = false;
};

// The camera's turn over the exposure from the image's motion over a frame interval (last
// frame's pixel -> this one's, read as a turn: the rotation nearest K^-1 M K) times the
// exposure's share of the interval.
[[nodiscard]] cv::Vec3d smearTurnFromMotion(const cv::Matx33d& K, const cv::Matx33d& imageMotion, double exposure) noexcept;

// The parts of a dense alignment's samples (dense_alignment.cpp), and a mark per part.
struct DensePartGrid;
using DensePartMask = std::array<bool, DenseAlignment::kPartGrid * DenseAlignment::kPartGrid>;

class DenseAligner {
 public:
  // Sizes the buffers for `params.maxSamples` (allocates: the only call that does).
  void reserve(const DenseAlignmentOptions& params);

  // From `start`, the pose whose blurred keyframe best explains `frame` (a pyramid of the
  // pinhole image with at least params.coarseLevel levels), and the camera's turn over the
  // exposure from `smearTurn` (rotation vector, camera axes; 0: a sharp frame, kept sharp).
  // False when the target shows too few pixels, the steps diverge, or the result is not
  // finite. Deterministic; allocates nothing once reserved.
  bool align(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame, const cv::Vec3d& smearTurn,
             const PlanarPose& start, const DenseAlignmentOptions& params, DenseAlignment& out) noexcept;

  // The evidence at `pose` as it is (nothing fitted but gain and bias): the keyframe blurred by
  // `smearTurn`, rendered at params.fineLevel, against the frame. Fills zncc, sigma, samples,
  // visibleShare and the parts' agreement (out.pose = pose, no covariance). False when the target
  // shows too few pixels there. Allocates nothing once reserved.
  bool verify(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame, const cv::Vec3d& smearTurn,
              const PlanarPose& pose, const DenseAlignmentOptions& params, DenseAlignment& out) noexcept;

  // A start for align() where the start is only a guess among several (the poses of the way out,
  // for the way back): at params.coarseLevel, `start` turned by the best shift within
  // params.searchRadius, and that shift's score (align's own search's: the mean ZNCC of the
  // better half of the textured parts). False when the target shows too few pixels there or no
  // shift correlates. Allocates nothing once reserved.
  bool probe(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame, const cv::Vec3d& smearTurn,
             const PlanarPose& start, const DenseAlignmentOptions& params, PlanarPose& shifted, double& score) noexcept;

 private:
  struct Sample {
    float x = 0, y = 0;        // frame-level pixel
    // d(pixel)/d(camera motion): the image motion of the plane point seen here per radian of a
    // turn and per metre of a move of the camera (camera axes), u's row then v's.
    std::array<float, 12> motion{};
    float dx = 0, dy = 0;      // its smear over the exposure, level pixels
    float frame = 0;           // the frame's value there
    float model = 0;           // the blurred keyframe there
    float gx = 0, gy = 0;      // the blurred keyframe's gradient, per frame-level pixel
    float mx = 0, my = 0;      // the gradient's first moment along the smear (tap offset times gradient)
    bool valid = false;
  };
  std::vector<Sample> samples_;
  std::vector<float> scratch_;
  std::size_t capacity_ = 0;

  struct Level;
  bool prepareLevel(const cv::Matx33d& K, const DenseTarget& target, const ImagePyramid& frame, const PlanarPose& pose,
                    int level, const DenseAlignmentOptions& params, Level& out) noexcept;
  int render(const Level& level, const PlanarPose& pose, const cv::Vec<double, 6>& smear, int maxTaps, bool wide) noexcept;
  // The rendered samples' best integer shift against the frame (ZNCC), applied to `pose` as a
  // turn of the camera about its centre, and its score. False when no shift correlates.
  bool searchShift(const Level& level, int radius, PlanarPose& pose, double& score) noexcept;
  [[nodiscard]] double meanSmearOf(const Level& level) const noexcept;  // over the valid samples, level pixels
  // Counts the parts of `grid` (partGridOf the level's samples); `agreeing` (when given) marks
  // the agreeing ones.
  void judgeParts(const Level& level, const DensePartGrid& grid, DenseAlignment& out,
                  DensePartMask* agreeing = nullptr) const noexcept;
  // visibleShare and frameShare of `samples` valid samples on the level's grid.
  static void noteCoverage(const Level& level, int samples, DenseAlignment& out) noexcept;
};

}  // namespace marionette::ar
