#include "markerless_impl.hpp"

// Measuring a pose where KLT on corners gave none: the whole keyframe, blurred along the image's
// motion since the last frame, aligned to the frame (dense_alignment.hpp).

namespace marionette::ar {

cv::Vec3d MarkerlessTracker::Impl::frameIntervalTurn(const PlanarPose& prediction, bool& haveMotion,
                                                     bool poseDifference) const noexcept {
  // The image's motion over the last frame interval: measured this frame, else the one the
  // last frame's pose and the prediction imply for the plane (the smear is the plane's).
  cv::Matx33d motion = cv::Matx33d::eye();
  haveMotion = imageMotionFound && haveLastImageMotion;
  if (haveMotion) {
    motion = lastImageMotion;
  } else if (havePreviousFramePose && poseDifference) {
    cv::Matx33d previousInverse;
    haveMotion = invertHomography(planeToImage(K, previousFramePose), previousInverse);
    if (haveMotion) motion = planeToImage(K, prediction) * previousInverse;
  }
  return haveMotion ? smearTurnFromMotion(K, motion, 1.0) : cv::Vec3d(0, 0, 0);
}

Measurement MarkerlessTracker::Impl::denseEvidence(const DenseAlignment& a, const KeyframeData& kf) noexcept {
  Measurement m;
  m.onFloor = !kf.reference;
  m.frameShare = a.frameShare;
  m.pose = a.pose;
  m.dense = true;
  m.ncc = a.zncc;
  m.inlierShare = a.inlierShare;
  m.visibleShare = a.visibleShare;
  m.parts = a.parts;
  m.agreeingParts = a.agreeingParts;
  m.agreeingSpan = a.agreeingSpan;
  m.smearPx = a.smearPx;
  return m;
}

bool MarkerlessTracker::Impl::carriedPoseShows(const PlanarPose& pose, int keyframe, const cv::Vec3d& smearTurn) {
  const StageTimer timer(stats.denseMs);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  DenseAlignment at;
  if (!dense.verify(K, DenseTarget{kf.denseLevels, kf.planeToImage}, framePyramid(), smearTurn, pose, denseParams, at))
    return false;
  const Measurement seen = denseEvidence(at, kf);
  notePhotometricEvidence(seen);
  // The by-parts gate of a dense pose, at the pose as carried: what shows of the keyframe seen
  // most (the target, or the floor around it, on the same plane) is where the pose puts it.
  return seen.viewShare() >= settings.minDenseVisibleShare && agreesByParts(seen);
}

bool MarkerlessTracker::Impl::carry(const PlanarPose& prediction, double seconds, StampedPose& out) {
  // The prediction is the last pose given, carried by the image's motion that KLT on the
  // background grid measured this frame, through the frames since (LOST ones too, where the
  // chain of measured motions held). Not across a smear: the motion then comes from the whole
  // image's shift, or from a grid on smeared texture (1-2 deg off on the stress pans), and parts
  // agree along a smear wherever they are put on it.
  if (!settings.carryPoses || !stats.backgroundMotion || !imageMotionFound || stats.imageShift ||
      chainedSinceGiven < 0 || carriedFrames + chainedSinceGiven >= settings.maxCarriedFrames)
    return false;
  bool haveTurn = false;
  const cv::Vec3d smearTurn = frameIntervalTurn(prediction, haveTurn) * exposure;
  if (!(cv::norm(smearTurn) * K(0, 0) < kDenseFirstSmearPx)) return false;
  // The last pose's covariance plus the carry's error for each frame since: given while three
  // sigma stay drawable.
  out = StampedPose{prediction, seconds, lastGiven.covariance, 0, 0};
  const double steps = chainedSinceGiven + 1;
  const double rotation = settings.carryRotationSigmaDeg / kDegrees, position = settings.carryPositionSigmaM;
  addIsotropicVariance(out.covariance.data(), steps * rotation * rotation, steps * position * position);
  covarianceSigmas(out.covariance.data(), out.positionSigma, out.rotationSigmaDeg);
  const double drawnM = std::max(settings.maxDrawnErrorM,
                                 settings.maxDrawnErrorFraction * glm::length(cameraPosition(prediction)));
  return 3 * out.positionSigma <= drawnM && 3 * out.rotationSigmaDeg <= settings.maxDrawnErrorDeg &&
         carriedPoseShows(prediction, chooseKeyframe(prediction), smearTurn);
}

bool MarkerlessTracker::Impl::alignDense(const PlanarPose& prediction, int keyframe, Measurement& out,
                                         bool poseDifference) {
  const StageTimer timer(stats.denseMs);
  const KeyframeData& kf = keyframes[static_cast<std::size_t>(keyframe)];
  stats.predicted = true;
  stats.predictedCameraToWorld = cameraToWorld(prediction);
  bool haveMotion = false;
  const cv::Vec3d frameTurn = frameIntervalTurn(prediction, haveMotion, poseDifference);
  DenseAlignment result;
  const DenseTarget target{kf.denseLevels, kf.planeToImage};
  // The turn over the exposure is at most the interval's as measured (kMaxExposureShare of it,
  // and a pixel's worth): otherwise a hand crossing a still target is explained as a smear of
  // everything.
  DenseAlignmentOptions params = denseParams;
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
  out = denseEvidence(result, kf);
  out.exposure = measuredExposure;
  out.rms = result.sigma;
  // As counts (the per-frame logs show them as inliers/tried): the samples within Huber's
  // threshold of the samples.
  out.tried = result.samples;
  out.inliers = static_cast<int>(std::lround(result.inlierShare * result.samples));
  out.spread = 1;
  // A pose that only parts of the target support (not explained as a whole: a hand over the
  // rest) knows what those parts' samples tell: the covariance from theirs alone, and no pose
  // without one (no part agrees, or theirs leave the pose undetermined).
  const bool byPartsOnly = !explainedAsWhole(out);
  if (byPartsOnly && !result.haveAgreeingCovariance) return false;
  const std::array<double, 36>& fitted = byPartsOnly ? result.agreeingCovariance : result.covariance;
  for (std::size_t i = 0; i < 36; ++i) out.covariance[i] = fitted[i] * settings.denseCovarianceScale;
  // The model's own error (line smears of a turn, no camera translation over the exposure, the
  // pyramid's smoothing): a floor under the pixels' statistics.
  addIsotropicVariance(out.covariance.data(), kDenseFloorRotationRad * kDenseFloorRotationRad,
                       kDenseFloorPositionM * kDenseFloorPositionM);
  addKeyframeError(kf, out.covariance.data());
  covarianceSigmas(out.covariance.data(), out.positionSigma, out.rotationSigmaDeg);
  out.haveCovariance = std::isfinite(out.positionSigma) && std::isfinite(out.rotationSigmaDeg);
  stats.blurPx = result.smearPx;
  return out.haveCovariance;
}

}  // namespace marionette::ar
