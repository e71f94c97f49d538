#include "markerless_impl.hpp"

// The image's own motion from the last frame to this one: what carries the pose through a sudden
// turn, a smear, or a look away.

namespace marionette::ar {

bool MarkerlessTracker::Impl::backgroundPrediction(const PlanarPose& guess, PlanarPose& out, bool guessHasVelocity) {
  const StageTimer timer(stats.motionMs);
  if (!settings.backgroundMotion || !havePreviousFrame || !havePreviousFramePose) return false;
  const cv::Matx33d previousG = planeToImageHomography(K, previousFramePose);
  const cv::Matx33d guessG = planeToImageHomography(K, guess);
  // Last frame's pixel -> this frame's, as guessed; a guess without a velocity (a chain through a
  // look away), or one older than the image's last measured motion, starts from that motion
  // instead (a pan goes on).
  const bool fromLastMotion = (!guessHasVelocity || previousFrameChained) && haveLastImageMotion;
  const cv::Matx33d guessMotion = fromLastMotion ? lastImageMotion : cv::Matx33d(guessG * previousG.inv());
  // Started from the last motion, a second call this frame (the chain's prediction, then the
  // fallback after tracking failed) would repeat a failed search to the bit.
  if (fromLastMotion && lastMotionFailed) return false;
  if (!measureImageMotion(guessMotion)) {
    lastMotionFailed = lastMotionFailed || fromLastMotion;
    return false;
  }
  PlanarPose moved;
  if (!poseFromPlaneHomography(K, lastImageMotion * previousG, moved)) return false;
  const glm::dvec3 c = cameraPosition(moved);
  if (!(c.y > 1e-3) || !(glm::length(c) <= maxDistance())) return false;
  out = moved;
  return true;
}

bool MarkerlessTracker::Impl::measureImageMotion(const cv::Matx33d& guessMotion) {
  imageMotionTried = true;
  cv::Matx33d motion;
  if (!gridImageMotion(guessMotion, motion) && !shiftImageMotion(guessMotion, motion)) return false;
  lastImageMotion = motion;
  haveLastImageMotion = true;
  imageMotionFound = true;
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
  LucasKanadeOptions params;
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
  HomographyRansacOptions ransac;
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
  ImageShiftOptions params;
  params.coarseLevel = std::min(settings.pyramidLevels, 3);
  ImageShift shift;
  if (!estimateImageShift(pyramids[static_cast<std::size_t>(currentFrame ^ 1)], framePyramid(), guess, params, shift))
    return false;
  motion = rotationShiftHomography(K, shift.shift);
  stats.imageShift = true;
  return true;
}

}  // namespace marionette::ar
