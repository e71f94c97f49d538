#include "marionette_ar/pose_hold.hpp"

#include <algorithm>
#include <cmath>

namespace marionette::ar {

float PoseHold::targetOpacity(const PoseQuality& quality) noexcept {
  if (!quality.limited) return 1.0f;
  double confidence = 1;
  // Three standard deviations against the error a drawn pose may have (the tracker's bound).
  if (quality.positionSigmaM > 0 || quality.rotationSigmaDeg > 0)
    confidence = std::clamp(1.0 - std::max(3 * quality.positionSigmaM / 0.05, 3 * quality.rotationSigmaDeg / 2.0),
                            0.0, 1.0);
  if (!std::isfinite(confidence)) confidence = 0;
  return kLimitedLowest + (kLimitedHighest - kLimitedLowest) * static_cast<float>(confidence);
}

void PoseHold::update(bool posed, const glm::dmat4& pose, double seconds, const PoseQuality& quality) noexcept {
  if (!posed) {
    if (posedNow_) opacity_ = opacity(seconds);  // where the fade-out starts
    posedNow_ = false;
    return;
  }
  const float target = targetOpacity(quality);
  // Eased toward the target from the last opacity (the first pose starts at its own: a
  // relocalized launch is confirmed, and shows the character at once).
  const float from = posedNow_ ? opacity_ : (everPosed_ ? opacity(seconds) : target);
  const double dt = everPosed_ ? std::clamp(seconds - lastPoseTime_, 0.0, 1.0) : 1.0 / 30.0;
  const auto k = static_cast<float>(1.0 - std::exp(-dt / kEaseSeconds));
  opacity_ = from + (target - from) * k;
  posedNow_ = true;
  held_ = pose;
  everPosed_ = true;
  lastPoseTime_ = seconds;
}

float PoseHold::opacity(double seconds) const noexcept {
  if (!everPosed_) return 0;
  if (posedNow_) return opacity_;
  // Lost: the held pose fades out over holdSeconds.
  const double left = holdSeconds_ > 0 ? 1.0 - (seconds - lastPoseTime_) / holdSeconds_ : 0.0;
  const float faded = opacity_ * static_cast<float>(std::clamp(left, 0.0, 1.0));
  return hideWhenLost_ ? faded : std::max(faded, kLimitedLowest);
}

}  // namespace marionette::ar
