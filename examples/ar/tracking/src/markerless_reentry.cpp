#include "markerless_impl.hpp"

// The target coming back after the image's motion lost it: a look away through a smear that
// defeated the frame-to-frame motion, or up at a blank sky. Nothing predicts the pose then, and
// ORB finds no features in a smear of 40-100 px, so the target used to stay LOST until the camera
// slowed down (docs/tracking.md, "Re-entry along the way out"). A camera that looked away mostly
// comes back the way it went: the poses of the way out (given, or carried by the image's motion)
// are starts for the dense alignment, which follows such smears from a start within its search.

namespace marionette::ar {

void MarkerlessTracker::Impl::rememberExitPath(const PlanarPose& pose) {
  // Only where the target is in view or near it: the target comes back at the edge it left by,
  // and a long look away would push those poses out of the path. A new pose where the view
  // turned or moved (a sideways step) since the last one kept.
  if (!targetNearView(K, camera, pose, map.targetWidth, map.targetHeight,
                      kAwayMarginFraction * std::max(camera.width, camera.height)) ||
      (exitPathCount > 0 && rotationBetweenDeg(pose, exitPath[0]) < kExitPathStepDeg &&
       glm::length(cameraPosition(pose) - cameraPosition(exitPath[0])) <
           kExitPathStepShare * glm::length(cameraPosition(exitPath[0]))))
    return;
  for (int i = std::min(exitPathCount, kExitPathPoses - 1); i > 0; --i)
    exitPath[static_cast<std::size_t>(i)] = exitPath[static_cast<std::size_t>(i - 1)];
  exitPath[0] = pose;
  exitPathCount = std::min(exitPathCount + 1, kExitPathPoses);
}

bool MarkerlessTracker::Impl::searchReentry(double seconds, Measurement& out) {
  if (!settings.reentrySearch || !settings.denseAlignment || exitPathCount == 0 || keyframes.empty() ||
      !(seconds - lastGivenTime <= settings.reentrySearchSeconds))
    return false;
  // The smear: the image's motion since the last frame (no pose needed; not again where this
  // frame's chain already tried), over the exposure; none where it cannot be measured.
  if (!imageMotionTried && havePreviousFrame) {
    const StageTimer timer(stats.motionMs);
    (void)measureImageMotion(haveLastImageMotion ? lastImageMotion : cv::Matx33d::eye());
  }
  const cv::Vec3d smearTurn = imageMotionFound ? smearTurnFromMotion(K, lastImageMotion, exposure) : cv::Vec3d(0, 0, 0);
  // Against the reference only: the floor around it repeats its texture at every tile of a
  // carpet, the target does not.
  const KeyframeData& reference = keyframes[0];
  const DenseTarget target{reference.denseLevels, reference.planeToImage};
  PlanarPose best;
  double bestScore = kMinReentryScore;
  {
    const StageTimer timer(stats.denseMs);
    for (int i = 0; i < exitPathCount; ++i) {
      PlanarPose shifted;
      double score = 0;
      if (dense.probe(K, target, framePyramid(), smearTurn, exitPath[static_cast<std::size_t>(i)], denseParams, shifted,
                      score) &&
          score > bestScore)
        best = shifted, bestScore = score;
    }
  }
  if (!(bestScore > kMinReentryScore)) return false;
  Measurement aligned;
  if (!alignDense(best, 0, aligned, false)) return false;
  // The next frame confirms it from this pose, densely again: the two are not independent, so
  // this one must be explained both as a whole and by its parts (either suffices elsewhere).
  if (!explainedAsWhole(aligned) || !agreesByParts(aligned)) return false;
  out = aligned;
  return true;
}

}  // namespace marionette::ar
