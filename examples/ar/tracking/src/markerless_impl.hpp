// The markerless tracker's state and its steps (a private header of examples/ar/tracking/src):
// markerless_tracker.cpp runs a frame (predict, track, judge, relocalize) and builds trackers,
// markerless_track.cpp measures a pose from a prediction (KLT against the keyframe, the blur
// model, the evidence), markerless_gates.cpp judges a measurement (evidence, motion model,
// confirmation), markerless_image_motion.cpp carries the pose by the image's own motion,
// markerless_dense.cpp aligns the whole keyframe under a smear, markerless_reentry.cpp searches
// for a target coming back from the poses of the way out, and markerless_map.cpp keeps the
// keyframes (relocalization, map growth).
#pragma once
#include "marionette_ar/tracking/markerless_tracker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "grey_frame.hpp"
#include "hamming_matcher.hpp"
#include "dense_alignment.hpp"
#include "image_shift.hpp"
#include "tilted_views.hpp"
#include "lucas_kanade.hpp"
#include "motion_blur.hpp"
#include "perspective_warp.hpp"
#include "planar_geometry.hpp"
#include "planar_pose.hpp"
#include "pose_filter.hpp"

namespace marionette::ar::markerless {

inline constexpr int kMaxReferenceSide = 1024;  // larger references are scaled down (KLT works at camera scale)
inline constexpr int kCornersPerKeyframe = 500;
inline constexpr int kReferenceLevels = 4;  // the reference at 1, 1/2, 1/4, 1/8: warp from the nearest scale
inline constexpr int kMinRelocalizationInliers = 15;
inline constexpr double kMaxBlurFraction = 0.1;  // longest motion blur modelled, of the frame's width
// How long the background's frame-to-frame motion alone may carry the pose (never given, only
// where tracking starts): a look away and back within it tracks again without relocalizing.
inline constexpr double kMaxChainSeconds = 1.5;
// Frames a keyframe added while tracking may wait for its ORB features (makeKeyframe).
inline constexpr long kMaxFeatureDelayFrames = 10;
inline constexpr int kMinBackgroundPoints = 16;
inline constexpr int kMaxRelocalizationSkips = 3;
inline constexpr double kAwayMarginFraction = 0.25;  // of the image's larger side
// A keyframe seen this much larger than it was taken is replaced by a new one (map extension),
// and counts for less when choosing the keyframe to track against.
inline constexpr double kMaxMagnification = 1.6;
inline constexpr double kLooseFitPx = 0.75;
inline constexpr double kFewAgreeShare = 0.3;  // of the corners tried: fewer agreeing weaken a tight fit
// A dense pose's error is at least this (standard deviations): on a sharp view the alignment is
// 2 mm and 0.12 deg off (dense_alignment_test), however many pixels agree.
inline constexpr double kDenseFloorPositionM = 0.0025;
// Past this smear KLT on corners rarely gives a pose (docs/tracking.md: 13 % at 25-40 px): after a
// dense pose with such a smear, the next frame aligns densely first.
inline constexpr double kDenseFirstSmearPx = 25;
// After the floor gave the pose where the reference failed, the floor goes first for this many
// frames; then the reference is tried first again (the hand may have left).
inline constexpr int kFloorFirstFrames = 8;
// The dense alignment's turn over the exposure against the image's measured motion over the frame
// interval: at most this share of it (an exposure is at most the interval, and the turn's speed
// changes a little within it), about an axis within acos(this) of it.
inline constexpr double kMaxExposureShare = 1.3;
inline constexpr double kMinSmearAxisCosine = 0.8;
// The dense alignment's shift search (pixels of its coarse level) from a start the image's motion
// measured this frame.
inline constexpr int kMeasuredStartSearchRadius = 2;
// A LIMITED KLT pose with the template blurred this much or more is checked by the dense alignment.
inline constexpr double kDenseCheckBlurPx = 10;
// The poses of the way out kept for the re-entry search (newest first), this far apart: the
// dense alignment's shift search covers +-48 px (5 deg at fx 525) around each.
inline constexpr int kExitPathPoses = 16;
inline constexpr double kExitPathStepDeg = 3.0;
inline constexpr double kExitPathStepShare = 0.05;  // ... or the camera moved this share of its distance
// The re-entry search's best start must correlate this well (align's search score; its own search
// keeps 0.3): a start 25 deg off scored 0.66 under a smear (dense_alignment_test).
inline constexpr double kMinReentryScore = 0.8;
inline constexpr double kDenseFloorRotationRad = 0.15 * 3.14159265358979323846 / 180;  // inliers' rms past which the fit is a smeared template's

// cv::Mat::setTo allocates a scratch buffer on every call: this does not.
void fill(cv::Mat& image, std::uint8_t value) noexcept;

// What the map keeps per keyframe for the per-frame path, prepared once.
struct KeyframeData {
  std::vector<cv::Mat> levels;  // grey image pyramid (level 0 views the map's bytes)
  std::vector<cv::Mat> denseLevels;  // the same and coarser, down to 16 px: the dense alignment's
  cv::Matx33d planeToImage, imageToPlane;
  std::vector<cv::Point2f> corners;       // level-0 pixels
  std::vector<cv::Point2f> cornerPlane;   // (X, Z) metres
  cv::Mat descriptors;                    // ORB, one row per feature
  std::vector<cv::Point2f> featurePixels;
  glm::dvec3 cameraPosition{0.0};  // the camera that took it (keyframe 0: none)
  double meanGrey = 128;
  bool reference = false;
  // The error the keyframe's own pose left in its plane mapping (rotation vector in world axes,
  // then the camera position; zero for the reference): a pose measured against it carries that
  // error too, whatever its own inliers say.
  std::array<double, 36> covariance{};
  // From its camera to the floor at its image's centre, metres: the lever through which an
  // error of its orientation moves the floor points it maps (and so a pose measured from them).
  glm::dvec3 lever{0.0};
};

// A pose measured against a keyframe other than the reference carries that keyframe's own error
// (independent of the frame's noise: no number of inliers or pixels averages it away). Adds it,
// with its lever's term, to a covariance in planar_pose.hpp's layout (markerless_track.cpp).
void addKeyframeError(const KeyframeData& kf, double covariance[36]) noexcept;

// One measured pose and the evidence the gates judge it by.
// Adds the time from construction to destruction to `ms` (the per-stage times of FrameStats).
class StageTimer {
 public:
  explicit StageTimer(double& ms) noexcept : ms_(ms), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() { ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count(); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& ms_;
  std::chrono::steady_clock::time_point start_;
};

struct Measurement {
  PlanarPose pose;
  double rms = 0;
  int inliers = 0, tried = 0;
  double spread = 0;  // the inliers' narrowest spread over the tried corners
  double ncc = 0;     // mean normalized cross-correlation of template and frame at the inliers
  std::array<double, 36> covariance{};
  double positionSigma = 0, rotationSigmaDeg = 0;
  bool haveCovariance = false;
  bool dense = false;        // from the dense alignment: ncc over all the target's pixels
  double inlierShare = 0;    // dense: the pixels within Huber's threshold
  double visibleShare = 0;   // dense: the keyframe's area in view
  double frameShare = 0;     // dense: the frame's area the keyframe's samples cover
  bool onFloor = false;      // dense: against a keyframe of the floor, not the reference
  // How much of the keyframe is seen: of the reference, its area in view; of a floor keyframe (a
  // camera frame, whose area on the plane may reach the horizon), that or the frame it covers.
  [[nodiscard]] double viewShare() const noexcept { return onFloor ? std::max(visibleShare, frameShare) : visibleShare; }
  int parts = 0, agreeingParts = 0;  // dense: textured parts of the target, and those that agree
  double agreeingSpan = 0;   // dense: the agreeing parts' extent, narrower axis, 0..1
  double smearPx = 0;        // dense: the mean smear over the target, pixels
  double exposure = 0;       // dense: the exposure's share of the frame interval it measured (0: none)
};

// Which keyframe to track against: the one seeing most of the predicted view, and the floor
// keyframe seeing most of it with at least minFloorRetryCorners of its corners in view (-1: none).
struct KeyframeChoice {
  int best = 0;
  int floor = -1;
};

// A pose with its time and uncertainty: the history the motion model works from.
struct StampedPose {
  PlanarPose pose;
  double time = 0;
  std::array<double, 36> covariance{};
  double positionSigma = 0, rotationSigmaDeg = 0;
};

enum class Evidence { None, Limited, Tracking };
enum class Verdict { Rejected, Limited, Tracking, Pending };

inline constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// sqrt of the smaller eigenvalue of the points' covariance: their spread across the narrowest
// direction, pixels.
[[nodiscard]] double narrowestSpread(const std::vector<cv::Point2f>& points) noexcept;

}  // namespace marionette::ar::markerless

namespace marionette::ar {

// Only the markerless_*.cpp files include this header: the names above are theirs.
using namespace markerless;  // NOLINT(google-build-using-namespace)

struct MarkerlessTracker::Impl {
  CameraModel camera;
  MarkerlessSettings settings;
  PlanarMap map;
  std::vector<KeyframeData> keyframes;
  std::vector<TiltedView> tiltedViews;  // of keyframe 0, the reference
  cv::Matx33d K;
  cv::Ptr<cv::ORB> orb;
  GreyFrame grey;
  PoseFilter filter;
  FrameStats stats;

  // Pose history (world -> OpenCV camera). Confirmed poses (TRACKING, newest first) are the
  // motion model's base: only they give a velocity. The anchor is the last measured pose
  // given out (TRACKING or LIMITED), where the next frame's tracking starts. A pending pose is
  // a relocalization (or a strong pose off the motion model) that the next frame must confirm
  // before anything is given from it.
  std::array<StampedPose, 2> confirmed{};
  int confirmedCount = 0;
  StampedPose anchor, pending;
  bool haveAnchor = false, havePending = false;
  bool gaveLast = false;  // the last frame gave a pose (the filter continues from it)
  // The pose given last frame with its uncertainty: where a carried pose starts (the image's
  // motion moves it, and its covariance grows by the carry's error).
  StampedPose lastGiven;
  int carriedFrames = 0;  // consecutive frames given as carried
  // Through this update() call, tracking tries a floor keyframe before the reference: the
  // reference failed and the floor gave the pose (a hand over the target stays a while).
  long floorFirstUntil = -1;
  // Frames since the last pose given through which the image's motion carried it (nothing
  // given, LOST): -1 once that chain broke (no motion measured, a pending pose in between).
  int chainedSinceGiven = -1;
  // The keyframe whose ORB features are still to come (-1: none), and the frame that added it.
  int featuresPending = -1;
  long featuresPendingSince = 0;

  // Buffers reused every frame.
  cv::Mat warped, blurred;
  ImagePyramid templatePyramid;
  // This frame's and the last one's grey pinhole images and pyramids (alternating): the
  // frame-to-frame motion of the whole image corrects the prediction.
  std::array<cv::Mat, 2> frameCopies;
  std::array<ImagePyramid, 2> pyramids;
  int currentFrame = 0;
  bool havePreviousFrame = false;
  // The best estimate of the last frame's pose: the pose given, the pending one, or the
  // background's prediction while nothing was given (chained for at most kMaxChainSeconds).
  PlanarPose previousFramePose;
  bool havePreviousFramePose = false;
  bool previousFrameChained = false;  // that pose is the image motion's, nothing measured
  int relocalizationSkips = 0;        // consecutive frames not relocalized: the target away from the view
  // This frame's pose carried from the last given one by the image's motion alone (no anchor).
  PlanarPose chainPrediction;
  bool haveChainPrediction = false;
  // The last frame-to-frame homography measured (kept while consecutive frames measure one).
  cv::Matx33d lastImageMotion = cv::Matx33d::eye();
  bool haveLastImageMotion = false, imageMotionFound = false;
  bool lastMotionFailed = false;  // this frame's search from lastImageMotion found nothing
  bool imageMotionTried = false;  // this frame measured the image's motion (found or not)
  double lastGivenTime = -1e300;
  // The poses of the way out (given, or carried by the image's motion), newest first, at least
  // kExitPathStepDeg apart: where the re-entry search starts (markerless_reentry.cpp).
  std::array<PlanarPose, kExitPathPoses> exitPath{};
  int exitPathCount = 0;
  std::vector<cv::Point2f> backgroundGrid, backgroundFrom, backgroundTo, backgroundFound;
  std::vector<unsigned char> backgroundStatus, backgroundMask;
  HomographyRansac backgroundRansac;
  [[nodiscard]] const ImagePyramid& framePyramid() const noexcept { return pyramids[static_cast<std::size_t>(currentFrame)]; }
  LucasKanade lk;
  PlanarPoseSolver solver;
  MotionBlur blur;
  MotionBlurScratch blurScratch;
  DenseAligner dense;
  DenseAlignmentOptions denseParams;
  // The exposure's share of the frame interval, as the dense alignment last measured it.
  double exposure = 0.5;
  bool exposureMeasured = false;  // by an accepted dense pose (0.5 until then: a guess)
  double lastDenseSmearPx = 0;    // the last frame's pose was dense, under this smear
  std::vector<cv::Point2f> levelPoints;
  std::vector<cv::Point2f> predicted, found, planePoints, inlierPlane, inlierImage, inlierFrom, blurFrom, blurTo;
  std::vector<int> cornerIndex;
  std::vector<unsigned char> status, mask;
  std::vector<cv::KeyPoint> frameKeypoints;
  cv::Mat frameDescriptors;
  std::vector<HammingMatch> matches;
  cv::Matx33d homography;
  // The occlusion mask (occlusionMask()): made on its first call, computed once per frame asked.
  std::unique_ptr<TargetOcclusion> occlusion;
  long frames = 0, occlusionFrame = -1;  // update() calls; the one the mask was computed for
  bool framePosed = false;               // the last update() gave a pose
  glm::dmat4 framePose{1.0};             // that pose before the smoothing

  Impl(const CameraModel& c, const MarkerlessSettings& s)
      : camera(c), settings(s), filter(s.smoothingMinCutoffHz, s.smoothingBeta) {
    K = cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
    orb = cv::ORB::create(s.relocalizationFeatures, 1.2f, 6, 19, 0, 2, cv::ORB::FAST_SCORE, 19, 15);
    grey.configure(c);
    blurScratch.reserve(c.width, c.height);
    denseParams.coarseLevel = std::min(denseParams.coarseLevel, s.pyramidLevels);
    denseParams.fineLevel = std::min(denseParams.fineLevel, denseParams.coarseLevel);
    dense.reserve(denseParams);
    // Sized once: the per-frame path allocates nothing (tracking_allocation_test).
    for (std::size_t i = 0; i < 2; ++i) {
      frameCopies[i].create(c.height, c.width, CV_8UC1);
      pyramids[i].configure(c.width, c.height, s.pyramidLevels);
    }
    // A 12 x 9 grid over the frame, 24 px in from its border: the background's sample points.
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 12; ++i)
        backgroundGrid.emplace_back(static_cast<float>(24 + (c.width - 48) * (i + 0.5) / 12),
                                    static_cast<float>(24 + (c.height - 48) * (j + 0.5) / 9));
    for (auto* v : {&backgroundFrom, &backgroundTo, &backgroundFound}) v->reserve(backgroundGrid.size());
    backgroundStatus.reserve(backgroundGrid.size());
    backgroundMask.reserve(backgroundGrid.size());
    backgroundRansac.reserve(backgroundGrid.size());
    templatePyramid.configure(c.width, c.height, s.pyramidLevels);
    const std::size_t points = static_cast<std::size_t>(std::max(s.trackedCorners, s.relocalizationFeatures) + 64);
    solver.reserve(points);
    matches.reserve(static_cast<std::size_t>(s.relocalizationFeatures) + 64);
    mask.reserve(points);
    status.reserve(points);
    for (auto* v : {&predicted, &found, &planePoints, &inlierPlane, &inlierImage, &inlierFrom, &blurFrom, &blurTo, &levelPoints})
      v->reserve(points);
  }

  void prepareKeyframe(std::size_t i);
  // A keyframe's ORB features (from its grey image) and their per-frame copy.
  void addFeatures(PlanarKeyframe& k);
  void prepareFeatures(std::size_t i);
  // The ORB features of the keyframe added last, when they are still to come (featuresPending;
  // where OpenCV fails, the keyframe keeps none). inFrame: called by update(), noted in this
  // frame's stats.
  void finishKeyframeFeatures(bool inFrame) noexcept;
  // Matches this frame's ORB features to a feature set; the pose from the best match so far goes
  // to `out` when it has more inliers than `bestInliers`.
  void matchFeatures(const cv::Mat& descriptors, const std::vector<cv::Point2f>& pixels, const cv::Matx33d& imageToPlane,
                     bool unique, PlanarPose& out, int& bestInliers);
  // Its corners for KLT, and (withFeatures) ORB features for relocalization.
  // A keyframe added while tracking gets its features on a later frame: one whose pose KLT gave
  // from the first prediction on a sharp frame, or at the latest kMaxFeatureDelayFrames after it, or
  // before a relocalization or the map is read. ORB on a keyframe takes about 8 ms, a frame that
  // adds one has tracked already (PTAM and ORB-SLAM make keyframes in a thread of their own:
  // here a frame's time stays bounded, the same on every run).
  PlanarKeyframe makeKeyframe(const cv::Mat& image, const cv::Matx33d& planeToImage, bool withFeatures = true);
  bool track(const PlanarPose& prediction, int keyframe, Measurement& out);
  // The smear the image's motion measured this frame makes over the exposure a dense pose
  // measured (0: either unknown; a camera with a short exposure smears nothing, whatever its turn).
  [[nodiscard]] double expectedSmearPx() const noexcept {
    return imageMotionFound && exposureMeasured ? cv::norm(smearTurnFromMotion(K, lastImageMotion, exposure)) * K(0, 0)
                                                : 0.0;
  }
  // The pose by the dense alignment of the keyframe from `prediction` (markerless_dense.cpp).
  // (poseDifference false: where the image's motion was not measured this frame, no smear rather
  // than the one the last frame's pose and `prediction` imply: the re-entry search's starts are
  // no prediction.)
  bool alignDense(const PlanarPose& prediction, int keyframe, Measurement& out, bool poseDifference = true);
  // The camera's turn over the last frame interval: from the image's motion measured this
  // frame, else from the last frame's pose to `prediction` (haveMotion false: neither).
  [[nodiscard]] cv::Vec3d frameIntervalTurn(const PlanarPose& prediction, bool& haveMotion,
                                            bool poseDifference = true) const noexcept;
  // A dense alignment's pose and evidence as a measurement (no covariance yet).
  [[nodiscard]] static Measurement denseEvidence(const DenseAlignment& a, const KeyframeData& kf) noexcept;
  // Whether the target shows where the pose carried by the image's motion puts it (blurred by
  // `smearTurn`): enough of its parts agree there, as the dense gate asks (markerless_dense.cpp).
  bool carriedPoseShows(const PlanarPose& pose, int keyframe, const cv::Vec3d& smearTurn);
  // Where nothing measured passed: the prediction (the last pose given, carried by the image's
  // motion measured this frame) as a pose to give at `seconds`, with its covariance, when the
  // target's parts agree at it and three sigma stay drawable (markerless_dense.cpp).
  bool carry(const PlanarPose& prediction, double seconds, StampedPose& out);
  // The dense gate's agreement by parts: enough of the target's textured parts agree on their own,
  // spread over it (markerless_gates.cpp).
  [[nodiscard]] bool agreesByParts(const Measurement& m) const noexcept;
  // The dense gate's whole: the blurred keyframe explains the frame (ZNCC) with enough of its
  // pixels within Huber's threshold (markerless_gates.cpp).
  [[nodiscard]] bool explainedAsWhole(const Measurement& m) const noexcept;
  // A measurement's photometric evidence (its ncc; a dense one's shares and parts) into this
  // frame's stats, for the logs and calibration.
  void notePhotometricEvidence(const Measurement& m) noexcept;
  [[nodiscard]] Evidence evidenceOf(const Measurement& m) const noexcept;
  // The motion model: distance of `pose` from what the confirmed poses predict at `seconds`,
  // and what a hand-held camera could have done since (stats' motion fields). True within it.
  bool motionAllows(const Measurement& m, const StampedPose& base, bool withVelocity, double seconds) noexcept;
  Verdict judge(const Measurement& m, double seconds, bool relocalized) noexcept;
  [[nodiscard]] bool haveVelocity() const noexcept;
  bool predict(double seconds, PlanarPose& out);
  // The last frame's pose moved by the homography that carries the last frame's image onto
  // this one (KLT on a grid, RANSAC), started from `guess`. False when too little agrees.
  bool backgroundPrediction(const PlanarPose& guess, PlanarPose& out, bool guessHasVelocity = true);
  // The last frame's pixel -> this frame's: KLT on the grid and RANSAC, or (where a smear
  // defeats the grid) the whole image's shift read as a turn of the camera (image_shift.hpp).
  bool gridImageMotion(const cv::Matx33d& guessMotion, cv::Matx33d& motion);
  // Either of them, kept as this frame's measured motion (lastImageMotion).
  bool measureImageMotion(const cv::Matx33d& guessMotion);
  bool shiftImageMotion(const cv::Matx33d& guessMotion, cv::Matx33d& motion);
  bool loadFrame(const ImageView& frame);
  void forgetOld(double seconds) noexcept;
  void forgetAll() noexcept;
  void confirm(const Measurement& m, double seconds) noexcept;
  // The keyframe that sees most of the predicted view (the reference counts a quarter more), and
  // the floor keyframe that does (one pass over their corners).
  KeyframeChoice chooseKeyframes(const PlanarPose& prediction);
  int chooseKeyframe(const PlanarPose& prediction) { return chooseKeyframes(prediction).best; }
  // The best keyframe, or the floor's while it goes first (floorFirstUntil).
  [[nodiscard]] int keyframeToTrack(const KeyframeChoice& choice) const noexcept;
  [[nodiscard]] bool floorGoesFirst() const noexcept { return frames <= floorFirstUntil; }
  // A floor keyframe is tried where tracking against the reference failed when this many of its
  // corners fall in the predicted view: twice what TRACKING needs agreeing.
  [[nodiscard]] int minFloorRetryCorners() const noexcept { return 2 * settings.minTrackingInliers; }
  bool relocalize(PlanarPose& out);
  // Relocalization's ORB run once on a frame-sized image at construction (markerless_map.cpp).
  void warmUpRelocalization();
  // A pose given, or carried by the image's motion through a look away: the newest of the way
  // out when the target is near the view and it turned kExitPathStepDeg from the last kept.
  void rememberExitPath(const PlanarPose& pose);
  // Where nothing predicts the pose and relocalization gave none: the reference aligned densely
  // from the best-correlating pose of the way out (markerless_reentry.cpp).
  bool searchReentry(double seconds, Measurement& out);
  void maybeExtendMap(const Measurement& m);
  // Frame pixels per keyframe pixel at the keyframe's centre, seen from p.
  [[nodiscard]] double keyframeMagnification(const PlanarPose& p, int keyframe) const;
  // Past this the target is a few pixels wide and any homography fits it: not a pose.
  [[nodiscard]] double maxDistance() const noexcept { return 40.0 * std::max(map.targetWidth, map.targetHeight); }
  // Enough of the corners tried agree, closely: a verified pose. Blur, occlusion or a wrong
  // prediction leave fewer, looser inliers (LIMITED at best).
  [[nodiscard]] bool isStrong(const Measurement& m) const noexcept {
    return m.inliers >= settings.minTrackingInliers && 3 * m.inliers >= m.tried && m.rms <= settings.maxTrackingRmsPx;
  }
  TrackedPose update(const ImageView& frame, double seconds);
};

}  // namespace marionette::ar
