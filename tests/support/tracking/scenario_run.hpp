// Runs a tracker over a standard scenario (scenarios.hpp) rendered once in memory: the
// poses, the per-frame times and the report against the exact trajectory. The accuracy
// test and marionette_tracking_eval share it, so both measure the same thing.
#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "tracking/scenarios.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace marionette::ar::synthetic {

struct RenderedScenario {
  Scenario scenario;
  std::vector<cv::Mat> frames;  // RGB8
};

// The project's standard scene: opencv-doc's graf1.png, 0.30 m wide, on a floor textured with
// baboon.jpg (2 mm a pixel), seen by a 640x480 camera with fx = fy = 600.
[[nodiscard]] SequenceRenderer standardRenderer();
[[nodiscard]] std::string standardTargetImage();  // graf1.png's path
// The standard target in grey, resized (INTER_AREA) to `size`: the scene of the image tests.
// std::runtime_error naming the file when it is missing (Debian opencv-doc).
[[nodiscard]] cv::Mat standardTargetGrey(cv::Size size);
// The standard target's grey image at its own size and its pyrDown levels down to about 16 px
// (as the tracker keeps a keyframe for its dense alignment), with the plane (X, Z metres) ->
// level-0 pixel mapping, kStandardTargetWidth wide and centred.
struct TargetPyramid {
  std::vector<cv::Mat> levels;
  cv::Matx33d planeToImage;
};
[[nodiscard]] TargetPyramid standardTargetPyramid();
inline constexpr double kStandardTargetWidth = 0.30;

// Renders the named scenarios (all when `names` is empty).
[[nodiscard]] std::vector<RenderedScenario> renderScenarios(const SequenceRenderer& renderer, int framesPerScenario,
                                                            const std::vector<std::string>& names = {});

struct ScenarioRun {
  std::vector<TrackedPose> poses;
  std::vector<double> ms;  // update() wall time per frame
  double medianMs = 0, p95Ms = 0;
  int relocalizations = 0, keyframes = 0;
  TrajectoryReport report;
};

// A fresh markerless tracker from the standard target, over every frame at the scenario's fps.
[[nodiscard]] ScenarioRun runMarkerless(const RenderedScenario& rendered, const CameraModel& camera,
                                        const MarkerlessSettings& settings);

[[nodiscard]] double percentile(std::vector<double> values, double p);

}  // namespace marionette::ar::synthetic
