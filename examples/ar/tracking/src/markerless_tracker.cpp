#include "marionette_ar/tracking/markerless_tracker.hpp"

#include <algorithm>
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
#include "image_shift.hpp"
#include "tilted_views.hpp"
#include "lucas_kanade.hpp"
#include "motion_blur.hpp"
#include "perspective_warp.hpp"
#include "planar_geometry.hpp"
#include "planar_pose.hpp"
#include "pose_filter.hpp"

namespace marionette::ar {

namespace {

constexpr int kMaxReferenceSide = 1024;  // larger references are scaled down (KLT works at camera scale)
constexpr int kCornersPerKeyframe = 500;
constexpr int kReferenceLevels = 4;  // the reference at 1, 1/2, 1/4, 1/8: warp from the nearest scale
constexpr int kMinRelocalizationInliers = 15;
constexpr double kMaxBlurFraction = 0.1;  // longest motion blur modelled, of the frame's width
// How long the background's frame-to-frame motion alone may carry the pose (never given, only
// where tracking starts): a look away and back within it tracks again without relocalizing.
constexpr double kMaxChainSeconds = 1.5;
constexpr int kMinBackgroundPoints = 16;
// A keyframe seen this much larger than it was taken is replaced by a new one (map extension),
// and counts for less when choosing the keyframe to track against.
constexpr double kMaxMagnification = 1.6;
constexpr double kLooseFitPx = 0.75;  // inliers' rms past which the fit is a smeared template's

// cv::Mat::setTo allocates a scratch buffer on every call.
void fill(cv::Mat& image, std::uint8_t value) noexcept {
  for (int y = 0; y < image.rows; ++y) std::memset(image.ptr<std::uint8_t>(y), value, static_cast<std::size_t>(image.cols));
}

// What the map keeps per keyframe for the per-frame path, prepared once.
struct KeyframeData {
  std::vector<cv::Mat> levels;  // grey image pyramid (level 0 views the map's bytes)
  cv::Matx33d planeToImage, imageToPlane;
  std::vector<cv::Point2f> corners;       // level-0 pixels
  std::vector<cv::Point2f> cornerPlane;   // (X, Z) metres
  cv::Mat descriptors;                    // ORB, one row per feature
  std::vector<cv::Point2f> featurePixels;
  glm::dvec3 cameraPosition{0.0};  // the camera that took it (keyframe 0: none)
  double meanGrey = 128;
  bool reference = false;
};

// One measured pose and the evidence the gates judge it by.
struct Measurement {
  PlanarPose pose;
  double rms = 0;
  int inliers = 0, tried = 0;
  double spread = 0;  // the inliers' narrowest spread over the tried corners
  double ncc = 0;     // mean normalized cross-correlation of template and frame at the inliers
  std::array<double, 36> covariance{};
  double positionSigma = 0, rotationSigmaDeg = 0;
  bool haveCovariance = false;
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

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// sqrt of the smaller eigenvalue of the points' covariance: their spread across the narrowest
// direction, pixels.
double narrowestSpread(const std::vector<cv::Point2f>& points) noexcept {
  if (points.size() < 2) return 0;
  double mx = 0, my = 0;
  for (const cv::Point2f& p : points) mx += p.x, my += p.y;
  const double n = static_cast<double>(points.size());
  mx /= n, my /= n;
  double sxx = 0, syy = 0, sxy = 0;
  for (const cv::Point2f& p : points) {
    sxx += (p.x - mx) * (p.x - mx);
    syy += (p.y - my) * (p.y - my);
    sxy += (p.x - mx) * (p.y - my);
  }
  sxx /= n, syy /= n, sxy /= n;
  return std::sqrt(std::max(0.0, 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy)));
}

// Bilinear sample of a grey image; false outside it.
bool sample(const cv::Mat& image, float x, float y, float& out) noexcept {
  if (!(x >= 0) || !(y >= 0) || x > static_cast<float>(image.cols - 2) || y > static_cast<float>(image.rows - 2))
    return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const std::uint8_t* r0 = image.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = image.ptr<std::uint8_t>(y0 + 1);
  out = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

// Zero-mean normalized cross-correlation of the (2 half + 1)^2 patches around a in `templ` and
// b in `frame`; NaN where a patch leaves its image or is flat.
double patchNcc(const cv::Mat& templ, cv::Point2f a, const cv::Mat& frame, cv::Point2f b, int half) noexcept {
  double st = 0, sf = 0, stt = 0, sff = 0, stf = 0;
  int n = 0;
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -half; dx <= half; ++dx) {
      float t = 0, f = 0;
      if (!sample(templ, a.x + static_cast<float>(dx), a.y + static_cast<float>(dy), t) ||
          !sample(frame, b.x + static_cast<float>(dx), b.y + static_cast<float>(dy), f))
        return std::numeric_limits<double>::quiet_NaN();
      st += t, sf += f, stt += double(t) * t, sff += double(f) * f, stf += double(t) * f;
      ++n;
    }
  const double vt = stt - st * st / n, vf = sff - sf * sf / n;
  if (!(vt > 1e-6 * n) || !(vf > 1e-6 * n)) return std::numeric_limits<double>::quiet_NaN();
  return (stf - st * sf / n) / std::sqrt(vt * vf);
}

}  // namespace

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
  // This frame's pose carried from the last given one by the image's motion alone (no anchor).
  PlanarPose chainPrediction;
  bool haveChainPrediction = false;
  // The last frame-to-frame homography measured (kept while consecutive frames measure one).
  cv::Matx33d lastImageMotion = cv::Matx33d::eye();
  bool haveLastImageMotion = false, imageMotionFound = false;
  double lastGivenTime = -1e300;
  std::vector<cv::Point2f> backgroundGrid, backgroundFrom, backgroundTo, backgroundFound;
  std::vector<unsigned char> backgroundStatus, backgroundMask;
  HomographyRansac backgroundRansac;
  [[nodiscard]] const ImagePyramid& framePyramid() const noexcept { return pyramids[static_cast<std::size_t>(currentFrame)]; }
  LucasKanade lk;
  PlanarPoseSolver solver;
  MotionBlur blur;
  MotionBlurScratch blurScratch;
  std::vector<cv::Point2f> levelPoints;
  std::vector<cv::Point2f> predicted, found, planePoints, inlierPlane, inlierImage, inlierFrom, blurFrom, blurTo;
  std::vector<int> cornerIndex;
  std::vector<unsigned char> status, mask;
  std::vector<cv::KeyPoint> frameKeypoints;
  cv::Mat frameDescriptors;
  std::vector<HammingMatch> matches;
  cv::Matx33d homography;

  Impl(const CameraModel& c, const MarkerlessSettings& s)
      : camera(c), settings(s), filter(s.smoothingMinCutoffHz, s.smoothingBeta) {
    K = cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
    orb = cv::ORB::create(s.relocalizationFeatures, 1.2f, 6, 19, 0, 2, cv::ORB::FAST_SCORE, 19, 15);
    grey.configure(c);
    blurScratch.reserve(c.width, c.height);
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
  // Matches this frame's ORB features to a feature set; the pose from the best match so far goes
  // to `out` when it has more inliers than `bestInliers`.
  void matchFeatures(const cv::Mat& descriptors, const std::vector<cv::Point2f>& pixels, const cv::Matx33d& imageToPlane,
                     bool unique, PlanarPose& out, int& bestInliers);
  PlanarKeyframe makeKeyframe(const cv::Mat& image, const cv::Matx33d& planeToImage);
  bool track(const PlanarPose& prediction, int keyframe, Measurement& out);
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
  bool shiftImageMotion(const cv::Matx33d& guessMotion, cv::Matx33d& motion);
  bool loadFrame(const ImageView& frame);
  void forgetOld(double seconds) noexcept;
  void forgetAll() noexcept;
  void confirm(const Measurement& m, double seconds) noexcept;
  int chooseKeyframe(const PlanarPose& prediction);
  bool relocalize(PlanarPose& out);
  void maybeExtendMap(const PlanarPose& p, double rms, int inliers, int tried);
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

PlanarKeyframe MarkerlessTracker::Impl::makeKeyframe(const cv::Mat& image, const cv::Matx33d& planeToImage) {
  PlanarKeyframe k;
  k.width = image.cols;
  k.height = image.rows;
  k.grey.assign(image.datastart, image.datastart + image.total());
  if (!image.isContinuous()) {
    k.grey.clear();
    for (int r = 0; r < image.rows; ++r) k.grey.insert(k.grey.end(), image.ptr(r), image.ptr(r) + image.cols);
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) k.planeToImage[static_cast<std::size_t>(r * 3 + c)] = planeToImage(r, c);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, kCornersPerKeyframe, 0.01, 8, cv::noArray(), 5);
  for (const auto& c : corners) k.corners.push_back({c.x, c.y});
  // 12 levels (a 7.4x range of scales): a keyframe is matched from close up and from afar.
  auto detector = cv::ORB::create(settings.referenceFeatures, 1.2f, 12, 19, 0, 2, cv::ORB::HARRIS_SCORE, 19, 15);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  detector->detectAndCompute(image, cv::noArray(), kps, desc);
  for (std::size_t i = 0; i < kps.size(); ++i) {
    PlanarFeature f;
    f.x = kps[i].pt.x;
    f.y = kps[i].pt.y;
    f.size = kps[i].size;
    f.angle = kps[i].angle;
    f.response = kps[i].response;
    f.octave = kps[i].octave;
    std::copy_n(desc.ptr<std::uint8_t>(static_cast<int>(i)), 32, f.descriptor.begin());
    k.features.push_back(f);
  }
  return k;
}

void MarkerlessTracker::Impl::prepareKeyframe(std::size_t i) {
  PlanarKeyframe& k = map.keyframes[i];
  KeyframeData d;
  d.reference = i == 0;
  d.levels.push_back(cv::Mat(k.height, k.width, CV_8UC1, k.grey.data()));
  const int levels = d.reference ? kReferenceLevels : 1;
  for (int l = 1; l < levels && d.levels.back().cols >= 32 && d.levels.back().rows >= 32; ++l) {
    cv::Mat down;
    cv::pyrDown(d.levels.back(), down);
    d.levels.push_back(down);
  }
  d.meanGrey = cv::mean(d.levels[0])[0];
  d.planeToImage = cv::Matx33d(k.planeToImage.data());
  d.imageToPlane = d.planeToImage.inv();
  // Corners interleaved over an 8x8 grid (the strongest of each cell, then the second...),
  // so that the first N in view spread over all of it: an occluder or the image border then
  // takes its share of the points, not all of the strongest ones.
  constexpr int kCells = 8;
  std::vector<int> perCell(kCells * kCells, 0);
  std::vector<std::pair<int, std::size_t>> order;
  for (std::size_t c = 0; c < k.corners.size(); ++c) {
    const int cx = std::clamp(static_cast<int>(k.corners[c][0] * kCells / static_cast<float>(k.width)), 0, kCells - 1);
    const int cy = std::clamp(static_cast<int>(k.corners[c][1] * kCells / static_cast<float>(k.height)), 0, kCells - 1);
    order.emplace_back(perCell[static_cast<std::size_t>(cy * kCells + cx)]++, c);
  }
  std::sort(order.begin(), order.end());
  for (const auto& [rank, c] : order) {
    d.corners.emplace_back(k.corners[c][0], k.corners[c][1]);
    d.cornerPlane.push_back(applyHomography(d.imageToPlane, d.corners.back()));
  }
  d.descriptors.create(static_cast<int>(k.features.size()), 32, CV_8UC1);
  for (std::size_t f = 0; f < k.features.size(); ++f) {
    std::copy_n(k.features[f].descriptor.begin(), 32, d.descriptors.ptr<std::uint8_t>(static_cast<int>(f)));
    d.featurePixels.emplace_back(k.features[f].x, k.features[f].y);
  }
  if (!d.reference) {
    // The camera centre from the plane-to-image homography K [r1 r3 t].
    PlanarPose p;
    if (poseFromPlaneHomography(K, d.planeToImage, p)) d.cameraPosition = cameraPosition(p);
  } else {
    // The reference as a camera would take it: square on, one of its pixels to one of the frame's.
    d.cameraPosition = glm::dvec3(0, K(0, 0) * map.targetWidth / k.width, 0);
  }
  // From the half-size level: the views serve a target seen small (a frontal or near one is the
  // reference's), and they cost a quarter (130 ms at launch from the full size, on this machine class).
  if (d.reference)
    tiltedViews = makeTiltedViews(d.levels[std::min<std::size_t>(1, d.levels.size() - 1)], d.levels[0].cols,
                                  settings.tiltedViewFeatures);
  if (i < keyframes.size()) keyframes[i] = std::move(d);
  else keyframes.push_back(std::move(d));
}


int MarkerlessTracker::Impl::chooseKeyframe(const PlanarPose& prediction) {
  const cv::Matx33d G = planeToImageHomography(K, prediction);
  int best = 0, bestCount = -1;
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    int count = 0;
    for (const cv::Point2f& p : keyframes[k].cornerPlane) {
      const cv::Vec3d h = G * cv::Vec3d(p.x, p.y, 1.0);
      if (h[2] <= 1e-9) continue;
      const double u = h[0] / h[2], v = h[1] / h[2];
      count += u >= 0 && v >= 0 && u < camera.width && v < camera.height;
    }
    // The reference is sharper and exact: a camera keyframe must see clearly more. A keyframe
    // magnified past kMaxMagnification has less detail than the frame: it counts for less.
    int score = keyframes[k].reference ? count + count / 4 : count;
    const double magnification = keyframeMagnification(prediction, static_cast<int>(k));
    if (magnification > kMaxMagnification) score = static_cast<int>(score * kMaxMagnification / magnification);
    if (score > bestCount) {
      bestCount = score;
      best = static_cast<int>(k);
    }
  }
  return best;
}

bool MarkerlessTracker::Impl::track(const PlanarPose& prediction, int keyframe, Measurement& out) {
  stats.predicted = true;
  stats.predictedCameraToWorld = cameraToWorld(prediction);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  const cv::Mat& frame = grey.pinhole();
  PlanarPose current = prediction;
  out = Measurement{};
  int inliers = 0;
  double rms = 0;
  const cv::Mat* usedTemplate = &warped;
  for (int pass = 0; pass <= settings.refinements; ++pass) {
    const cv::Matx33d G = planeToImageHomography(K, current);
    const cv::Matx33d W0 = G * kf.imageToPlane;  // keyframe level-0 pixel -> frame pixel
    // The pyramid level whose scale is nearest the view's (a 1 px step in the level image
    // moves about 1 px in the frame): warping from it does not alias.
    const double scale = homographyScaleAt(W0, cv::Point2f(static_cast<float>(kf.levels[0].cols) * 0.5f,
                                                           static_cast<float>(kf.levels[0].rows) * 0.5f));
    int level = 0;
    while (level + 1 < static_cast<int>(kf.levels.size()) && scale < 0.7 / (1 << level)) ++level;
    const double f = 1.0 / (1 << level);
    // Level pixel (centre convention) -> level-0 pixel: x0 = (x + 0.5) / f - 0.5.
    const cv::Matx33d levelToBase(1 / f, 0, 0.5 / f - 0.5, 0, 1 / f, 0.5 / f - 0.5, 0, 0, 1);

    predicted.clear();
    planePoints.clear();
    levelPoints.clear();
    const float margin = static_cast<float>(settings.kltWindow);
    for (std::size_t c = 0; c < kf.corners.size() && static_cast<int>(predicted.size()) < settings.trackedCorners; ++c) {
      const cv::Vec3d h = W0 * cv::Vec3d(kf.corners[c].x, kf.corners[c].y, 1.0);
      if (h[2] <= 1e-9) continue;
      const float u = static_cast<float>(h[0] / h[2]), v = static_cast<float>(h[1] / h[2]);
      if (u < margin || v < margin || u >= static_cast<float>(frame.cols) - margin ||
          v >= static_cast<float>(frame.rows) - margin)
        continue;
      predicted.emplace_back(u, v);
      planePoints.push_back(kf.cornerPlane[c]);
      levelPoints.emplace_back(static_cast<float>((kf.corners[c].x + 0.5) * f - 0.5),
                               static_cast<float>((kf.corners[c].y + 0.5) * f - 0.5));
    }
    if (predicted.size() < static_cast<std::size_t>(std::max(settings.minLimitedInliers, 6))) return false;
    // Around the keyframe the template is flat at the frame's mean: no false edge where the
    // keyframe ends for KLT's coarse levels, and no texture KLT could match at zero motion (a
    // copy of the frame there would confirm any prediction).
    const cv::Mat& level0 = kf.levels[static_cast<std::size_t>(level)];
    double gain = 1, bias = 0;
    const bool adjust = matchGain(level0, levelPoints, frame, predicted, settings.kltWindow, gain, bias) &&
                        (std::abs(gain - 1) > 0.03 || std::abs(bias) > 3);
    // Only the region KLT reads is warped (the points' box, grown by the window at the
    // coarsest level): the warp was half of a frame's time over the whole image.
    const auto background = static_cast<std::uint8_t>(std::clamp(kf.meanGrey * gain + bias + 0.5, 0.0, 255.0));
    warped.create(frame.size(), CV_8UC1);
    fill(warped, background);
    float x0 = predicted[0].x, y0 = predicted[0].y, x1 = x0, y1 = y0;
    for (const cv::Point2f& p : predicted) {
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    const int grow = settings.kltWindow * (1 << (pass == 0 ? settings.pyramidLevels : 1));
    const cv::Rect region = cv::Rect(static_cast<int>(x0) - grow, static_cast<int>(y0) - grow,
                                     static_cast<int>(x1 - x0) + 2 * grow + 1, static_cast<int>(y1 - y0) + 2 * grow + 1) &
                            cv::Rect(0, 0, frame.cols, frame.rows);
    const auto meanGrey = static_cast<std::uint8_t>(std::clamp(kf.meanGrey + 0.5, 0.0, 255.0));
    if (!warpPerspectiveRegion(level0, W0 * levelToBase, warped, region, meanGrey)) return false;
    // The exposure after the warp (the same up to rounding, and only over the region).
    if (adjust)
      for (int y = region.y; y < region.y + region.height; ++y) {
        std::uint8_t* row = warped.ptr<std::uint8_t>(y);
        for (int x = region.x; x < region.x + region.width; ++x)
          row[x] = static_cast<std::uint8_t>(std::clamp(row[x] * gain + bias + 0.5, 0.0, 255.0));
      }
    // Motion blur: the template is smeared as the frame is (motion_blur.hpp). The blur found
    // last frame is used first; without one, the frame's statistics may propose one, which
    // the aligned search then confirms (or not) after KLT.
    MotionBlur proposal;
    if (pass == 0 && !blur.any())
      proposal = estimateMotionBlur(warped, frame, predicted, kMaxBlurFraction * frame.cols, blurScratch);
    PlanarPose estimate;
    for (int attempt = 0; attempt < 2; ++attempt) {
      const cv::Mat* templ = &warped;
      if (blur.any()) {
        blurred.create(frame.size(), CV_8UC1);
        fill(blurred, background);
        applyMotionBlur(warped, blur, region, blurred, blurScratch);
        templ = &blurred;
      }
      found = predicted;
      // A smear longer than the window leaves it little texture along the smear: the window
      // grows with the smear (1.25 times, up to 31 px: docs/tracking.md).
      LucasKanadeParams lkParams;
      lkParams.window = blur.any() ? std::max(settings.kltWindow, std::min(25, static_cast<int>(blur.lengthPx) | 1))
                                   : settings.kltWindow;
      lkParams.coarseWindow = settings.kltWindow;  // the smear halves with each level
      lkParams.levels = pass == 0 ? settings.pyramidLevels : std::min(settings.pyramidLevels, 1);
      status.resize(predicted.size());
      if (!templatePyramid.buildRegion(*templ, region, background)) return false;
      lk.track(templatePyramid, framePyramid(), predicted, found, status, lkParams);
      usedTemplate = templ;
      inlierPlane.clear();
      inlierImage.clear();
      inlierFrom.clear();
      for (std::size_t i = 0; i < found.size(); ++i)
        if (status[i]) {
          inlierPlane.push_back(planePoints[i]);
          inlierImage.push_back(found[i]);
          inlierFrom.push_back(predicted[i]);
        }
      if (!robustPlanarPose(K, inlierPlane, inlierImage, 2.0, maxDistance(), solver, mask, estimate, rms, inliers, &homography)) {
        if (attempt == 0 && !blur.any() && proposal.any()) {
          blur = proposal;  // the sharp template found nothing in a smeared frame: try the proposal
          continue;
        }
        return false;
      }
      // Inliers within 2 px of the homography but not of the pose: a degenerate pose (seen with
      // 12 inliers and 10 px after a fast turn), not a measurement. (A target that is no
      // pinhole view at all, as the graffiti pair, needs maxTrackingRmsPx raised.)
      if (rms > std::max(2.0, settings.maxTrackingRmsPx)) return false;
      if (pass > 0 || (!blur.any() && !proposal.any())) break;
      // Misaligned patches look blurred: the search needs a pose TRACKING would accept.
      if (inliers < settings.minTrackingInliers || rms > 2 * settings.maxTrackingRmsPx) break;
      // The blur from patches KLT aligned (the RANSAC inliers): for the next frame, and for
      // this one when it changed clearly (the onset or the end of a smear).
      blurFrom.clear();
      blurTo.clear();
      for (std::size_t i = 0; i < inlierFrom.size(); ++i)
        if (mask[i]) {
          blurFrom.push_back(inlierFrom[i]);
          blurTo.push_back(inlierImage[i]);
        }
      const MotionBlur used = blur;
      blur = refineMotionBlur(warped, frame, blurFrom, blurTo, used.any() ? used : proposal, kMaxBlurFraction * frame.cols,
                              blurScratch);
      proposal = {};
      if (used.any() == blur.any() && std::abs(used.lengthPx - blur.lengthPx) <= 0.2 * std::max(used.lengthPx, 5.0)) break;
    }
    current = estimate;
    if (inliers < settings.minLimitedInliers) return false;
  }
  stats.corners = static_cast<int>(predicted.size());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) stats.planeToImage[static_cast<std::size_t>(r * 3 + c)] = homography(r, c);
  out.pose = current;
  out.rms = rms;
  out.inliers = inliers;
  out.tried = static_cast<int>(predicted.size());
  // The evidence beyond the counts. Spread: the inliers (solver.image) against the corners
  // tried, across the narrowest direction of each.
  const double triedSpread = narrowestSpread(predicted);
  out.spread = triedSpread > 0 ? narrowestSpread(solver.image) / triedSpread : 0;
  // Photometric: the template's patches against the frame's where KLT put them, at up to 48
  // inliers spread over the list (it is interleaved over the keyframe).
  double nccSum = 0;
  int nccCount = 0;
  const std::size_t step = std::max<std::size_t>(1, inlierFrom.size() / 48);
  for (std::size_t i = 0; i < inlierFrom.size() && i < mask.size(); i += step) {
    if (!mask[i]) continue;
    const double c = patchNcc(*usedTemplate, inlierFrom[i], frame, inlierImage[i], 4);
    if (std::isfinite(c)) nccSum += c, ++nccCount;
  }
  out.ncc = nccCount > 0 ? nccSum / nccCount : 0;
  // The covariance from the final step's normal equations (planar_pose.hpp). Where the inliers
  // themselves fit loosely (rms over kLooseFitPx: the template does not match the frame, as under
  // a smear longer than the blur model) and few of the corners tried agree, the ones that agree
  // share one bias: the independent features shrink with the square of that share under 60 %
  // (calibrated on the stress sequences: docs/tracking.md). An occluder leaves the inliers tight
  // and costs nothing here.
  const double share = static_cast<double>(inliers) / std::max(1, out.tried);
  const double looseFit = rms > kLooseFitPx ? std::pow(std::min(1.0, share / 0.6), 2.0) : 1.0;
  double covariance[36];
  out.haveCovariance = planarPoseCovariance(K, solver.plane, solver.image, {}, current,
                                            std::max(rms, settings.minFeatureSigmaPx),
                                            settings.effectiveFeatures * looseFit,
                                            covariance);
  if (out.haveCovariance) {
    std::copy(covariance, covariance + 36, out.covariance.begin());
    out.positionSigma = std::sqrt(covariance[21] + covariance[28] + covariance[35]);
    out.rotationSigmaDeg = std::sqrt(covariance[0] + covariance[7] + covariance[14]) * kDegrees;
  }
  return true;
}

bool MarkerlessTracker::Impl::relocalize(PlanarPose& out) {
  stats.relocalized = true;
  const cv::Mat& frame = grey.pinhole();
  orb->detectAndCompute(frame, cv::noArray(), frameKeypoints, frameDescriptors);
  if (frameKeypoints.size() < static_cast<std::size_t>(kMinRelocalizationInliers)) return false;
  int bestInliers = 0;
  for (const KeyframeData& kf : keyframes) {
    if (!kf.reference && !haveAnchor) continue;  // floor keyframes relocalize only near the last pose (below)
    matchFeatures(kf.descriptors, kf.featurePixels, kf.imageToPlane, kf.reference, out, bestInliers);
  }
  // The tilted views only when the keyframes found nothing: a frontal view does without their cost.
  if (bestInliers == 0)
    for (const TiltedView& v : tiltedViews)
      matchFeatures(v.descriptors, v.featurePixels, keyframes[0].imageToPlane, true, out, bestInliers);
  return bestInliers > 0;
}

void MarkerlessTracker::Impl::matchFeatures(const cv::Mat& descriptors, const std::vector<cv::Point2f>& pixels,
                                            const cv::Matx33d& imageToPlane, bool unique, PlanarPose& out,
                                            int& bestInliers) {
  if (descriptors.rows < 2) return;
  matchNearestTwo(frameDescriptors, descriptors, matches);
  inlierPlane.clear();
  inlierImage.clear();
  for (const HammingMatch& m : matches)
    if (m.distance < 0.8 * m.second && m.distance < 64) {
      inlierPlane.push_back(applyHomography(imageToPlane, pixels[static_cast<std::size_t>(m.train)]));
      inlierImage.push_back(frameKeypoints[static_cast<std::size_t>(m.query)].pt);
    }
  if (inlierPlane.size() < static_cast<std::size_t>(kMinRelocalizationInliers)) return;
  PlanarPose candidate;
  double rms = 0;
  int inliers = 0;
  if (!robustPlanarPose(K, inlierPlane, inlierImage, 4.0, maxDistance(), solver, mask, candidate, rms, inliers)) return;
  if (inliers < kMinRelocalizationInliers || inliers <= bestInliers) return;
  // The floor around a target may repeat (tiles, carpet): a keyframe of it can match the
  // wrong repeat. Only the reference is unique; a floor keyframe relocalizes only near the
  // last measured pose.
  if (!unique &&
      !(haveAnchor && glm::length(cameraPosition(candidate) - cameraPosition(anchor.pose)) <
                          0.3 * std::max(0.05, glm::length(cameraPosition(anchor.pose)))))
    return;
  bestInliers = inliers;
  out = candidate;
}

void MarkerlessTracker::Impl::maybeExtendMap(const PlanarPose& p, double rms, int inliers, int tried) {
  if (static_cast<int>(map.keyframes.size()) >= PlanarMap::kMaxKeyframes) return;
  // A keyframe when the view reaches past the target, or (as PTAM and ORB-SLAM add them as the
  // camera closes in) when the keyframe tracked against is seen much larger than it was taken:
  // its texture, magnified, no longer matches the frame's detail.
  const bool pastTarget = visibleTargetFraction(K, camera, p, map.targetWidth, map.targetHeight) < settings.extendBelowVisible;
  // Closing in on the target itself (floor keyframes carry their pose's error: no chains of them).
  const bool closer = stats.keyframe >= 0 && keyframes[static_cast<std::size_t>(stats.keyframe)].reference &&
                      keyframeMagnification(p, stats.keyframe) > kMaxMagnification;
  // Or, as PTAM adds them, when tracking still holds but the keyframe matches less and less (a
  // surface not quite flat, things standing on it seen from elsewhere) and the camera has moved
  // away from every keyframe's viewpoint.
  const glm::dvec3 c = cameraPosition(p);
  const double distance = std::max(0.05, c.y);
  double nearest = HUGE_VAL;
  for (const KeyframeData& kf : keyframes) nearest = std::min(nearest, glm::length(kf.cameraPosition - c));
  // Looser inliers, most of the corners still agreeing, on a frame without a smear (a smear
  // loosens them too, and would make a blurred keyframe; an occluder takes corners away, and a
  // keyframe of it would keep the occluder).
  const bool fading = rms > 0.5 * settings.maxTrackingRmsPx && 5 * inliers >= 4 * tried && !blur.any() &&
                      nearest > 0.05 * distance;
  if (!pastTarget && !closer && !fading) return;
  for (std::size_t k = 0; k < keyframes.size() && !fading; ++k) {
    const KeyframeData& kf = keyframes[k];
    if (kf.reference) continue;
    // One near enough already, seen at about its own scale.
    if (glm::length(kf.cameraPosition - c) < 0.3 * distance &&
        keyframeMagnification(p, static_cast<int>(k)) <= kMaxMagnification)
      return;
  }
  map.keyframes.push_back(makeKeyframe(grey.pinhole(), planeToImageHomography(K, p)));
  prepareKeyframe(map.keyframes.size() - 1);
  stats.keyframeAdded = true;
}

double MarkerlessTracker::Impl::keyframeMagnification(const PlanarPose& p, int keyframe) const {
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  const cv::Matx33d w = planeToImageHomography(K, p) * kf.imageToPlane;  // keyframe pixel -> frame pixel
  return homographyScaleAt(w, cv::Point2f(static_cast<float>(kf.levels[0].cols) * 0.5f,
                                          static_cast<float>(kf.levels[0].rows) * 0.5f));
}

Evidence MarkerlessTracker::Impl::evidenceOf(const Measurement& m) const noexcept {
  if (!m.haveCovariance) return Evidence::None;
  // A loose fit that fewer than half of the corners tried support is no pose: on the stress
  // sequences such poses (13-43 % agreeing, rms 1.1-1.4 px) were 5-11 cm and 2.5-7 deg off, while
  // smeared frames the blur model follows keep 55-70 % (docs/tracking.md).
  if (m.rms > kLooseFitPx && 2 * m.inliers < m.tried) return Evidence::None;
  // Nor is a pose that under a tenth of the corners tried agree with, however tight: on the
  // stress sequences the two such poses (6-7 %) were 2.6-4.9 cm and 2.1-3.8 deg off, KLT's few
  // chance agreements after a smear; hands hiding most of the target left 12 % and more.
  if (10 * m.inliers < m.tried) return Evidence::None;
  // Three standard deviations within the error a drawn pose may have (positions: an absolute
  // bound, or a share of the viewing distance for a target seen from afar).
  const double distance = glm::length(cameraPosition(m.pose));
  const double drawnM = std::max(settings.maxDrawnErrorM, settings.maxDrawnErrorFraction * distance);
  const double trackingM = std::max(settings.maxTrackingErrorM, settings.maxTrackingErrorFraction * distance);
  const bool limited = m.inliers >= settings.minLimitedInliers && m.spread >= settings.minLimitedSpread &&
                       m.ncc >= settings.minLimitedNcc && 3 * m.positionSigma <= drawnM &&
                       3 * m.rotationSigmaDeg <= settings.maxDrawnErrorDeg;
  if (!limited) return Evidence::None;
  const bool tracking = isStrong(m) && m.spread >= settings.minTrackingSpread && m.ncc >= settings.minTrackingNcc &&
                        3 * m.positionSigma <= trackingM && 3 * m.rotationSigmaDeg <= settings.maxTrackingErrorDeg;
  return tracking ? Evidence::Tracking : Evidence::Limited;
}

bool MarkerlessTracker::Impl::haveVelocity() const noexcept {
  // Two confirmed poses close enough in time that their difference is a velocity.
  return confirmedCount >= 2 && confirmed[0].time > confirmed[1].time &&
         confirmed[0].time - confirmed[1].time <= 0.2;
}

bool MarkerlessTracker::Impl::motionAllows(const Measurement& m, const StampedPose& base, bool withVelocity,
                                           double seconds) noexcept {
  const double dt = std::max(0.0, seconds - base.time);
  const double aMax = settings.maxAcceleration, alphaMax = settings.maxAngularAccelerationDeg;
  // Noise: three standard deviations of both poses.
  double positionLimit = 3 * std::hypot(base.positionSigma, m.positionSigma);
  double rotationLimit = 3 * std::hypot(base.rotationSigmaDeg, m.rotationSigmaDeg);
  PlanarPose reference = base.pose;
  if (withVelocity) {
    // Constant velocity from the two confirmed poses: their difference is the velocity half
    // their interval ago, so at most acceleration a gives an error a dt (dt + pair) / 2. The
    // velocity's own error (the two poses' noise over their interval) grows with dt.
    const StampedPose& a = confirmed[1];
    const double pair = base.time - a.time;
    reference = extrapolate(a.pose, a.time, base.pose, base.time, seconds);
    positionLimit += 0.5 * aMax * dt * (dt + pair) + 3 * std::hypot(a.positionSigma, base.positionSigma) * dt / pair;
    rotationLimit +=
        0.5 * alphaMax * dt * (dt + pair) + 3 * std::hypot(a.rotationSigmaDeg, base.rotationSigmaDeg) * dt / pair;
  } else {
    positionLimit += settings.maxSpeed * dt + 0.5 * aMax * dt * dt;
    rotationLimit += settings.maxAngularSpeedDeg * dt + 0.5 * alphaMax * dt * dt;
  }
  stats.motionPositionM = glm::length(cameraPosition(m.pose) - cameraPosition(reference));
  stats.motionRotationDeg = rotationBetweenDeg(m.pose, reference);
  stats.motionPositionLimitM = positionLimit;
  stats.motionRotationLimitDeg = rotationLimit;
  return stats.motionPositionM <= positionLimit && stats.motionRotationDeg <= rotationLimit;
}

Verdict MarkerlessTracker::Impl::judge(const Measurement& m, double seconds, bool relocalized) noexcept {
  stats.inliers = m.inliers;
  stats.rmsPx = m.rms;
  stats.spread = m.spread;
  stats.judgedCameraToWorld = cameraToWorld(m.pose);
  stats.ncc = m.ncc;
  stats.positionSigmaM = m.positionSigma;
  stats.rotationSigmaDeg = m.rotationSigmaDeg;
  stats.rejection = Rejection::None;
  const Evidence evidence = evidenceOf(m);
  if (evidence == Evidence::None) {
    stats.rejection = Rejection::Evidence;
    return Verdict::Rejected;
  }
  const bool strong = evidence == Evidence::Tracking;
  if (relocalized && !strong) {
    // Counted strong by relocalization's own check, less certain by its covariance (a target
    // partly hidden at launch): the next frame must confirm it.
    stats.rejection = Rejection::Unconfirmed;
    return Verdict::Pending;
  }
  if (havePending && !relocalized) {
    // Tracked from a pose awaiting confirmation: it is confirmed when this frame, measured from
    // it, continues it within what the camera can do (no velocity known yet).
    if (motionAllows(m, pending, false, seconds)) return strong ? Verdict::Tracking : Verdict::Limited;
    stats.rejection = Rejection::Unconfirmed;
    return strong ? Verdict::Pending : Verdict::Rejected;
  }
  if (confirmedCount > 0) {
    if (motionAllows(m, confirmed[0], haveVelocity(), seconds)) return strong ? Verdict::Tracking : Verdict::Limited;
    // Off the motion model: wrong, or the camera was jolted. A strong pose gets the next
    // frame to confirm it, as a relocalization does.
    stats.rejection = Rejection::Motion;
    return strong ? Verdict::Pending : Verdict::Rejected;
  }
  // No recent confirmed pose. A relocalization (ORB against the map, independent of the image's
  // motion) that agrees with the pose the image's motion carried since the last one given is
  // confirmed by it; anything else waits for the next frame.
  if (relocalized && haveChainPrediction && posesAgree(m.pose, chainPrediction, 0.05, 3.0)) return Verdict::Tracking;
  stats.rejection = Rejection::Unconfirmed;
  return Verdict::Pending;
}

bool MarkerlessTracker::Impl::predict(double seconds, PlanarPose& out) {
  if (havePending) {
    out = pending.pose;  // no velocity known yet (the image's motion is the fallback, below)
    return true;
  }
  // The last frame was carried by the image's motion (nothing measured since the anchor): the
  // image's motion goes on carrying it; the anchor's velocity, older, would overshoot a turn.
  if (haveAnchor && previousFrameChained && backgroundPrediction(previousFramePose, out, false)) {
    stats.backgroundMotion = true;
    chainPrediction = out;
    haveChainPrediction = true;
    return true;
  }
  if (haveAnchor) {
    out = haveVelocity() ? extrapolateFrom(confirmed[1].pose, confirmed[1].time, confirmed[0].pose,
                                           confirmed[0].time, anchor.pose, anchor.time, seconds)
                         : anchor.pose;
    return true;
  }
  // Nothing given lately: the last frame's estimate carried by the image's motion, if any.
  if (havePreviousFramePose && seconds - lastGivenTime <= kMaxChainSeconds &&
      backgroundPrediction(previousFramePose, out, false)) {
    stats.backgroundMotion = true;
    chainPrediction = out;
    haveChainPrediction = true;
    return true;
  }
  return false;
}

bool MarkerlessTracker::Impl::backgroundPrediction(const PlanarPose& guess, PlanarPose& out, bool guessHasVelocity) {
  if (!settings.backgroundMotion || !havePreviousFrame || !havePreviousFramePose) return false;
  const cv::Matx33d previousG = planeToImageHomography(K, previousFramePose);
  const cv::Matx33d guessG = planeToImageHomography(K, guess);
  // Last frame's pixel -> this frame's, as guessed; a guess without a velocity (a chain through a
  // look away), or one older than the image's last measured motion, starts from that motion
  // instead (a pan goes on).
  const cv::Matx33d guessMotion =
      (!guessHasVelocity || previousFrameChained) && haveLastImageMotion ? lastImageMotion
                                                                       : cv::Matx33d(guessG * previousG.inv());
  cv::Matx33d motion;
  if (!gridImageMotion(guessMotion, motion) && !shiftImageMotion(guessMotion, motion)) return false;
  lastImageMotion = motion;
  haveLastImageMotion = true;
  imageMotionFound = true;
  PlanarPose moved;
  if (!poseFromPlaneHomography(K, motion * previousG, moved)) return false;
  const glm::dvec3 c = cameraPosition(moved);
  if (!(c.y > 1e-3) || !(glm::length(c) <= maxDistance())) return false;
  out = moved;
  return true;
}

bool MarkerlessTracker::Impl::gridImageMotion(const cv::Matx33d& guessMotion, cv::Matx33d& motion) {
  backgroundFrom.clear();
  backgroundTo.clear();
  for (const cv::Point2f& p : backgroundGrid) {
    const cv::Vec3d h = guessMotion * cv::Vec3d(p.x, p.y, 1.0);
    if (!(h[2] > 1e-9)) continue;
    const float u = static_cast<float>(h[0] / h[2]), v = static_cast<float>(h[1] / h[2]);
    const auto w = static_cast<float>(camera.width), h2 = static_cast<float>(camera.height);
    if (!(u > -0.5f * w && u < 1.5f * w && v > -0.5f * h2 && v < 1.5f * h2)) continue;
    backgroundFrom.push_back(p);
    backgroundTo.emplace_back(u, v);
  }
  if (backgroundFrom.size() < static_cast<std::size_t>(kMinBackgroundPoints)) return false;
  backgroundStatus.resize(backgroundFrom.size());
  LucasKanadeParams params;
  params.window = settings.kltWindow;
  params.levels = settings.pyramidLevels;
  lk.track(pyramids[static_cast<std::size_t>(currentFrame ^ 1)], framePyramid(), backgroundFrom, backgroundTo,
           backgroundStatus, params);
  backgroundFound.clear();
  std::size_t n = 0;
  for (std::size_t i = 0; i < backgroundFrom.size(); ++i)
    if (backgroundStatus[i]) {
      backgroundFrom[n] = backgroundFrom[i];
      backgroundFound.push_back(backgroundTo[i]);
      ++n;
    }
  backgroundFrom.resize(n);
  if (n < static_cast<std::size_t>(kMinBackgroundPoints)) return false;
  backgroundMask.resize(n);
  HomographyRansacParams ransac;
  ransac.thresholdPx = 3.0;
  int inliers = 0;
  if (!backgroundRansac.estimate(backgroundFrom, backgroundFound, ransac, motion, backgroundMask, inliers)) return false;
  // Most of what was followed must move together, over a good part of the frame.
  if (inliers < kMinBackgroundPoints || 2 * inliers < static_cast<int>(n)) return false;
  backgroundTo.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (backgroundMask[i]) backgroundTo.push_back(backgroundFound[i]);
  return narrowestSpread(backgroundTo) >= 0.1 * std::min(camera.width, camera.height);
}

bool MarkerlessTracker::Impl::shiftImageMotion(const cv::Matx33d& guessMotion, cv::Matx33d& motion) {
  // Where the guess moves the principal point: the search's centre.
  const cv::Vec3d h = guessMotion * cv::Vec3d(K(0, 2), K(1, 2), 1.0);
  if (!(h[2] > 1e-9)) return false;
  const cv::Point2f guess(static_cast<float>(h[0] / h[2] - K(0, 2)), static_cast<float>(h[1] / h[2] - K(1, 2)));
  ImageShiftParams params;
  params.coarseLevel = std::min(settings.pyramidLevels, 3);
  ImageShift shift;
  if (!estimateImageShift(pyramids[static_cast<std::size_t>(currentFrame ^ 1)], framePyramid(), guess, params, shift))
    return false;
  motion = rotationShiftHomography(K, shift.shift);
  stats.imageShift = true;
  return true;
}

bool MarkerlessTracker::Impl::loadFrame(const ImageView& frame) {
  if (!grey.load(frame)) return false;
  currentFrame ^= 1;
  const cv::Mat& pinhole = grey.pinhole();
  cv::Mat& copy = frameCopies[static_cast<std::size_t>(currentFrame)];
  for (int y = 0; y < pinhole.rows; ++y)
    std::memcpy(copy.ptr<std::uint8_t>(y), pinhole.ptr<std::uint8_t>(y), static_cast<std::size_t>(pinhole.cols));
  if (!pyramids[static_cast<std::size_t>(currentFrame)].build(copy)) {
    havePreviousFrame = false;
    return false;
  }
  return true;
}

void MarkerlessTracker::Impl::forgetOld(double seconds) noexcept {
  const double hold = settings.holdLimitedSeconds + 1e-9;
  if (confirmedCount > 0 && seconds - confirmed[0].time > hold) confirmedCount = 0;
  if (havePending && seconds - pending.time > hold) havePending = false;
  if (haveAnchor && seconds - anchor.time > hold) {
    haveAnchor = false;
    blur = {};
  }
}

void MarkerlessTracker::Impl::forgetAll() noexcept {
  confirmedCount = 0;
  haveAnchor = havePending = gaveLast = havePreviousFrame = havePreviousFramePose = haveLastImageMotion = previousFrameChained = false;
  blur = {};
  filter.reset();
}

void MarkerlessTracker::Impl::confirm(const Measurement& m, double seconds) noexcept {
  const StampedPose p{m.pose, seconds, m.covariance, m.positionSigma, m.rotationSigmaDeg};
  confirmed[1] = confirmed[0];
  confirmed[0] = p;
  confirmedCount = std::min(confirmedCount + 1, 2);
  anchor = p;
  haveAnchor = true;
}

TrackedPose MarkerlessTracker::Impl::update(const ImageView& frame, double seconds) {
  stats = FrameStats{};
  TrackedPose result;
  if (!loadFrame(frame)) return result;
  forgetOld(seconds);
  haveChainPrediction = false;
  imageMotionFound = false;

  // The smear is the last accepted measurement's: an attempt judged wrong leaves it as it was
  // (a smear proposed on a wrong prediction would blur the template of every later attempt).
  const MotionBlur blurBefore = blur;
  // Track from the prediction: the pending pose, or the anchor moved by the confirmed velocity.
  PlanarPose prediction;
  Measurement m;
  Verdict verdict = Verdict::Rejected;
  const bool havePrediction = predict(seconds, prediction);
  if (havePrediction) {
    stats.keyframe = chooseKeyframe(prediction);
    if (track(prediction, stats.keyframe, m)) verdict = judge(m, seconds, false);
  }
  // The constant-velocity prediction found nothing usable (a sudden turn, a smear hiding the
  // corners): try again from where the whole image's motion since the last frame puts the pose.
  if (havePrediction && verdict == Verdict::Rejected && !stats.backgroundMotion) {
    PlanarPose moved;
    if (backgroundPrediction(prediction, moved)) {
      blur = blurBefore;
      stats.backgroundMotion = true;
      prediction = moved;
      stats.keyframe = chooseKeyframe(prediction);
      Measurement retried;
      if (track(prediction, stats.keyframe, retried)) {
        const Verdict v = judge(retried, seconds, false);
        if (v != Verdict::Rejected) m = retried, verdict = v;
      }
    }
  }
  const bool fromPending = havePending && (verdict == Verdict::Tracking || verdict == Verdict::Limited);
  // Relocalize when tracking found nothing, or had nothing to start from. A measurement that
  // failed only its gates while the anchor is recent saw the target: ORB on the same frame (a
  // smear, a hand) finds no better, and costs 12 ms.
  const bool measuredNearAnchor = stats.corners > 0 && haveAnchor && stats.rejection == Rejection::Evidence;
  if (verdict == Verdict::Rejected && !measuredNearAnchor) {
    // Relocalize; the candidate counts only when tracking from it (an independent, photometric
    // check against the keyframe) agrees.
    PlanarPose candidate;
    blur = blurBefore;
    if (relocalize(candidate)) {
      const int keyframe = chooseKeyframe(candidate);
      Measurement checked;
      // Agreeing within 5 %; or, where the refinement is overwhelming (three times TRACKING's
      // inliers, under 1 px), within 25 % and 10 deg: a target seen small (a 2 m floor mat from
      // 3.4 m, docs/authoring.md) gives ORB a pose off by more than 5 % that KLT still locks onto.
      if (track(candidate, keyframe, checked) && isStrong(checked) &&
          (posesAgree(candidate, checked.pose, 0.05) ||
           (checked.inliers >= 3 * settings.minTrackingInliers && checked.rms < 1.0 &&
            posesAgree(candidate, checked.pose, 0.25, 10.0)))) {
        stats.keyframe = keyframe;
        m = checked;
        verdict = judge(m, seconds, true);
      }
    }
  }

  if (verdict == Verdict::Rejected) blur = blurBefore;
  PlanarPose shown = m.pose;
  if (fromPending) {
    // A new start: the pending pose's motion is unknown, so the velocity starts here.
    confirmedCount = 0;
    havePending = false;
    gaveLast = false;
  }
  switch (verdict) {
    case Verdict::Tracking:
    case Verdict::Limited:
      // Confirmed: the motion model's base (a LIMITED pose passed the same checks, on looser evidence).
      havePending = false;
      confirm(m, seconds);
      result.state = verdict == Verdict::Tracking ? TrackingState::Tracking : TrackingState::Limited;
      break;
    case Verdict::Pending:
      pending = StampedPose{m.pose, seconds, m.covariance, m.positionSigma, m.rotationSigmaDeg};
      havePending = true;
      break;
    case Verdict::Rejected:
      havePending = false;
      break;
  }
  if (result.state != TrackingState::Lost) {
    result.inliers = m.inliers;
    result.reprojectionErrorPx = m.rms;
    result.covariance = m.covariance;
    result.positionSigmaM = m.positionSigma;
    result.rotationSigmaDeg = m.rotationSigmaDeg;
    if (result.state == TrackingState::Tracking) maybeExtendMap(m.pose, m.rms, m.inliers, m.tried);
  } else if (haveVelocity() && haveAnchor) {
    // Nothing measured to give: continue the confirmed motion while its worst case (the
    // largest acceleration for the time since the anchor, plus the velocity's own error)
    // stays drawable. Hand-held, that is a frame or two.
    const double dt = seconds - anchor.time;
    const double pair = confirmed[0].time - confirmed[1].time;
    const double velocityPosition = std::hypot(confirmed[0].positionSigma, confirmed[1].positionSigma) / pair;
    const double velocityRotation = std::hypot(confirmed[0].rotationSigmaDeg, confirmed[1].rotationSigmaDeg) / pair;
    const double worstPosition = 0.5 * settings.maxAcceleration * dt * (dt + pair) + 3 * velocityPosition * dt;
    const double worstRotation = 0.5 * settings.maxAngularAccelerationDeg * dt * (dt + pair) + 3 * velocityRotation * dt;
    if (dt <= settings.holdLimitedSeconds + 1e-9 && worstPosition <= settings.maxDrawnErrorM &&
        worstRotation <= settings.maxDrawnErrorDeg) {
      shown = extrapolateFrom(confirmed[1].pose, confirmed[1].time, confirmed[0].pose, confirmed[0].time,
                              anchor.pose, anchor.time, seconds);
      result.state = TrackingState::Limited;
      stats.extrapolated = true;
      // One standard deviation: the worst case read as three.
      result.positionSigmaM = std::hypot(anchor.positionSigma, worstPosition / 3);
      result.rotationSigmaDeg = std::hypot(anchor.rotationSigmaDeg, worstRotation / 3);
      const double grow = result.positionSigmaM * result.positionSigmaM - anchor.positionSigma * anchor.positionSigma;
      const double growRotation = (result.rotationSigmaDeg * result.rotationSigmaDeg -
                                   anchor.rotationSigmaDeg * anchor.rotationSigmaDeg) / (kDegrees * kDegrees);
      result.covariance = anchor.covariance;
      for (int i = 0; i < 3; ++i) {
        result.covariance[static_cast<std::size_t>(i * 7)] += growRotation / 3;
        result.covariance[static_cast<std::size_t>(21 + i * 7)] += grow / 3;
      }
    }
  }
  // What the next frame's background motion starts from.
  haveLastImageMotion = haveLastImageMotion && imageMotionFound;
  havePreviousFrame = true;
  havePreviousFramePose = true;
  previousFrameChained = false;
  if (result.state != TrackingState::Lost) previousFramePose = shown;
  else if (havePending) previousFramePose = pending.pose;
  else if (stats.backgroundMotion) previousFramePose = prediction, previousFrameChained = true;
  else havePreviousFramePose = false;
  if (result.state == TrackingState::Lost) {
    gaveLast = false;
    return result;
  }
  lastGivenTime = seconds;
  if (!gaveLast) filter.reset();  // a new stretch of poses: do not blend with the last one
  gaveLast = true;
  const glm::dmat4 raw = cameraToWorld(shown);
  const double distance = std::max(0.05, glm::length(glm::dvec3(raw[3])));
  result.cameraToWorld = settings.smoothing ? filter.filter(raw, seconds, distance) : raw;
  return result;
}

MarkerlessTracker::MarkerlessTracker(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MarkerlessTracker::~MarkerlessTracker() = default;

TrackedPose MarkerlessTracker::update(const ImageView& frame, double seconds) noexcept {
  try {
    return impl_->update(frame, seconds);
  } catch (const cv::Exception&) {
    impl_->forgetAll();  // OpenCV refused something: LOST, never a throw
    return {};
  } catch (const std::bad_alloc&) {
    impl_->forgetAll();
    return {};
  }
}

void MarkerlessTracker::reset() noexcept { impl_->forgetAll(); }

const CameraModel& MarkerlessTracker::camera() const noexcept { return impl_->camera; }
const PlanarMap& MarkerlessTracker::map() const noexcept { return impl_->map; }
const MarkerlessTracker::FrameStats& MarkerlessTracker::lastFrame() const noexcept { return impl_->stats; }

namespace {

std::string checkSettings(const MarkerlessSettings& s) {
  if (s.trackedCorners < 8 || s.trackedCorners > 2000) return "trackedCorners must be 8..2000";
  if (s.pyramidLevels < 0 || s.pyramidLevels > 6) return "pyramidLevels must be 0..6";
  if (s.kltWindow < 5 || s.kltWindow > 61) return "kltWindow must be 5..61";
  if (s.refinements < 0 || s.refinements > 5) return "refinements must be 0..5";
  if (s.relocalizationFeatures < 50 || s.relocalizationFeatures > 20000) return "relocalizationFeatures must be 50..20000";
  if (s.tiltedViewFeatures < 0 || s.tiltedViewFeatures > PlanarMap::kMaxPointsPerKeyframe)
    return "tiltedViewFeatures must be 0..20000";
  if (s.referenceFeatures < 50 || s.referenceFeatures > PlanarMap::kMaxPointsPerKeyframe)
    return "referenceFeatures must be 50..20000";
  if (s.minLimitedInliers < 6 || s.minTrackingInliers < s.minLimitedInliers)
    return "need 6 <= minLimitedInliers <= minTrackingInliers";
  if (!(s.maxTrackingRmsPx > 0) || !std::isfinite(s.maxTrackingRmsPx)) return "maxTrackingRmsPx must be positive";
  if (!(s.smoothingMinCutoffHz > 0) || !std::isfinite(s.smoothingMinCutoffHz) || !(s.smoothingBeta >= 0) ||
      !std::isfinite(s.smoothingBeta))
    return "smoothing cut-off must be positive and beta non-negative";
  if (!(s.holdLimitedSeconds >= 0) || !std::isfinite(s.holdLimitedSeconds)) return "holdLimitedSeconds must be >= 0";
  for (const double v : {s.maxSpeed, s.maxAcceleration, s.maxAngularSpeedDeg, s.maxAngularAccelerationDeg,
                         s.maxDrawnErrorM, s.maxDrawnErrorDeg, s.maxTrackingErrorM, s.maxTrackingErrorDeg,
                         s.minFeatureSigmaPx, s.effectiveFeatures})
    if (!(v > 0) || !std::isfinite(v))
      return "the motion model, drawn-error bounds, minFeatureSigmaPx and effectiveFeatures must be positive";
  for (const double v : {s.maxDrawnErrorFraction, s.maxTrackingErrorFraction, s.minTrackingSpread, s.minLimitedSpread,
                         s.minTrackingNcc, s.minLimitedNcc})
    if (!(v >= 0) || !std::isfinite(v)) return "the error fractions, spreads and NCC thresholds must be >= 0";
  return {};
}

}  // namespace

std::unique_ptr<MarkerlessTracker> MarkerlessTracker::fromTargetPixels(const CameraModel& camera,
                                                                       const ImageView& target, double targetWidth,
                                                                       const MarkerlessSettings& settings,
                                                                       Diagnostics& diagnostics) {
  if (const std::string p = camera.problem(); !p.empty()) {
    diagnostics.error("camera", p);
    return nullptr;
  }
  if (const std::string p = checkSettings(settings); !p.empty()) {
    diagnostics.error("tracker settings", p);
    return nullptr;
  }
  if (!std::isfinite(targetWidth) || !(targetWidth > 0) || targetWidth > 1e4) {
    diagnostics.error("--target-width", "the target's width must be a positive number of metres");
    return nullptr;
  }
  if (!target.valid() || target.channels != 1 || target.width < 32 || target.height < 32) {
    diagnostics.error("target", "the reference image must be grey and at least 32x32 pixels");
    return nullptr;
  }
  try {
    cv::Mat image(target.height, target.width, CV_8UC1, const_cast<std::uint8_t*>(target.pixels),
                  static_cast<std::size_t>(target.rowBytes()));
    cv::Mat scaled;
    const int side = std::max(image.cols, image.rows);
    if (side > kMaxReferenceSide) {
      const double f = static_cast<double>(kMaxReferenceSide) / side;
      cv::resize(image, scaled, cv::Size(), f, f, cv::INTER_AREA);
    } else {
      scaled = image.clone();
    }
    auto impl = std::make_unique<Impl>(camera, settings);
    impl->map.camera = camera;
    impl->map.keyframes.reserve(PlanarMap::kMaxKeyframes);  // the images stay where the pyramids view them
    impl->map.targetWidth = targetWidth;
    impl->map.targetHeight = targetWidth * scaled.rows / scaled.cols;
    const double metresPerPixel = targetWidth / scaled.cols;
    // (X, Z) -> pixel: u = X / s + w / 2 - 0.5 (pixel centres at integers, the target's
    // edges at +-width / 2).
    const cv::Matx33d planeToImage(1 / metresPerPixel, 0, scaled.cols * 0.5 - 0.5, 0, 1 / metresPerPixel,
                                   scaled.rows * 0.5 - 0.5, 0, 0, 1);
    impl->map.keyframes.push_back(impl->makeKeyframe(scaled, planeToImage));
    if (impl->map.keyframes[0].features.size() < 30 || impl->map.keyframes[0].corners.size() < 30) {
      diagnostics.error("target", "the reference image has too little texture to track (" +
                                      std::to_string(impl->map.keyframes[0].corners.size()) + " corners, " +
                                      std::to_string(impl->map.keyframes[0].features.size()) +
                                      " ORB features; at least 30 of each)");
      return nullptr;
    }
    impl->prepareKeyframe(0);
    return std::unique_ptr<MarkerlessTracker>(new MarkerlessTracker(std::move(impl)));
  } catch (const cv::Exception& e) {
    diagnostics.error("target", std::string("OpenCV failed: ") + e.what());
    return nullptr;
  }
}

std::unique_ptr<MarkerlessTracker> MarkerlessTracker::fromTarget(const CameraModel& camera,
                                                                 const std::string& targetImage, double targetWidth,
                                                                 const MarkerlessSettings& settings,
                                                                 Diagnostics& diagnostics) {
  cv::Mat image;
  try {
    image = cv::imread(targetImage, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    diagnostics.error(targetImage, std::string("cannot be read: ") + e.what());
    return nullptr;
  }
  if (image.empty()) {
    diagnostics.error(targetImage, "cannot be read as an image");
    return nullptr;
  }
  Diagnostics local;
  auto t = fromTargetPixels(camera, {image.data, image.cols, image.rows, 1, static_cast<std::ptrdiff_t>(image.step)},
                            targetWidth, settings, local);
  for (Diagnostic d : local.items) {
    if (d.file == "target") d.file = targetImage;
    diagnostics.items.push_back(std::move(d));
  }
  return t;
}

std::unique_ptr<MarkerlessTracker> MarkerlessTracker::fromMap(const CameraModel& camera, PlanarMap map,
                                                              const std::string& mapName,
                                                              const MarkerlessSettings& settings,
                                                              Diagnostics& diagnostics) {
  if (const std::string p = checkSettings(settings); !p.empty()) {
    diagnostics.error("tracker settings", p);
    return nullptr;
  }
  if (const std::string p = camera.problem(); !p.empty()) {
    diagnostics.error("camera", p);
    return nullptr;
  }
  const CameraModel& m = map.camera;
  auto close = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b)); };
  if (m.width != camera.width || m.height != camera.height || !close(m.fx, camera.fx) || !close(m.fy, camera.fy) ||
      !close(m.cx, camera.cx) || !close(m.cy, camera.cy)) {
    diagnostics.error(mapName, "the map was made with a " + std::to_string(m.width) + "x" + std::to_string(m.height) +
                                   " camera (fx " + std::to_string(m.fx) + "), not this " +
                                   std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                   " one (fx " + std::to_string(camera.fx) + "): make the map again with this camera");
    return nullptr;
  }
  try {
    auto impl = std::make_unique<Impl>(camera, settings);
    impl->map = std::move(map);
    impl->map.keyframes.reserve(PlanarMap::kMaxKeyframes);  // the images stay where the pyramids view them
    for (std::size_t i = 0; i < impl->map.keyframes.size(); ++i) impl->prepareKeyframe(i);
    return std::unique_ptr<MarkerlessTracker>(new MarkerlessTracker(std::move(impl)));
  } catch (const cv::Exception& e) {
    diagnostics.error(mapName, std::string("OpenCV failed on the map: ") + e.what());
    return nullptr;
  }
}

}  // namespace marionette::ar
