#include "markerless_impl.hpp"

// Measuring a pose where KLT on corners gave none: the whole keyframe, blurred along the image's
// motion since the last frame, aligned to the frame (dense_alignment.hpp).

namespace marionette::ar {

cv::Vec3d MarkerlessTracker::Impl::frameIntervalTurn(const PlanarPose& prediction, bool& haveMotion) const noexcept {
  // The image's motion over the last frame interval: measured this frame, else the one the
  // last frame's pose and the prediction imply for the plane (the smear is the plane's).
  cv::Matx33d motion = cv::Matx33d::eye();
  haveMotion = imageMotionFound && haveLastImageMotion;
  if (haveMotion) {
    motion = lastImageMotion;
  } else if (havePreviousFramePose) {
    cv::Matx33d previousInverse;
    haveMotion = invertHomography(planeToImage(K, previousFramePose), previousInverse);
    if (haveMotion) motion = planeToImage(K, prediction) * previousInverse;
  }
  return haveMotion ? smearTurnFromMotion(K, motion, 1.0) : cv::Vec3d(0, 0, 0);
}

bool MarkerlessTracker::Impl::carriedPoseShows(const PlanarPose& pose, int keyframe) {
  const StageTimer timer(stats.denseMs);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  bool haveMotion = false;
  const cv::Vec3d turn = frameIntervalTurn(pose, haveMotion) * exposure;
  DenseAlignment at;
  if (!dense.verify(K, DenseTarget{kf.denseLevels, kf.planeToImage}, framePyramid(), turn, pose, denseParams, at))
    return false;
  stats.ncc = at.zncc;
  stats.visibleShare = at.visibleShare;
  stats.parts = at.parts;
  stats.agreeingParts = at.agreeingParts;
  stats.agreeingSpan = at.agreeingSpan;
  // The by-parts gate of a dense pose (markerless_gates.cpp), at the pose as carried: what shows
  // of the target is where the pose puts it.
  return at.visibleShare >= settings.minDenseVisibleShare && at.agreeingParts >= settings.minDenseAgreeingParts &&
         at.agreeingParts >= settings.minDenseAgreeingShare * at.parts && at.agreeingSpan >= settings.minDenseAgreeingSpan;
}

bool MarkerlessTracker::Impl::carry(const PlanarPose& prediction, StampedPose& out) {
  // The prediction is the last pose given, carried by the image's motion that KLT on the
  // background grid measured this frame. Not across a smear: the motion then comes from the
  // whole image's shift, or from a grid on smeared texture (1-2 deg off on the stress pans), and
  // parts agree along a smear wherever they are put on it.
  // Carried from the last pose given, through the frames since (LOST ones too, where the chain
  // of measured motions held): each adds the carry's error.
  if (!settings.carryPoses || !stats.backgroundMotion || !imageMotionFound || stats.imageShift ||
      chainedSinceGiven < 0 || carriedFrames + chainedSinceGiven >= settings.maxCarriedFrames)
    return false;
  bool haveTurn = false;
  const double smearPx = cv::norm(frameIntervalTurn(prediction, haveTurn)) * K(0, 0) * exposure;
  if (!(smearPx < kDenseFirstSmearPx)) return false;
  // The last pose's covariance and the carry's error a frame: given while three sigma stay drawable.
  out = StampedPose{prediction, lastGiven.time, lastGiven.covariance, 0, 0};
  const double steps = chainedSinceGiven + 1;
  const double rotation = settings.carryRotationSigmaDeg / kDegrees, position = settings.carryPositionSigmaM;
  for (int i = 0; i < 3; ++i) {
    out.covariance[static_cast<std::size_t>(i * 7)] += steps * rotation * rotation / 3;
    out.covariance[static_cast<std::size_t>(21 + i * 7)] += steps * position * position / 3;
  }
  covarianceSigmas(out.covariance.data(), out.positionSigma, out.rotationSigmaDeg);
  const double drawnM = std::max(settings.maxDrawnErrorM,
                                 settings.maxDrawnErrorFraction * glm::length(cameraPosition(prediction)));
  return 3 * out.positionSigma <= drawnM && 3 * out.rotationSigmaDeg <= settings.maxDrawnErrorDeg &&
         carriedPoseShows(prediction, chooseKeyframe(prediction));
}

bool MarkerlessTracker::Impl::alignDense(const PlanarPose& prediction, int keyframe, Measurement& out) {
  const StageTimer timer(stats.denseMs);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  stats.predicted = true;
  stats.predictedCameraToWorld = cameraToWorld(prediction);
  bool haveMotion = false;
  const cv::Vec3d frameTurn = frameIntervalTurn(prediction, haveMotion);
  DenseAlignment result;
  const DenseTarget target{kf.denseLevels, kf.planeToImage};
  // The turn over the exposure is at most the interval's as measured (kMaxExposureShare of it,
  // and a pixel's worth): otherwise a hand crossing a still target is explained as a smear of
  // everything.
  DenseAlignmentParams params = denseParams;
  if (imageMotionFound && haveMotion) {
    params.maxSmearTurn = std::min(params.maxSmearTurn, kMaxExposureShare * cv::norm(frameTurn) + 1.0 / K(0, 0));
    // The start is the image's measured motion's (within a degree or so): a wide search would
    // only find a wrong peak along a long smear, where the correlation is flat.
    params.searchRadius = std::min(params.searchRadius, kMeasuredStartSearchRadius);
  }
  if (!dense.align(K, target, framePyramid(), frameTurn * exposure, prediction, params, result)) return false;
  // The exposure the frame's blur shows (its turn against the frame interval's), where the turn
  // is long enough to tell: cameras keep an exposure for many frames, the next smeared frame
  // starts from it.
  double measuredExposure = 0;
  const double frameAngle = cv::norm(frameTurn);
  if (imageMotionFound && frameAngle * K(0, 0) >= 8) {
    // The turn the blur shows must be about the axis of the image's measured one (either sense:
    // a smear has no direction); otherwise the alignment explained the blur by another pose, or
    // by something else moving (a hand crossing in its own direction): aligned again under the
    // measured smear, kept as it is.
    const double turnAngle = cv::norm(result.smearTurn);
    const double ratio = turnAngle / frameAngle;
    if (std::abs(result.smearTurn.dot(frameTurn)) >= kMinSmearAxisCosine * turnAngle * frameAngle) {
      measuredExposure = std::clamp(ratio, 0.1, 1.0);
    } else {
      params.fitSmear = false;
      if (!dense.align(K, target, framePyramid(), frameTurn * exposure, prediction, params, result)) return false;
    }
  }
  const glm::dvec3 c = cameraPosition(result.pose);
  if (!(c.y > 1e-3) || !(glm::length(c) <= maxDistance())) return false;
  out = Measurement{};
  out.pose = result.pose;
  out.dense = true;
  out.ncc = result.zncc;
  out.inlierShare = result.inlierShare;
  out.visibleShare = result.visibleShare;
  out.parts = result.parts;
  out.agreeingParts = result.agreeingParts;
  out.agreeingSpan = result.agreeingSpan;
  out.smearPx = result.smearPx;
  out.exposure = measuredExposure;
  out.rms = result.sigma;
  // As counts (the per-frame logs show them as inliers/tried): the samples within Huber's
  // threshold of the samples.
  out.tried = result.samples;
  out.inliers = static_cast<int>(std::lround(result.inlierShare * result.samples));
  out.spread = 1;
  for (std::size_t i = 0; i < 36; ++i) out.covariance[i] = result.covariance[i] * settings.denseCovarianceScale;
  // The model's own error (line smears of a turn, no camera translation over the exposure, the
  // pyramid's smoothing): a floor under the pixels' statistics.
  for (int i = 0; i < 3; ++i) {
    out.covariance[static_cast<std::size_t>(i * 7)] += kDenseFloorRotationRad * kDenseFloorRotationRad / 3;
    out.covariance[static_cast<std::size_t>(21 + i * 7)] += kDenseFloorPositionM * kDenseFloorPositionM / 3;
  }
  addKeyframeError(kf, out.covariance.data());
  covarianceSigmas(out.covariance.data(), out.positionSigma, out.rotationSigmaDeg);
  out.haveCovariance = std::isfinite(out.positionSigma) && std::isfinite(out.rotationSigmaDeg);
  stats.blurPx = result.smearPx;
  return out.haveCovariance;
}

}  // namespace marionette::ar
