// A one-euro filter (Casiez, Roussel and Vogel, CHI 2012) on a camera pose: a low-pass
// whose cut-off rises with speed, so a still camera does not jitter and a moving one lags
// little. Position and rotation are filtered separately (rotation by slerp).
#pragma once
#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>

namespace marionette::ar {

class PoseFilter {
 public:
  PoseFilter(double minCutoffHz, double beta) : minCutoff_(minCutoffHz), beta_(beta) {}
  void reset() noexcept { primed_ = false; }

  // `speedScale` turns rotation speed (rad/s) into the units of position speed (m/s):
  // the distance to what the camera looks at, so a turn and a shift that move the image
  // equally open the filter equally.
  glm::dmat4 filter(const glm::dmat4& pose, double seconds, double speedScale) noexcept {
    const glm::dvec3 p(pose[3]);
    const glm::dquat q = glm::normalize(glm::quat_cast(glm::dmat3(pose)));
    if (!primed_ || !(seconds > time_)) {
      primed_ = seconds >= time_ || !primed_;
      time_ = seconds;
      p_ = p;
      q_ = q;
      speed_ = 0;
      return pose;
    }
    const double dt = seconds - time_;
    time_ = seconds;
    glm::dquat qn = q;
    if (glm::dot(qn, q_) < 0) qn = -qn;
    const double angle = 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(qn, q_))));
    const double rawSpeed = glm::length(p - p_) / dt + angle / dt * speedScale;
    speed_ += alpha(kDerivativeCutoffHz, dt) * (rawSpeed - speed_);
    const double a = alpha(minCutoff_ + beta_ * speed_, dt);
    p_ += a * (p - p_);
    q_ = glm::normalize(glm::slerp(q_, qn, a));
    glm::dmat4 out = glm::mat4_cast(q_);
    out[3] = glm::dvec4(p_, 1.0);
    return out;
  }

 private:
  static constexpr double kDerivativeCutoffHz = 1.0;
  static double alpha(double cutoffHz, double dt) noexcept {
    const double tau = 1.0 / (2.0 * 3.14159265358979323846 * cutoffHz);
    return 1.0 / (1.0 + tau / dt);
  }
  double minCutoff_, beta_;
  bool primed_ = false;
  double time_ = 0, speed_ = 0;
  glm::dvec3 p_{0.0};
  glm::dquat q_{1, 0, 0, 0};
};

}  // namespace marionette::ar
