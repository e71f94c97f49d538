// What the renderer draws the characters with, given the camera poses a tracker (or a replayed
// trajectory) gives frame by frame: the last pose, held for holdSeconds after a loss, and an
// opacity that says how far to trust it (docs/ar-renderer.md, "Tracked scenes").
//
// Opacity: 1 for a TRACKING pose; for a LIMITED one between 0.35 and 0.8 by its confidence
// (1 - three standard deviations over 5 cm or 2 degrees, whichever is worse; 0.8 when the
// tracker gives none). It eases toward that with a time constant of 0.1 s, so a character fades
// between states rather than snapping (the first pose starts at its own). After a loss the held pose fades out
// linearly over holdSeconds (to 0.35 and no lower when hideWhenLost is false). GL-free, no
// allocation.
#pragma once
#include <glm/mat4x4.hpp>

namespace marionette::ar {

struct PoseQuality {
  bool limited = false;            // LIMITED rather than TRACKING
  double positionSigmaM = 0;       // the pose's standard deviations; 0 when unknown
  double rotationSigmaDeg = 0;
};

class PoseHold {
 public:
  static constexpr float kLimitedLowest = 0.35f, kLimitedHighest = 0.8f;
  static constexpr double kEaseSeconds = 0.1;

  PoseHold(double holdSeconds, bool hideWhenLost) : holdSeconds_(holdSeconds), hideWhenLost_(hideWhenLost) {}
  // A frame at `seconds`: with a pose (camera-to-world) or lost (`pose` and `quality` ignored).
  void update(bool posed, const glm::dmat4& pose, double seconds, const PoseQuality& quality = {}) noexcept;

  [[nodiscard]] bool hasPose(double seconds) const noexcept {
    return everPosed_ && (posedNow_ || seconds - lastPoseTime_ <= holdSeconds_);
  }
  [[nodiscard]] bool charactersVisible(double seconds) const noexcept {
    return hasPose(seconds) || (everPosed_ && !hideWhenLost_);
  }
  // The characters' opacity at `seconds` (0 when they are not visible).
  [[nodiscard]] float opacity(double seconds) const noexcept;
  // The opacity a pose of this quality is drawn at, once eased.
  [[nodiscard]] static float targetOpacity(const PoseQuality& quality) noexcept;
  [[nodiscard]] glm::dmat4 viewInDouble() const noexcept { return glm::inverse(held_); }
  [[nodiscard]] glm::mat4 view() const noexcept { return glm::mat4(viewInDouble()); }

 private:
  double holdSeconds_;
  bool hideWhenLost_;
  glm::dmat4 held_{1.0};
  bool everPosed_ = false, posedNow_ = false;
  double lastPoseTime_ = -1e300;
  float opacity_ = 0;  // eased, at lastPoseTime_
};

}  // namespace marionette::ar
