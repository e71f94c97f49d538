// Markerless tracking of a textured planar surface (the paper's case), keyframe-based in the
// spirit of PTAM and ORB-SLAM's tracking thread, specialised to a plane:
//
//  - Tracking: the keyframe nearest the predicted view is warped into that view (the
//    constant-velocity prediction of the last pose), its corners are found in the frame by
//    pyramidal KLT from where the warp puts them, and the pose comes from a RANSAC homography
//    then IPPE and Levenberg-Marquardt on the inliers. Every correspondence is anchored to a
//    keyframe, never to the previous frame, so the pose does not drift. `refinements` more
//    passes warp again with the new pose (patches then match closely).
//  - Relocalization (at launch and when LOST): ORB features of the frame against each
//    keyframe's, a RANSAC homography, then the tracking step from that pose as the check.
//    TRACKING is reported only when that independent, photometric check agrees: no false poses.
//  - Map extension: while TRACKING with less than `extendBelowVisible` of the target in view,
//    the frame becomes a keyframe (its texture around the target lies on the same plane).
//  - Smoothing: a one-euro filter (Casiez et al. 2012) on position and rotation, which
//    removes jitter on a still camera and lags under a frame when it moves (docs/tracking.md).
#pragma once
#include <array>
#include <memory>
#include <string>

#include "marionette_ar/tracking/planar_map.hpp"
#include "marionette_ar/tracking/tracker.hpp"

namespace marionette::ar {

struct MarkerlessSettings {
  int trackedCorners = 200;      // KLT points per frame
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
  bool smoothing = true;
  double smoothingMinCutoffHz = 1.0;  // one-euro filter: cut-off at rest
  double smoothingBeta = 100.0;       // how fast the cut-off rises with speed (per m/s)
  double holdLimitedSeconds = 0.25;   // after losing the features, extrapolate as LIMITED this long
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

  // The map as it is now (the reference and any keyframes added while tracking).
  [[nodiscard]] const PlanarMap& map() const noexcept;
  // What the last update() did (for logs and the evaluation).
  struct FrameStats {
    bool relocalized = false;      // ORB relocalization ran this frame
    bool keyframeAdded = false;
    int keyframe = -1;             // the keyframe tracked against
    int corners = 0, inliers = 0;  // KLT points tried, inliers of the pose
    double rmsPx = 0;
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
