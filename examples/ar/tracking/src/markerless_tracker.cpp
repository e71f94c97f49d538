#include "marionette_ar/tracking/markerless_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "grey_frame.hpp"
#include "hamming_matcher.hpp"
#include "tilted_views.hpp"
#include "lucas_kanade.hpp"
#include "motion_blur.hpp"
#include "perspective_warp.hpp"
#include "planar_geometry.hpp"
#include "pose_filter.hpp"

namespace marionette::ar {

namespace {

constexpr int kMaxReferenceSide = 1024;  // larger references are scaled down (KLT works at camera scale)
constexpr int kCornersPerKeyframe = 500;
constexpr int kReferenceLevels = 4;  // the reference at 1, 1/2, 1/4, 1/8: warp from the nearest scale
constexpr int kMinRelocalizationInliers = 15;
constexpr double kMaxBlurFraction = 0.1;  // longest motion blur modelled, of the frame's width

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

  // Pose history (world -> OpenCV camera).
  bool havePose = false, havePrevious = false;
  PlanarPose pose, previous;
  double poseTime = 0, previousTime = 0, lastSeen = -1e300;
  TrackingState lastState = TrackingState::Lost;
  bool lastMeasured = false;  // the last frame's pose came from features, not extrapolation

  // Buffers reused every frame.
  cv::Mat warped, blurred;
  ImagePyramid framePyramid, templatePyramid;
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
    framePyramid.configure(c.width, c.height, s.pyramidLevels);
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
  bool track(const PlanarPose& prediction, int keyframe, PlanarPose& out, double& rms, int& inliers);
  int chooseKeyframe(const PlanarPose& prediction);
  bool relocalize(PlanarPose& out);
  void maybeExtendMap(const PlanarPose& p);
  // Past this the target is a few pixels wide and any homography fits it: not a pose.
  [[nodiscard]] double maxDistance() const noexcept { return 40.0 * std::max(map.targetWidth, map.targetHeight); }
  // Enough of the corners tried agree, closely: a verified pose. Blur, occlusion or a wrong
  // prediction leave fewer, looser inliers (LIMITED at best).
  [[nodiscard]] bool isStrong(int inliers, double rms) const noexcept {
    return inliers >= settings.minTrackingInliers && 3 * inliers >= stats.corners && rms <= settings.maxTrackingRmsPx;
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
    // The reference is sharper and exact: a camera keyframe must see clearly more.
    const int score = keyframes[k].reference ? count + count / 4 : count;
    if (score > bestCount) {
      bestCount = score;
      best = static_cast<int>(k);
    }
  }
  return best;
}

bool MarkerlessTracker::Impl::track(const PlanarPose& prediction, int keyframe, PlanarPose& out, double& rms,
                                    int& inliers) {
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  const cv::Mat& frame = grey.pinhole();
  PlanarPose current = prediction;
  inliers = 0;
  rms = 0;
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
      lk.track(templatePyramid, framePyramid, predicted, found, status, lkParams);
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
  out = current;
  return true;
}

bool MarkerlessTracker::Impl::relocalize(PlanarPose& out) {
  stats.relocalized = true;
  const cv::Mat& frame = grey.pinhole();
  orb->detectAndCompute(frame, cv::noArray(), frameKeypoints, frameDescriptors);
  if (frameKeypoints.size() < static_cast<std::size_t>(kMinRelocalizationInliers)) return false;
  int bestInliers = 0;
  for (const KeyframeData& kf : keyframes) {
    if (!kf.reference && !havePose) continue;  // floor keyframes relocalize only near the last pose (below)
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
      !(havePose && glm::length(cameraPosition(candidate) - cameraPosition(pose)) <
                        0.3 * std::max(0.05, glm::length(cameraPosition(pose)))))
    return;
  bestInliers = inliers;
  out = candidate;
}

void MarkerlessTracker::Impl::maybeExtendMap(const PlanarPose& p) {
  if (static_cast<int>(map.keyframes.size()) >= PlanarMap::kMaxKeyframes) return;
  if (visibleTargetFraction(K, camera, p, map.targetWidth, map.targetHeight) >= settings.extendBelowVisible) return;
  const glm::dvec3 c = cameraPosition(p);
  const double distance = std::max(0.05, c.y);
  for (const KeyframeData& k : keyframes)
    if (!k.reference && glm::length(k.cameraPosition - c) < 0.3 * distance) return;  // one near enough
  map.keyframes.push_back(makeKeyframe(grey.pinhole(), planeToImageHomography(K, p)));
  prepareKeyframe(map.keyframes.size() - 1);
  stats.keyframeAdded = true;
}

TrackedPose MarkerlessTracker::Impl::update(const ImageView& frame, double seconds) {
  stats = FrameStats{};
  TrackedPose result;
  if (!grey.load(frame) || !framePyramid.build(grey.pinhole())) return result;

  // Constant-velocity prediction from the last two poses.
  PlanarPose prediction = pose;
  if (havePose && havePrevious && poseTime > previousTime)
    prediction = extrapolate(previous, previousTime, pose, poseTime, seconds);

  PlanarPose estimate;
  double rms = 0;
  int inliers = 0;
  bool tracked = false, verified = false;
  if (havePose && seconds - lastSeen <= settings.holdLimitedSeconds + 1e-9) {
    stats.keyframe = chooseKeyframe(prediction);
    tracked = track(prediction, stats.keyframe, estimate, rms, inliers);
    verified = tracked && lastState == TrackingState::Tracking && lastMeasured;
  }
  if (!tracked) {
    // Relocalize; the pose counts only when tracking from it (an independent, photometric
    // check against the keyframe) agrees.
    PlanarPose candidate;
    if (relocalize(candidate)) {
      stats.keyframe = chooseKeyframe(candidate);
      PlanarPose checked;
      // Agreeing within 5 %; or, where the refinement is overwhelming (three times TRACKING's
      // inliers, under 1 px), within 25 % and 10 deg: a target seen small (a 2 m floor mat from
      // 3.4 m, docs/authoring.md) gives ORB a pose off by more than 5 % that KLT still locks onto.
      if (track(candidate, stats.keyframe, checked, rms, inliers) && isStrong(inliers, rms) &&
          (posesAgree(candidate, checked, 0.05) ||
           (inliers >= 3 * settings.minTrackingInliers && rms < 1.0 && posesAgree(candidate, checked, 0.25, 10.0)))) {
        estimate = checked;
        tracked = verified = true;
        filter.reset();
        havePrevious = false;
      }
    }
  }
  stats.inliers = inliers;
  stats.rmsPx = rms;
  PlanarPose shown = estimate;
  if (tracked) {
    previous = pose;
    previousTime = poseTime;
    havePrevious = havePose;
    pose = estimate;
    poseTime = seconds;
    havePose = true;
    lastSeen = seconds;
    // TRACKING: a strong pose that continues a measured one (this frame's features followed
    // from the last frame's pose) or a relocalization the photometric check confirmed.
    result.state = isStrong(inliers, rms) && (verified || lastMeasured) ? TrackingState::Tracking
                                                                       : TrackingState::Limited;
    lastMeasured = true;
    result.inliers = inliers;
    result.reprojectionErrorPx = rms;
    if (result.state == TrackingState::Tracking) maybeExtendMap(pose);
  } else if (havePose && seconds - lastSeen <= settings.holdLimitedSeconds) {
    // Features lost for a moment (a fast turn, a hand over the target): extrapolate briefly
    // from the last two measured poses (never from an extrapolation: that would compound).
    shown = prediction;
    result.state = TrackingState::Limited;
    lastMeasured = false;
  } else {
    havePose = havePrevious = lastMeasured = false;
    blur = {};
    filter.reset();
  }
  lastState = result.state;
  if (result.state == TrackingState::Lost) return result;
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
    impl_->havePose = impl_->havePrevious = false;  // OpenCV refused something: LOST, never a throw
    impl_->lastState = TrackingState::Lost;
    return {};
  } catch (const std::bad_alloc&) {
    impl_->havePose = impl_->havePrevious = false;
    impl_->lastState = TrackingState::Lost;
    return {};
  }
}

void MarkerlessTracker::reset() noexcept {
  impl_->havePose = impl_->havePrevious = impl_->lastMeasured = false;
  impl_->lastState = TrackingState::Lost;
  impl_->lastSeen = -1e300;
  impl_->filter.reset();
}

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
