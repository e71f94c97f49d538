// `marionette-ar SCENE.json --restore AUGMENTATION.json`: the augmentation put back into the
// scene (its tracker and map, exposure, environment, each character's placement and BML), and
// what the restore measures (docs/authoring.md "Restore"): the first frame drawn with a verified
// pose, the time from process start to it, and, where the frames come with exact poses (a
// sequence folder's truth.csv), how far the restored characters appear from where they were
// authored. A bad augmentation or map is an error naming it; the renderer then runs without it.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>

#include "ar_scene_file.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "marionette_ar/authoring/augmentation.hpp"
#include "marionette_ar/pose_track.hpp"

namespace marionette::ar {

// Seconds since this process started (the kernel's start time, 10 ms resolution, then a
// steady clock from main's first call of it).
[[nodiscard]] double secondsSinceProcessStart() noexcept;

class AugmentationRestore {
 public:
  // Reads the augmentation and puts its tracker, environment and exposure into `scene`. False
  // (with the errors printed, `scene` unchanged) when it cannot: the renderer goes on without it.
  bool load(const std::string& augmentationPath, ArScene& scene, const std::string& truthCsv);
  [[nodiscard]] bool active() const noexcept { return augmentation_.has_value(); }
  // What load() and bind() found (printed as found): an error names the augmentation file and
  // the field, or the map file.
  [[nodiscard]] const Diagnostics& diagnostics() const noexcept { return diagnostics_; }

  // After the middleware scene is loaded: each placed character's anchor, its BML added to
  // `bml` at time 0. A placed character the scene lacks is an error; the others are restored.
  void bind(const Scene& scene, std::vector<TimedFile>& bml);
  // The matrix a character's world matrix is multiplied by, and whether it is drawn (a scene
  // character the augmentation does not place is not).
  [[nodiscard]] const glm::mat4& anchor(std::size_t character) const noexcept { return anchors_[character]; }
  [[nodiscard]] bool drawn(std::size_t character) const noexcept { return !active() || placed_[character]; }

  // A frame drawn at scene `time` (frame number `frame`): `verified` when the tracker's pose is
  // TRACKING and the characters were drawn with it, `view` the camera it drew with, in double
  // (rounded to float, it would be off by ~1e-5 degrees before any tracking error).
  void frameDrawn(long frame, double time, bool verified, const glm::dmat4& view);
  [[nodiscard]] long firstRegisteredFrame() const noexcept { return firstFrame_; }
  [[nodiscard]] double firstRegisteredSeconds() const noexcept { return firstSeconds_; }  // since launch; -1: none

  // The end of a launch phase (now, or `seconds` since process start). The report gives each
  // phase's duration: from the end of the one before (the first from process start).
  void mark(const char* phase) { mark(phase, secondsSinceProcessStart()); }
  void mark(const char* phase, double seconds) { phases_.emplace_back(phase, seconds); }

  // The --json report (restored, error, first_registered_frame, launch_to_registered_seconds,
  // placement_error_m / _deg at the first registered frame, their maxima over the run, and
  // launch_phases_seconds: each phase's duration, which add up to launch_to_registered_seconds).
  [[nodiscard]] std::string json(long frames) const;

 private:
  std::optional<Augmentation> augmentation_;
  std::string path_;  // the augmentation file
  Diagnostics diagnostics_;
  std::optional<PoseTrack> truth_;
  std::vector<glm::mat4> anchors_;
  std::vector<char> placed_;
  std::vector<glm::vec3> positions_;  // the placed characters' authored positions (their feet)
  long firstFrame_ = -1;
  double firstSeconds_ = -1;
  double firstErrorM_ = -1, firstErrorDeg_ = -1, maxErrorM_ = -1, maxErrorDeg_ = -1;
  long measured_ = 0;
  std::vector<std::pair<const char*, double>> phases_;  // each phase's end, seconds since process start
};

}  // namespace marionette::ar
