// Markerless tracking of a textured planar surface (the paper's case), keyframe-based in the
// spirit of PTAM and ORB-SLAM's tracking thread, specialised to a plane:
//
//  - Tracking: the keyframe nearest the predicted view is warped into that view, its corners
//    are found in the frame by pyramidal KLT from where the warp puts them, and the pose comes
//    from a RANSAC homography then IPPE and Levenberg-Marquardt on the inliers. Every
//    correspondence is anchored to a keyframe, never to the previous frame, so the pose does
//    not drift. The prediction is the constant-velocity motion of the confirmed poses,
//    corrected by how the whole image moved since the last frame (a frame-to-frame homography
//    of the background), which still follows a fast pan whose blur hides the target's corners.
//  - Gating: a pose leaves the tracker only when it passes every check (docs/tracking.md,
//    "Gating"): its own evidence (inliers, their spread over the corners tried, reprojection
//    rms, the template's photometric agreement, the pose's covariance) and the motion model
//    (the change from the last confirmed pose within what a hand-held camera can do in that
//    time). A pose that fails is not given (LOST) rather than drawn wrong.
//  - Relocalization (at launch and when tracking fails): ORB features of the frame against each
//    keyframe's, a RANSAC homography, then the tracking step from that pose as a photometric
//    check; the pose is given only once confirmed: it agrees with the motion model of a recent
//    confirmed pose, or the next frame tracks from it consistently.
//  - Map extension: while TRACKING with less than `extendBelowVisible` of the target in view,
//    with the target covering less than `extendBelowImageShare` of the image (the floor around
//    it), or with the view much closer or farther than every keyframe's, the frame becomes a
//    keyframe (its texture around the target lies on the same plane). Where tracking against the
//    target fails (a hand over most of it), a keyframe of the floor is tried, then goes first.
//  - Smoothing: a one-euro filter (Casiez et al. 2012) on position and rotation, which
//    removes jitter on a still camera and lags under a frame when it moves (docs/tracking.md).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "marionette_ar/tracking/planar_map.hpp"
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "marionette_ar/tracking/tracker.hpp"

namespace marionette::ar {

struct MarkerlessSettings {
  int trackedCorners = 200;      // KLT points per frame
  int floorTrackedCorners = 100; // ... against a keyframe of the floor around the target
  int pyramidLevels = 3;         // KLT pyramid levels above the full image
  int kltWindow = 15;            // KLT window side, pixels
  int refinements = 0;           // extra warp + KLT passes from the new pose (the work-precision table: no gain)
  int relocalizationFeatures = 600;  // ORB features per frame when LOST
  int referenceFeatures = 1200;  // ORB features per keyframe
  // ORB features of each of the reference's five simulated tilted views (docs/tracking.md,
  // "Relocalization"); matched only when the keyframes give no pose. 0: no tilted views.
  int tiltedViewFeatures = 400;
  int minTrackingInliers = 30;   // TRACKING needs this many inliers and rms < maxTrackingRmsPx
  int minLimitedInliers = 12;    // LIMITED needs this many
  double maxTrackingRmsPx = 1.0;
  double extendBelowVisible = 0.6;  // add a keyframe when less of the target is in view
  // ... or when the target covers less of the image than this (the view is mostly floor around
  // it), on a sharp frame, no floor keyframe within 30 % of the distance: a look away that comes
  // back at the image's edge then finds the floor in the map. 0 turns it off.
  double extendBelowImageShare = 0.5;
  bool smoothing = true;
  double smoothingMinCutoffHz = 1.0;  // one-euro filter: cut-off at rest
  double smoothingBeta = 100.0;       // how fast the cut-off rises with speed (per m/s)
  // Extrapolate as LIMITED after losing the features at most this long, and only while the
  // motion model's worst case stays within maxDrawnError* (at 30 fps hand-held: not at all; at
  // 60 fps a frame).
  double holdLimitedSeconds = 0.25;

  // The motion model: what a hand-held camera can do (docs/tracking.md, "Gating", gives the
  // figures that chose these). A pose farther from the accepted motion than these allow in the
  // time since is not given.
  double maxSpeed = 4.0;                        // m/s
  double maxAcceleration = 20.0;                // m/s^2
  double maxAngularSpeedDeg = 600.0;            // deg/s
  double maxAngularAccelerationDeg = 6000.0;    // deg/s^2
  // The worst error a drawn pose may have: a LIMITED pose's three standard deviations, and an
  // extrapolation's worst case under the motion model, stay within these. TRACKING needs
  // three standard deviations within the tighter pair. Positions: metres, or the fraction of
  // the viewing distance when that is more (a poster seen from 3 m).
  double maxDrawnErrorM = 0.05, maxDrawnErrorFraction = 0.05, maxDrawnErrorDeg = 2.0;
  double maxTrackingErrorM = 0.02, maxTrackingErrorFraction = 0.02, maxTrackingErrorDeg = 1.5;
  // Evidence: the inliers' spread across their narrowest direction, as a share of the corners
  // tried (all at one edge is not a pose), and the mean normalized cross-correlation of the
  // template's patches with the frame's at the inliers. TRACKING needs the first of each pair,
  // LIMITED the second.
  double minTrackingSpread = 0.3, minLimitedSpread = 0.2;
  double minTrackingNcc = 0.6, minLimitedNcc = 0.4;
  // The covariance's model: pixel noise at least this, and at most this many independent
  // features (KLT's errors are correlated: blur and a misaligned template move many at once).
  double minFeatureSigmaPx = 0.3;
  double effectiveFeatures = 40.0;
  // Predict from the frame-to-frame motion of the whole image (false: constant velocity alone).
  bool backgroundMotion = true;
  // Where KLT on corners gives no pose, align the whole keyframe, blurred along the image's
  // motion, to the frame (dense_alignment.hpp): what follows a smear of 25-60 px. Such a pose is
  // LIMITED at best, and needs the model to explain the frame this well (ZNCC over the
  // target's pixels) with this share of them within Huber's threshold, and this share of the
  // keyframe in view (a sliver at the image's edge fits poses 4 deg apart alike).
  bool denseAlignment = true;
  // (Against a keyframe of the floor, a camera frame whose area on the plane may reach the
  // horizon, the share of the frame it covers counts too, where larger.)
  double minDenseZncc = 0.8, minDenseInlierShare = 0.6, minDenseVisibleShare = 0.3;
  // Or, where something covers part of the target (a hand), its parts (a 4 x 4 grid over the
  // pixels in view) that agree on their own (ZNCC >= 0.85): at least this many, this share of
  // the textured parts, spanning this share of the grid both ways (not one corner's parts).
  // And a sliver at the edge under minDenseVisibleShare, down to minDenseSliverShare, when every
  // textured part agrees and there are minDenseSliverParts of them.
  int minDenseAgreeingParts = 4;
  double minDenseAgreeingShare = 0.3, minDenseAgreeingSpan = 0.5;
  double minDenseSliverShare = 0.15;
  int minDenseSliverParts = 6;
  // Where nothing measured passes, the pose given last frame carried by the image's motion
  // (measured this frame over the whole view) is given LIMITED when the target's parts agree at
  // it as the by-parts gate asks; its covariance is the last pose's plus the carry's error per
  // frame (calibrated on the stress sequences: docs/tracking.md), and it stops once 3 sigma
  // leaves the drawable bounds, or after maxCarriedFrames in a row.
  bool carryPoses = true;
  double carryRotationSigmaDeg = 0.2, carryPositionSigmaM = 0.006;
  int maxCarriedFrames = 10;
  // Neighbouring pixels' errors are correlated beyond the smear's length: the covariance of a
  // dense pose is multiplied by this (calibrated on the stress sequences: docs/tracking.md).
  double denseCovarianceScale = 0.5;
  // Where the target comes back after the image's motion lost it (a look away through a smear,
  // or at a blank sky) and ORB finds nothing in the smear: the reference aligned densely from
  // the poses of the way out (given, or carried by the image's motion; a way back passes near
  // them), for reentrySearchSeconds after the last pose given. Such a pose must agree as a whole
  // and by parts, and waits for the next frame's confirmation, as a relocalized one does
  // (docs/tracking.md, "Re-entry along the way out").
  bool reentrySearch = true;
  double reentrySearchSeconds = 2.0;
  // occlusionMask()'s (target_occlusion.hpp): made from the map's reference on its first call.
  OcclusionSettings occlusion{};
};

class MarkerlessTracker final : public Tracker {
 public:
  // From a reference image of the surface (any format OpenCV reads) of `targetWidth` metres.
  // Errors name the file or the setting.
  [[nodiscard]] static std::unique_ptr<MarkerlessTracker> fromTarget(const CameraModel& camera,
                                                                     const std::string& targetImage,
                                                                     double targetWidth,
                                                                     const MarkerlessSettings& settings,
                                                                     Diagnostics& diagnostics);
  // From a grey reference image in memory (rows top to bottom, width * height bytes).
  [[nodiscard]] static std::unique_ptr<MarkerlessTracker> fromTargetPixels(const CameraModel& camera,
                                                                           const ImageView& target,
                                                                           double targetWidth,
                                                                           const MarkerlessSettings& settings,
                                                                           Diagnostics& diagnostics);
  // From a saved map. A map made with another camera size or intrinsics is an error naming
  // `mapName`.
  [[nodiscard]] static std::unique_ptr<MarkerlessTracker> fromMap(const CameraModel& camera, PlanarMap map,
                                                                  const std::string& mapName,
                                                                  const MarkerlessSettings& settings,
                                                                  Diagnostics& diagnostics);
  ~MarkerlessTracker() override;

  [[nodiscard]] TrackedPose update(const ImageView& frame, double seconds) noexcept override;
  void reset() noexcept override;
  [[nodiscard]] const CameraModel& camera() const noexcept override;
  // The reference image against the last frame at the pose measured for it (before the
  // smoothing, which may lag the image by a fraction of a frame): target_occlusion.hpp.
  [[nodiscard]] bool hasOcclusionMask() const noexcept override { return true; }
  [[nodiscard]] const OcclusionMask* occlusionMask() noexcept override;

  // The map as it is now (the reference and any keyframes added while tracking). It completes
  // the ORB features of a keyframe added last, when they are still to come (a few milliseconds
  // of ORB): call it from the thread that calls update(), as the tracker's other calls.
  [[nodiscard]] const PlanarMap& map() const noexcept;
  // What the last update() did (for logs and the evaluation).
  // Why the frame's measured pose was not given (the first check it failed).
  enum class Rejection : std::uint8_t {
    None,
    Evidence,     // too few inliers, too loose, bunched at one edge, photometrically off, or too uncertain
    Motion,       // farther from the confirmed motion than a hand-held camera moves
    Unconfirmed,  // a relocalization (or a pose without a recent confirmed one) awaiting the next frame
  };
  struct FrameStats {
    bool relocalized = false;      // ORB relocalization ran this frame
    bool keyframeAdded = false;
    bool keyframeFeatures = false;  // the ORB features of a keyframe added on an earlier frame came now
    bool extrapolated = false;     // the pose given is the motion model's, not measured
    bool carried = false;          // the pose given is the last one carried by the image's motion, checked by parts
    bool backgroundMotion = false;  // the prediction used the frame-to-frame motion of the image
    bool imageShift = false;        // that motion came from the whole image's shift (a smear defeated the grid)
    bool dense = false;             // the pose judged last came from the dense alignment (KLT gave none)
    bool reentry = false;           // ... from the re-entry search, started from a pose of the way out
    int keyframe = -1;             // the keyframe tracked against
    int corners = 0, inliers = 0;  // KLT points tried, inliers of the pose
    double rmsPx = 0;
    double blurPx = 0;  // the smear the template was blurred by in the last track (0: none)
    // The measured pose's evidence (the last one judged this frame), for logs and calibration.
    double spread = 0;               // inliers' narrowest spread over the corners tried
    double ncc = 0;                  // mean normalized cross-correlation at the inliers
    // Dense poses: the share of the target's pixels within Huber's threshold, of its area in
    // view, and its textured parts that agree of those it has.
    double inlierShare = 0, visibleShare = 0, frameShare = 0;
    int parts = 0, agreeingParts = 0;
    double agreeingSpan = 0;
    // Where the frame's time went (milliseconds, summed over the attempts): the image's motion,
    // KLT on corners, the dense alignment, ORB relocalization.
    double motionMs = 0, kltMs = 0, denseMs = 0, relocalizationMs = 0;
    double positionSigmaM = 0, rotationSigmaDeg = 0;
    double motionPositionM = 0, motionRotationDeg = 0;  // distance from the motion model's prediction
    double motionPositionLimitM = 0, motionRotationLimitDeg = 0;  // what it allowed
    Rejection rejection = Rejection::None;
    // The last pose judged this frame, given or not (camera to target frame), to weigh the gates.
    glm::dmat4 judgedCameraToWorld{1.0};
    // The prediction tracking started from last (identity: none; the re-entry search's start
    // counts), to weigh the predictions.
    glm::dmat4 predictedCameraToWorld{1.0};
    bool predicted = false;
    // The RANSAC homography (X, Z, 1) -> pixel of the last tracking pass, row-major, before
    // the pose constrains it (a pinhole image of a plane is a homography whatever the
    // camera; the pose needs the intrinsics to be right).
    std::array<double, 9> planeToImage{};
  };
  [[nodiscard]] const FrameStats& lastFrame() const noexcept;

 private:
  struct Impl;
  explicit MarkerlessTracker(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace marionette::ar
