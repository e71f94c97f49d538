#include "markerless_impl.hpp"

// The keyframes: prepared once, chosen per frame, matched by ORB to relocalize, and added as the
// view moves past what the map holds.

namespace marionette::ar {

PlanarKeyframe MarkerlessTracker::Impl::makeKeyframe(const cv::Mat& image, const cv::Matx33d& planeToImage,
                                                    bool withFeatures) {
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
  if (withFeatures) addFeatures(k);
  return k;
}

void MarkerlessTracker::Impl::addFeatures(PlanarKeyframe& k) {
  const cv::Mat image(k.height, k.width, CV_8UC1, k.grey.data());
  // 12 levels (a 7.4x range of scales): a keyframe is matched from close up and from afar.
  auto detector = cv::ORB::create(settings.referenceFeatures, 1.2f, 12, 19, 0, 2, cv::ORB::HARRIS_SCORE, 19, 15);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  detector->detectAndCompute(image, cv::noArray(), kps, desc);
  k.features.clear();
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
}

void MarkerlessTracker::Impl::prepareFeatures(std::size_t i) {
  const PlanarKeyframe& k = map.keyframes[i];
  KeyframeData& d = keyframes[i];
  d.descriptors.create(static_cast<int>(k.features.size()), 32, CV_8UC1);
  d.featurePixels.clear();
  for (std::size_t f = 0; f < k.features.size(); ++f) {
    std::copy_n(k.features[f].descriptor.begin(), 32, d.descriptors.ptr<std::uint8_t>(static_cast<int>(f)));
    d.featurePixels.emplace_back(k.features[f].x, k.features[f].y);
  }
}

void MarkerlessTracker::Impl::finishKeyframeFeatures(bool inFrame) noexcept {
  if (featuresPending < 0) return;
  const auto i = static_cast<std::size_t>(featuresPending);
  featuresPending = -1;
  if (inFrame) stats.keyframeFeatures = true;
  try {
    addFeatures(map.keyframes[i]);
    prepareFeatures(i);
  } catch (...) {
    // Out of memory inside OpenCV: the keyframe stays without features (it still tracks; it
    // does not relocalize).
    map.keyframes[i].features.clear();
    keyframes[i].descriptors.release();
    keyframes[i].featurePixels.clear();
  }
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
  d.denseLevels = d.levels;
  while (d.denseLevels.size() < 8 && d.denseLevels.back().cols >= 32 && d.denseLevels.back().rows >= 32) {
    cv::Mat down;
    cv::pyrDown(d.denseLevels.back(), down);
    d.denseLevels.push_back(down);
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
  if (!d.reference) {
    // The camera centre from the plane-to-image homography K [r1 r3 t].
    PlanarPose p;
    const bool havePose = poseFromPlaneHomography(K, d.planeToImage, p);
    if (havePose) d.cameraPosition = cameraPosition(p);
    // The lever: from the camera to the floor at the image's centre; where that ray misses the
    // floor in front (a view at or past the horizon) or reaches past the tracker's range, the
    // mean of the floor points its corners map (the points tracking uses).
    const cv::Vec3d h = d.imageToPlane * cv::Vec3d(k.width * 0.5, k.height * 0.5, 1.0);
    const cv::Vec3d onFloor(h[0] / h[2], 0.0, h[1] / h[2]);  // object coordinates (X, 0, Z)
    const glm::dvec3 centre = glm::dvec3(onFloor[0], 0.0, onFloor[2]) - d.cameraPosition;
    const double depth = (rotationFromRodrigues(p.rvec) * onFloor + p.tvec)[2];  // in front of the camera: > 0
    if (havePose && std::isfinite(centre.x) && std::isfinite(centre.z) && depth > 0 &&
        glm::length(centre) <= maxDistance()) {
      d.lever = centre;
    } else {
      glm::dvec3 sum(0.0);
      int counted = 0;
      for (const cv::Point2f& q : d.cornerPlane) {
        const glm::dvec3 v = glm::dvec3(q.x, 0.0, q.y) - d.cameraPosition;
        if (std::isfinite(v.x) && std::isfinite(v.z) && glm::length(v) <= maxDistance()) sum += v, ++counted;
      }
      d.lever = counted > 0 ? sum / static_cast<double>(counted) : glm::dvec3(0.0);
    }
    // A keyframe of the floor (the view past the target) keeps its pose's error, which reaches
    // far through the lever: 13 times sigma at the 99th percentile on fast_turn without it. One
    // added while tracking gets its pose's own covariance (maybeExtendMap). A map read from disk
    // keeps none: it was taken from a TRACKING pose, whose three standard deviations were within
    // TRACKING's bounds; half of them is taken (the whole bound would leave a pose measured
    // against it no room for its own error, never TRACKING again after a relaunch). A keyframe
    // of the target itself (closing in) is left out: its error is small and near (docs/tracking.md).
    // The floor around a target in view is the keyframe without ORB features (maybeExtendMap):
    // told apart by what it holds, not by a setting that may differ from the run that made it.
    if (havePose && (k.features.empty() ||
                     visibleTargetFraction(K, camera, p, map.targetWidth, map.targetHeight) < settings.extendBelowVisible)) {
      const double distance = glm::length(d.cameraPosition);
      const double position = std::max(settings.maxTrackingErrorM, settings.maxTrackingErrorFraction * distance) / 6;
      const double rotation = settings.maxTrackingErrorDeg / 6 / kDegrees;
      for (int a = 0; a < 3; ++a) {
        d.covariance[static_cast<std::size_t>(a * 7)] = rotation * rotation / 3;
        d.covariance[static_cast<std::size_t>(21 + a * 7)] = position * position / 3;
      }
    }
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
  prepareFeatures(i);
}


KeyframeChoice MarkerlessTracker::Impl::chooseKeyframes(const PlanarPose& prediction) {
  const cv::Matx33d G = planeToImageHomography(K, prediction);
  KeyframeChoice choice;
  int bestScore = -1, floorScore = minFloorRetryCorners() - 1;
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
    if (score > bestScore) bestScore = score, choice.best = static_cast<int>(k);
    if (!keyframes[k].reference && score > floorScore) floorScore = score, choice.floor = static_cast<int>(k);
  }
  return choice;
}

int MarkerlessTracker::Impl::keyframeToTrack(const KeyframeChoice& choice) const noexcept {
  const bool floorFirst = floorGoesFirst() && keyframes[static_cast<std::size_t>(choice.best)].reference && choice.floor > 0;
  return floorFirst ? choice.floor : choice.best;
}

void MarkerlessTracker::Impl::warmUpRelocalization() {
  // ORB's first frame-sized call costs twice a later one (15 against 7 ms on the stress
  // sequences' first frames): the allocator maps its pyramid's memory fresh. One call at
  // construction, on the reference scaled to the frame, moves that out of the first frame.
  if (keyframes.empty() || keyframes[0].levels.empty()) return;
  cv::Mat frameSized;
  cv::resize(keyframes[0].levels[0], frameSized, cv::Size(camera.width, camera.height), 0, 0, cv::INTER_AREA);
  orb->detectAndCompute(frameSized, cv::noArray(), frameKeypoints, frameDescriptors);
  frameKeypoints.clear();
}

bool MarkerlessTracker::Impl::relocalize(PlanarPose& out) {
  const StageTimer timer(stats.relocalizationMs);
  stats.relocalized = true;
  finishKeyframeFeatures(true);  // the keyframe added last may be the one this view matches
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

void MarkerlessTracker::Impl::maybeExtendMap(const Measurement& m) {
  const PlanarPose& p = m.pose;
  const double rms = m.rms;
  const int inliers = m.inliers, tried = m.tried;
  if (static_cast<int>(map.keyframes.size()) >= PlanarMap::kMaxKeyframes) return;
  // A keyframe when the view reaches past the target, or (as PTAM and ORB-SLAM add them as the
  // camera closes in) when the keyframe tracked against is seen much larger than it was taken:
  // its texture, magnified, no longer matches the frame's detail.
  const bool pastTarget = visibleTargetFraction(K, camera, p, map.targetWidth, map.targetHeight) < settings.extendBelowVisible;
  // Or the floor around a target that is in view (PTAM adds keyframes as the view moves): a look
  // away that comes back with the target at the image's edge finds the floor in the map. On a
  // sharp frame (a blurred keyframe would blur every later template) where most of the corners
  // tried agree (not under a hand: a keyframe of it would keep the hand), as `fading` asks too.
  const bool sharpAndAgreeing = !blur.any() && 5 * inliers >= 4 * tried;
  const bool aroundTarget = !pastTarget && sharpAndAgreeing &&
                            targetImageShare(K, camera, p, map.targetWidth, map.targetHeight) < settings.extendBelowImageShare;
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
  const bool fading = rms > 0.5 * settings.maxTrackingRmsPx && sharpAndAgreeing && nearest > 0.05 * distance;
  if (!pastTarget && !aroundTarget && !closer && !fading) return;
  for (std::size_t k = 0; k < keyframes.size() && !fading; ++k) {
    const KeyframeData& kf = keyframes[k];
    // (Past the target, one without ORB features does not count: relocalizing there needs them.)
    if (kf.reference || (pastTarget && kf.descriptors.rows == 0 && static_cast<int>(k) != featuresPending)) continue;
    // One near enough already, seen at about its own scale.
    if (glm::length(kf.cameraPosition - c) < 0.3 * distance &&
        keyframeMagnification(p, static_cast<int>(k)) <= kMaxMagnification)
      return;
  }
  // Around a target in view, no ORB features (most of a keyframe's time): relocalizing there, the
  // reference is in view too, and a floor keyframe relocalizes only near the last pose anyway.
  // Elsewhere the features come on a later frame with time to spare (finishKeyframeFeatures):
  // the keyframe tracks from now on.
  finishKeyframeFeatures(true);  // one pending at a time
  map.keyframes.push_back(makeKeyframe(grey.pinhole(), planeToImageHomography(K, p), false));
  prepareKeyframe(map.keyframes.size() - 1);
  if (!aroundTarget) featuresPending = static_cast<int>(map.keyframes.size()) - 1, featuresPendingSince = frames;
  // A keyframe of the floor keeps the error of the pose it was taken from; one of the target
  // (closing in, fading) none (prepareKeyframe takes a keyframe without features for the floor
  // around the target, as a map read from disk holds it).
  keyframes.back().covariance = pastTarget || aroundTarget ? m.covariance : std::array<double, 36>{};
  stats.keyframeAdded = true;
}

double MarkerlessTracker::Impl::keyframeMagnification(const PlanarPose& p, int keyframe) const {
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  const cv::Matx33d w = planeToImageHomography(K, p) * kf.imageToPlane;  // keyframe pixel -> frame pixel
  return homographyScaleAt(w, cv::Point2f(static_cast<float>(kf.levels[0].cols) * 0.5f,
                                          static_cast<float>(kf.levels[0].rows) * 0.5f));
}

}  // namespace marionette::ar
