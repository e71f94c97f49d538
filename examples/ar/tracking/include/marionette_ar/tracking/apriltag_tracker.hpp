// The fiducial tracker: AprilTag 36h11 markers (libapriltag) and a PnP pose (OpenCV).
//
// World: one tag (single-tag mode) or a board of tags on the plane Y=0, following
// tracker.hpp. For one tag the world is the tag's: its centre at the origin, +Y out of its
// printed face, the tag image's right along +X and its down along +Z. A board tag sits at
// `centre` turned by `yawDegrees` about +Y from that orientation. Sizes are the edge of
// the black border (8 of the 10 cells of a 36h11 tag: the white margin is not included).
//
// State: TRACKING for a pose with reprojection rms < 2 px from one tag (single-tag mode),
// from >= 2 board tags, or from 1 board tag whose decision margin is >= 2 x
// minDecisionMargin; LIMITED for a pose from 1 board tag of a lower margin or with rms in
// [2, 4) px; LOST otherwise. Stateless between frames: reset() only clears detections().
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/tracking/tracker.hpp"

namespace marionette::ar {

struct AprilTagBoardTag {
  int id = 0;              // 36h11 code, 0 .. 586
  double size = 0;         // black-border edge length, metres
  glm::dvec3 centre{0.0};  // in the world, on Y=0
  double yawDegrees = 0;   // about +Y (counter-clockwise seen from +Y)
};

struct AprilTagSettings {
  double tagSize = 0.1;  // metres, single-tag mode
  int tagId = -1;        // single-tag mode: the tag to track; -1 = the lowest id seen
  // Non-empty: a board; every listed tag seen gives its 4 corners to one PnP. ({}: designated
  // initializers that leave it out draw no -Wmissing-field-initializers.)
  std::vector<AprilTagBoardTag> board{};
  float decimate = 2.0f;          // libapriltag quad_decimate (>= 1)
  float sigma = 0.0f;             // libapriltag quad_sigma (Gaussian blur, >= 0)
  int threads = 1;                // libapriltag nthreads (1: on the calling thread)
  bool refineEdges = true;        // libapriltag refine_edges: keep it for sub-pixel corners
  double minDecisionMargin = 30;  // detections below are rejected
  int maxHamming = 1;             // corrected bits accepted, 0 .. 2
};

class AprilTagTracker final : public Tracker {
 public:
  struct Detection {
    int id = 0;
    // Pixels, OpenCV convention (centre of the top-left pixel at 0, 0; libapriltag's own
    // are half a pixel more on both axes), distorted (as seen).
    // The tag's own order, libapriltag's: the corners of the tag image's black border at
    // its bottom-left, bottom-right, top-right, top-left (counter-clockwise on screen for
    // a tag seen from its front).
    std::array<glm::dvec2, 4> corners{};
    double decisionMargin = 0;
    int hamming = 0;
  };

  // Null with errors in `diagnostics` (placed at "AprilTagSettings" fields or "camera")
  // for a camera with a problem(), a tag size <= 0 or not finite, a tag id outside
  // -1 .. 586, board tags with duplicate ids, bad ids, sizes, centres off Y=0 or non-finite
  // yaws, decimate < 1, sigma < 0, threads < 1, maxHamming outside 0 .. 2.
  [[nodiscard]] static std::unique_ptr<AprilTagTracker> create(const CameraModel& camera,
                                                               const AprilTagSettings& settings,
                                                               Diagnostics& diagnostics);
  ~AprilTagTracker() override;
  AprilTagTracker(const AprilTagTracker&) = delete;
  AprilTagTracker& operator=(const AprilTagTracker&) = delete;

  [[nodiscard]] TrackedPose update(const ImageView& frame, double seconds) noexcept override;
  void reset() noexcept override;
  [[nodiscard]] const CameraModel& camera() const noexcept override;

  // The accepted detections of the last update(), sorted by id, one per id (the best
  // margin); empty after an invalid frame.
  [[nodiscard]] const std::vector<Detection>& detections() const noexcept;

  // The camera-to-world pose (renderer camera axes) in the world of that one tag of
  // black-border edge `tagSize` metres; nullopt when no pose is found.
  [[nodiscard]] static std::optional<glm::dmat4> cameraToTag(const CameraModel& camera, const Detection& detection,
                                                             double tagSize);

 private:
  struct Impl;
  explicit AprilTagTracker(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace marionette::ar
