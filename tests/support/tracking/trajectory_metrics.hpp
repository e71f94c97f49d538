// A tracker's estimated camera trajectory against the exact one: absolute trajectory error
// (no alignment: the world is metric and the target defines it), rotation error, false
// poses, jitter, and how fast the tracker relocalizes after losing the target.
#pragma once
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/tracker.hpp"

namespace marionette::ar::synthetic {

// Means and maxima over no frames, and jitter over fewer than 2 TRACKING frames, are NaN
// (so that any threshold on them fails).
struct TrajectoryReport {
  int frames = 0;
  int visibleFrames = 0;   // visibleFraction > 0
  int trackedFrames = 0;   // TRACKING or LIMITED
  int verifiedFrames = 0;  // TRACKING
  int within2cm = 0;       // visible frames with a TRACKING or LIMITED pose within 2 cm
  double ateRmsM = 0;      // position error over TRACKING and LIMITED frames, metres
  double ateMaxM = 0;
  double rotationMeanDeg = 0;  // angle of R_est^T R_true over the same frames
  double rotationMaxDeg = 0;
  int falsePoses = 0;  // TRACKING more than 5 cm off
  // TRACKING while visibleFraction == 0: right when the map reaches past the target (the
  // markerless tracker's keyframes of the floor around it), counted apart. Sequences with no
  // target at all (MarkerlessTracker.NoPoseInVideosWithoutTheTarget) must have no pose at all.
  int trackedOutOfView = 0;
  double jitterMm = 0;  // rms deviation of the TRACKING positions from their mean, mm
  double jitterPx = 0;  // the same of the world origin's projection through those poses, pixels
  // After the target becomes visible again following a stretch of frames where it is not
  // (the target having been visible before): frames from its reappearance to the first
  // TRACKING, the worst over all such returns. -1 when there is no such return, or when one
  // sees no TRACKING before the target goes again or the sequence ends.
  int framesToRelocalize = -1;
};

// All three lists must have the same length (std::invalid_argument otherwise).
[[nodiscard]] TrajectoryReport compareTrajectory(const std::vector<TrackedPose>& estimated,
                                                 const std::vector<glm::dmat4>& truth,
                                                 const std::vector<double>& visibleFraction, const CameraModel& camera);

// One line, e.g. "frames 150 visible 150 tracked 148 (TRACKING 140) <=2cm 147 ATE rms 3.1 mm
// max 9.0 mm rot mean 0.31 max 1.20 deg false 0 jitter 0.12 mm 0.05 px relocalize n/a".
[[nodiscard]] std::string formatReport(const TrajectoryReport& report);

// The angle of a^T b for two rotations (the upper-left 3x3 of camera-to-world matrices), degrees.
[[nodiscard]] double rotationErrorDeg(const glm::dmat4& a, const glm::dmat4& b);

}  // namespace marionette::ar::synthetic
