#include "markerless_impl.hpp"

namespace marionette::ar {

bool MarkerlessTracker::Impl::predict(double seconds, PlanarPose& out) {
  if (havePending) {
    out = pending.pose;  // no velocity known yet (the image's motion is the fallback, below)
    return true;
  }
  // The last frame's estimate carried by the image's motion: while the anchor is recent, once
  // the last frame was itself carried so (nothing measured since; the anchor's velocity, older,
  // would overshoot a turn); without an anchor, for kMaxChainSeconds after the last pose given.
  const bool chain = haveAnchor ? previousFrameChained
                                : havePreviousFramePose && seconds - lastGivenTime <= kMaxChainSeconds;
  if (chain && backgroundPrediction(previousFramePose, out, false)) {
    stats.backgroundMotion = true;
    chainPrediction = out;
    haveChainPrediction = true;
    return true;
  }
  if (!haveAnchor) return false;
  out = haveVelocity() ? extrapolateFrom(confirmed[1].pose, confirmed[1].time, confirmed[0].pose,
                                         confirmed[0].time, anchor.pose, anchor.time, seconds)
                       : anchor.pose;
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
  if (seconds - lastGivenTime > settings.reentrySearchSeconds) exitPathCount = 0;  // too long ago to search from
  if (haveAnchor && seconds - anchor.time > hold) {
    haveAnchor = false;
    blur = {};
  }
}

void MarkerlessTracker::Impl::forgetAll() noexcept {
  confirmedCount = 0;
  haveAnchor = havePending = gaveLast = havePreviousFrame = havePreviousFramePose = haveLastImageMotion = previousFrameChained = false;
  chainedSinceGiven = -1;
  carriedFrames = 0;
  floorFirstUntil = -1;
  exitPathCount = 0;
  blur = {};
  lastDenseSmearPx = 0;
  filter.reset();
  framePosed = false;  // the occlusion mask of this frame, asked after, is empty
  occlusionFrame = -1;
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
  ++frames;
  framePosed = false;
  TrackedPose result;
  if (!loadFrame(frame)) return result;
  forgetOld(seconds);
  haveChainPrediction = false;
  imageMotionFound = lastMotionFailed = imageMotionTried = false;

  // The smear is the last accepted measurement's: an attempt judged wrong leaves it as it was
  // (a smear proposed on a wrong prediction would blur the template of every later attempt).
  const MotionBlur blurBefore = blur;
  // Track from the prediction: the pending pose, or the anchor moved by the confirmed velocity.
  PlanarPose prediction;
  Measurement m;
  Verdict verdict = Verdict::Rejected;
  const bool havePrediction = predict(seconds, prediction);
  // A pending pose has no velocity: the image's motion is searched from its last measured one,
  // not from no motion at all (a pan goes on while a relocalization waits for confirmation).
  const bool predictionHasVelocity = !havePending;
  // The dense alignment from `from`: taken when its verdict is not a rejection.
  bool denseTried = false;
  auto tryDense = [&](const PlanarPose& from) {
    denseTried = true;
    Measurement aligned;
    if (!alignDense(from, stats.keyframe, aligned)) return false;
    const Verdict v = judge(aligned, seconds, false);
    if (v == Verdict::Rejected) return false;
    m = aligned, verdict = v;
    if (aligned.exposure > 0) exposure = aligned.exposure, exposureMeasured = true;
    return true;
  };
  // A smear past what KLT on corners follows (the image's motion measured this frame, over the
  // exposure, makes one; or the last frame's dense alignment measured one): the dense alignment
  // goes first.
  const bool smeared =
      settings.denseAlignment && (expectedSmearPx() >= kDenseFirstSmearPx || lastDenseSmearPx >= kDenseFirstSmearPx);
  if (havePrediction && smeared && !stats.backgroundMotion) {
    // The smear and the start from the image's own motion, measured: a smear extrapolated from
    // the last poses' velocity left a dense pose 2.4 deg off on the stress sequences.
    PlanarPose moved;
    if (backgroundPrediction(prediction, moved, predictionHasVelocity)) prediction = moved, stats.backgroundMotion = true;
  }
  KeyframeChoice choice;  // for the current prediction
  if (havePrediction) {
    choice = chooseKeyframes(prediction);
    stats.keyframe = keyframeToTrack(choice);
    if (!(smeared && tryDense(prediction)) && track(prediction, stats.keyframe, m)) verdict = judge(m, seconds, false);
  }
  // The constant-velocity prediction found nothing usable (a sudden turn, a smear hiding the
  // corners): try again from where the whole image's motion since the last frame puts the pose.
  if (havePrediction && verdict == Verdict::Rejected && !stats.backgroundMotion) {
    PlanarPose moved;
    if (backgroundPrediction(prediction, moved, predictionHasVelocity)) {
      blur = blurBefore;
      stats.backgroundMotion = true;
      prediction = moved;
      choice = chooseKeyframes(prediction);
      stats.keyframe = keyframeToTrack(choice);
      denseTried = false;
      Measurement retried;
      // Where the image's motion makes a long smear, so would KLT: 2 of 35 retries where the
      // grid failed gave a pose on the stress sequences (but a fast turn that only outran the
      // grid is no smear: fast_turn needs the retry). Nor where KLT already ran under the blur
      // model (a smear of kDenseCheckBlurPx or more: the last frame's, or the one this frame's
      // statistics proposed and its aligned patches did not refute) and found nothing usable:
      // from this prediction it meets the same frame, and the dense alignment, which measures
      // the smear from the image's motion, goes next (on the stress sequences the retry cost
      // 10-15 ms on such frames and the dense pose was given after it anyway; skipped, p95 17.1
      // -> 15.3 ms, every class within 2 cm as often or more: docs/tracking.md).
      const bool kltFailedUnderSmear = settings.denseAlignment && stats.blurPx >= kDenseCheckBlurPx;
      if ((expectedSmearPx() < kDenseFirstSmearPx || !settings.denseAlignment) && !kltFailedUnderSmear &&
          track(prediction, stats.keyframe, retried)) {
        const Verdict v = judge(retried, seconds, false);
        if (v != Verdict::Rejected) m = retried, verdict = v;
      }
    }
  }
  // Still nothing: the dense alignment of the whole keyframe (a smear that KLT cannot follow).
  // (A smear proposed by the KLT attempts that failed is not kept: the dense pose measured its own.)
  if (havePrediction && verdict == Verdict::Rejected && settings.denseAlignment && !denseTried && tryDense(prediction))
    blur = blurBefore;
  // Still nothing: the other kind of keyframe. Against the reference, the floor around it where
  // a keyframe of the floor sees the view (a hand over most of the target leaves the floor in
  // sight: its corners under the hand are RANSAC's outliers); the floor goes first for the next
  // frames. Against the floor first, the reference (the hand has left). Not where the image's
  // motion measured this frame makes a smear KLT cannot follow (as the retry above).
  if (havePrediction && verdict == Verdict::Rejected && stats.keyframe >= 0 &&
      (expectedSmearPx() < kDenseFirstSmearPx || !settings.denseAlignment)) {
    const bool onReference = keyframes[static_cast<std::size_t>(stats.keyframe)].reference;
    const bool floorWentFirst = !onReference && floorGoesFirst();
    const int other = onReference ? choice.floor : floorWentFirst ? 0 : -1;
    Measurement retried;
    if (other >= 0 && other != stats.keyframe) {
      blur = blurBefore;
      const int before = stats.keyframe;
      stats.keyframe = other;
      if (!track(prediction, other, retried)) {
        stats.keyframe = before;  // the figures logged are still the earlier attempt's
      } else {
        const Verdict v = judge(retried, seconds, false);
        if (v != Verdict::Rejected) {
          m = retried, verdict = v;
          floorFirstUntil = onReference ? frames + kFloorFirstFrames : -1;
        }
      }
    }
  }
  // A LIMITED pose of KLT under a smear, from a loose fit (that a bare majority of corners
  // supports), is checked against all of the target's pixels: the dense pose replaces it where it
  // passes.
  if (verdict == Verdict::Limited && !m.dense && stats.blurPx >= kDenseCheckBlurPx && m.rms > kLooseFitPx &&
      settings.denseAlignment) {
    const Measurement klt = m;
    const Verdict kltVerdict = verdict;
    const MotionBlur kltBlur = blur;
    const FrameStats kltStats = stats;  // the logs describe the pose given
    if (!tryDense(klt.pose)) m = klt, verdict = kltVerdict, blur = kltBlur, stats = kltStats;
  }
  const bool fromPending = havePending && (verdict == Verdict::Tracking || verdict == Verdict::Limited);
  // Relocalize when tracking found nothing, or had nothing to start from. A measurement that
  // failed only its gates while the anchor is recent saw the target: ORB on the same frame (a
  // smear, a hand) finds no better, and costs 12 ms.
  // (A dense alignment that saw the target counts too: ORB finds nothing in a smear. Saw it:
  // the whole or enough of its parts agree; a fit that ends anywhere, after a cut, saw nothing.)
  const bool denseSawTarget = stats.dense && (stats.ncc >= settings.minDenseZncc ||
                                              stats.agreeingParts >= settings.minDenseAgreeingParts);
  const bool measured = (stats.corners > 0 || denseSawTarget) && stats.rejection == Rejection::Evidence;
  const bool measuredNearAnchor = measured && haveAnchor;
  // So does one where the anchor has expired but the image's motion carried the last pose to
  // this frame (a hand over most of the target for seconds): there every kMaxRelocalizationSkips-th
  // frame relocalizes anyway. (On the stress sequences: p95 14.7 to 13.4 ms, one frame found a
  // frame later.)
  const bool measuredOnChain = measured && !haveAnchor && haveChainPrediction && relocalizationSkips < kMaxRelocalizationSkips;
  // Nor when the image's motion, measured this frame, puts the target well outside the view (a
  // look away): ORB would find nothing there. A chain may drift (5 deg at worst on the stress
  // sequences, 50 px), hence the margin, and every kMaxRelocalizationSkips-th frame tries anyway.
  const bool awayFromView = stats.backgroundMotion && imageMotionFound &&
                            relocalizationSkips < kMaxRelocalizationSkips &&
                            !targetNearView(K, camera, prediction, map.targetWidth, map.targetHeight,
                                            kAwayMarginFraction * std::max(camera.width, camera.height));
  relocalizationSkips = verdict == Verdict::Rejected && !measuredNearAnchor && (awayFromView || measuredOnChain) ? relocalizationSkips + 1 : 0;
  if (verdict == Verdict::Rejected && !measuredNearAnchor && !awayFromView && !measuredOnChain) {
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
    // Nothing predicted the pose and relocalization gave none (ORB finds nothing in a smear):
    // the way out, as starts.
    Measurement returned;
    if (verdict == Verdict::Rejected && !havePrediction && searchReentry(seconds, returned)) {
      m = returned;
      stats.keyframe = 0;
      stats.reentry = true;
      verdict = judge(m, seconds, true);
      if (verdict != Verdict::Rejected && m.exposure > 0) exposure = m.exposure, exposureMeasured = true;
    }
  }

  if (verdict == Verdict::Rejected) blur = blurBefore;
  lastDenseSmearPx = m.dense && verdict != Verdict::Rejected ? m.smearPx : 0.0;
  // A dense pose given (TRACKING or LIMITED) explained the frame with its smear, fitted or none: a
  // blur model KLT kept from before it, twice as long or more, has ended (a 25 px template blur
  // carried over two dense frames onto a sharp one gave a floor pose 2.6 deg off, 15 of 28 corners
  // agreeing: docs/tracking.md). KLT starts sharp again, and the frame's statistics propose a blur
  // if there is one.
  if (m.dense && (verdict == Verdict::Tracking || verdict == Verdict::Limited) && blur.any() &&
      m.smearPx < 0.5 * blur.lengthPx)
    blur = {};
  // Nothing measured passed: the last pose carried by the image's motion, where the target's
  // parts agree at it (docs/tracking.md, "Partly hidden targets").
  StampedPose carriedPose;
  const bool carried = verdict == Verdict::Rejected && havePrediction && carry(prediction, seconds, carriedPose);
  carriedFrames = carried ? carriedFrames + 1 : 0;
  stats.carried = carried;
  PlanarPose shown = carried ? prediction : m.pose;
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
  if (carried) {
    result.state = TrackingState::Limited;
    result.covariance = carriedPose.covariance;
    result.positionSigmaM = carriedPose.positionSigma;
    result.rotationSigmaDeg = carriedPose.rotationSigmaDeg;
  } else if (result.state != TrackingState::Lost) {
    result.inliers = m.inliers;
    result.reprojectionErrorPx = m.rms;
    result.covariance = m.covariance;
    result.positionSigmaM = m.positionSigma;
    result.rotationSigmaDeg = m.rotationSigmaDeg;
    if (result.state == TrackingState::Tracking) maybeExtendMap(m);
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
      addIsotropicVariance(result.covariance.data(), growRotation, grow);
    }
  }
  // The ORB features of a keyframe added on an earlier frame, on one with time to spare: KLT from
  // the first prediction gave its pose on a sharp frame, with no retry from the image's motion,
  // no dense alignment, no relocalization (makeKeyframe). (Asking also for a single KLT pass,
  // one keyframe and one blur, left more of them to the tenth frame, wherever it fell: p95 +0.5
  // ms on the stress sequences.)
  const bool firstAttempt = verdict == Verdict::Tracking && !stats.backgroundMotion && !stats.dense &&
                            !stats.relocalized && !blur.any() && !carried && !stats.keyframeAdded;
  if (featuresPending >= 0 && (firstAttempt || frames - featuresPendingSince >= kMaxFeatureDelayFrames))
    finishKeyframeFeatures(true);
  // What the next frame's background motion starts from.
  haveLastImageMotion = haveLastImageMotion && imageMotionFound;
  havePreviousFrame = true;
  havePreviousFramePose = true;
  previousFrameChained = false;
  if (result.state != TrackingState::Lost) {
    rememberExitPath(shown);
    previousFramePose = shown;
    previousFrameChained = carried;  // the next frame carries it on (nothing measured)
    lastGiven = StampedPose{shown, seconds, result.covariance, result.positionSigmaM, result.rotationSigmaDeg};
    chainedSinceGiven = 0;
  } else if (havePending) {
    previousFramePose = pending.pose;
    chainedSinceGiven = -1;
  } else if (stats.backgroundMotion && imageMotionFound) {
    previousFramePose = prediction, previousFrameChained = true;
    rememberExitPath(prediction);
    if (chainedSinceGiven >= 0) ++chainedSinceGiven;
  } else {
    havePreviousFramePose = false;
    chainedSinceGiven = -1;
  }
  if (result.state == TrackingState::Lost) {
    gaveLast = false;
    return result;
  }
  lastGivenTime = seconds;
  if (!gaveLast) filter.reset();  // a new stretch of poses: do not blend with the last one
  gaveLast = true;
  const glm::dmat4 raw = cameraToWorld(shown);
  framePose = raw;
  framePosed = true;
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

const OcclusionMask* MarkerlessTracker::occlusionMask() noexcept {
  Impl& m = *impl_;
  if (!m.occlusion) {
    try {
      Diagnostics ignored;  // the map's reference was checked when the tracker was made
      m.occlusion = TargetOcclusion::create(m.camera, m.map, m.settings.occlusion, ignored);
    } catch (const std::bad_alloc&) {
      return nullptr;
    }
    if (!m.occlusion) return nullptr;
  }
  if (m.occlusionFrame != m.frames) {
    m.occlusionFrame = m.frames;
    const cv::Mat& g = m.grey.raw();
    if (m.framePosed && !g.empty())
      m.occlusion->update(ImageView{g.data, g.cols, g.rows, 1, static_cast<std::ptrdiff_t>(g.step)}, m.framePose);
    else
      m.occlusion->clear();
  }
  return &m.occlusion->mask();
}

const CameraModel& MarkerlessTracker::camera() const noexcept { return impl_->camera; }
const PlanarMap& MarkerlessTracker::map() const noexcept {
  impl_->finishKeyframeFeatures(false);  // the map as saved holds every keyframe's features
  return impl_->map;
}
const MarkerlessTracker::FrameStats& MarkerlessTracker::lastFrame() const noexcept { return impl_->stats; }

namespace {

std::string checkSettings(const MarkerlessSettings& s) {
  if (s.trackedCorners < 8 || s.trackedCorners > 2000) return "trackedCorners must be 8..2000";
  if (s.floorTrackedCorners < 8 || s.floorTrackedCorners > 2000) return "floorTrackedCorners must be 8..2000";
  if (std::min(s.trackedCorners, s.floorTrackedCorners) < s.minTrackingInliers)
    return "trackedCorners and floorTrackedCorners must be at least minTrackingInliers";
  if (s.pyramidLevels < 0 || s.pyramidLevels > 6) return "pyramidLevels must be 0..6";
  if (s.kltWindow < 5 || s.kltWindow > 61) return "kltWindow must be 5..61";
  if (s.refinements < 0 || s.refinements > 5) return "refinements must be 0..5";
  if (s.relocalizationFeatures < 50 || s.relocalizationFeatures > 20000) return "relocalizationFeatures must be 50..20000";
  if (s.tiltedViewFeatures < 0 || s.tiltedViewFeatures > PlanarMap::kMaxPointsPerKeyframe)
    return "tiltedViewFeatures must be 0..20000";
  if (s.referenceFeatures < 50 || s.referenceFeatures > PlanarMap::kMaxPointsPerKeyframe)
    return "referenceFeatures must be 50..20000";
  if (const std::string p = s.occlusion.problem(); !p.empty()) return "occlusion: " + p;
  if (s.minDenseAgreeingParts < 1 || s.minDenseSliverParts < 1) return "minDenseAgreeingParts and minDenseSliverParts must be >= 1";
  if (s.maxCarriedFrames < 0 || !(s.carryRotationSigmaDeg >= 0) || !std::isfinite(s.carryRotationSigmaDeg) ||
      !(s.carryPositionSigmaM >= 0) || !std::isfinite(s.carryPositionSigmaM))
    return "maxCarriedFrames, carryRotationSigmaDeg and carryPositionSigmaM must be >= 0";
  if (s.minLimitedInliers < 6 || s.minTrackingInliers < s.minLimitedInliers)
    return "need 6 <= minLimitedInliers <= minTrackingInliers";
  if (!(s.maxTrackingRmsPx > 0) || !std::isfinite(s.maxTrackingRmsPx)) return "maxTrackingRmsPx must be positive";
  if (!(s.smoothingMinCutoffHz > 0) || !std::isfinite(s.smoothingMinCutoffHz) || !(s.smoothingBeta >= 0) ||
      !std::isfinite(s.smoothingBeta))
    return "smoothing cut-off must be positive and beta non-negative";
  if (!(s.holdLimitedSeconds >= 0) || !std::isfinite(s.holdLimitedSeconds)) return "holdLimitedSeconds must be >= 0";
  if (!(s.reentrySearchSeconds >= 0) || !std::isfinite(s.reentrySearchSeconds)) return "reentrySearchSeconds must be >= 0";
  for (const double v : {s.maxSpeed, s.maxAcceleration, s.maxAngularSpeedDeg, s.maxAngularAccelerationDeg,
                         s.maxDrawnErrorM, s.maxDrawnErrorDeg, s.maxTrackingErrorM, s.maxTrackingErrorDeg,
                         s.minFeatureSigmaPx, s.effectiveFeatures, s.denseCovarianceScale})
    if (!(v > 0) || !std::isfinite(v))
      return "the motion model, drawn-error bounds, minFeatureSigmaPx, effectiveFeatures and denseCovarianceScale must be "
             "positive";
  for (const double v : {s.maxDrawnErrorFraction, s.maxTrackingErrorFraction, s.extendBelowImageShare, s.minTrackingSpread, s.minLimitedSpread,
                         s.minTrackingNcc, s.minLimitedNcc, s.minDenseZncc, s.minDenseInlierShare, s.minDenseVisibleShare,
                         s.minDenseAgreeingShare, s.minDenseAgreeingSpan, s.minDenseSliverShare})
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
    impl->warmUpRelocalization();
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
    impl->warmUpRelocalization();
    return std::unique_ptr<MarkerlessTracker>(new MarkerlessTracker(std::move(impl)));
  } catch (const cv::Exception& e) {
    diagnostics.error(mapName, std::string("OpenCV failed on the map: ") + e.what());
    return nullptr;
  }
}

}  // namespace marionette::ar
