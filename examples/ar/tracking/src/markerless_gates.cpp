#include "markerless_impl.hpp"

// Judging a measurement: its evidence, the motion model, and the confirmation a relocalization
// or an off-model pose waits for (docs/tracking.md, "Gating and confidence").

namespace marionette::ar {

Evidence MarkerlessTracker::Impl::evidenceOf(const Measurement& m) const noexcept {
  if (!m.haveCovariance) return Evidence::None;
  const double distance = glm::length(cameraPosition(m.pose));
  const double drawnM = std::max(settings.maxDrawnErrorM, settings.maxDrawnErrorFraction * distance);
  if (m.dense) {
    // The whole target's pixels explained by the blurred keyframe: LIMITED at best (the smear
    // leaves the pose less certain along it, and the model is the frame's motion's, not seen).
    // Explained as a whole, or by parts where something covers the rest (docs/tracking.md).
    const bool whole = explainedAsWhole(m);
    const bool byParts = agreesByParts(m);
    const bool inView = m.viewShare() >= settings.minDenseVisibleShare;
    const bool sliver = m.viewShare() >= settings.minDenseSliverShare && m.parts >= settings.minDenseSliverParts &&
                        m.agreeingParts == m.parts && whole;
    const bool limited = ((inView && (whole || byParts)) || sliver) && 3 * m.positionSigma <= drawnM &&
                         3 * m.rotationSigmaDeg <= settings.maxDrawnErrorDeg;
    return limited ? Evidence::Limited : Evidence::None;
  }
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
  const double trackingM = std::max(settings.maxTrackingErrorM, settings.maxTrackingErrorFraction * distance);
  const bool limited = m.inliers >= settings.minLimitedInliers && m.spread >= settings.minLimitedSpread &&
                       m.ncc >= settings.minLimitedNcc && 3 * m.positionSigma <= drawnM &&
                       3 * m.rotationSigmaDeg <= settings.maxDrawnErrorDeg;
  if (!limited) return Evidence::None;
  const bool tracking = isStrong(m) && m.spread >= settings.minTrackingSpread && m.ncc >= settings.minTrackingNcc &&
                        3 * m.positionSigma <= trackingM && 3 * m.rotationSigmaDeg <= settings.maxTrackingErrorDeg;
  return tracking ? Evidence::Tracking : Evidence::Limited;
}

bool MarkerlessTracker::Impl::explainedAsWhole(const Measurement& m) const noexcept {
  return m.ncc >= settings.minDenseZncc && m.inlierShare >= settings.minDenseInlierShare;
}

bool MarkerlessTracker::Impl::agreesByParts(const Measurement& m) const noexcept {
  return m.agreeingParts >= settings.minDenseAgreeingParts && m.agreeingParts >= settings.minDenseAgreeingShare * m.parts &&
         m.agreeingSpan >= settings.minDenseAgreeingSpan;
}

void MarkerlessTracker::Impl::notePhotometricEvidence(const Measurement& m) noexcept {
  stats.ncc = m.ncc;
  stats.inlierShare = m.inlierShare;
  stats.visibleShare = m.visibleShare;
  stats.frameShare = m.frameShare;
  stats.parts = m.parts;
  stats.agreeingParts = m.agreeingParts;
  stats.agreeingSpan = m.agreeingSpan;
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
  stats.dense = m.dense;
  notePhotometricEvidence(m);  // the ncc too (KLT's measurements leave the dense fields at 0)
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

}  // namespace marionette::ar
