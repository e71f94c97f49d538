#include "marionette/animation/clip_optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace marionette {

float rotationAngle(const glm::quat& a, const glm::quat& b) noexcept {
  const float d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  const float s = d < 0.0f ? -1.0f : 1.0f;
  const float dx = a.x - s * b.x, dy = a.y - s * b.y, dz = a.z - s * b.z, dw = a.w - s * b.w;
  const float chord = std::sqrt(dx * dx + dy * dy + dz * dz + dw * dw);  // = 2 sin(angle / 4)
  return 4.0f * std::asin(std::min(1.0f, chord * 0.5f));
}

namespace {

float deviation(const glm::vec3& a, const glm::vec3& b, bool relative) noexcept {
  const glm::vec3 d = glm::abs(a - b);
  float m = std::max({d.x, d.y, d.z});
  if (relative) m /= std::max(1e-6f, std::max({std::fabs(b.x), std::fabs(b.y), std::fabs(b.z)}));
  return m;
}
float deviation(const glm::quat& a, const glm::quat& b, bool) noexcept { return rotationAngle(a, b); }

// Largest deviation of the track's values (key values only; cubic tangents
// must be zero for a constant track, checked by the caller) from `ref`.
template <class T>
float maxDeviation(const Track<T>& t, const T& ref, bool relative) {
  const std::size_t stride = t.interpolation == Interpolation::CubicSpline ? 3 : 1;
  const std::size_t offset = stride == 3 ? 1 : 0;
  float m = 0.0f;
  for (std::size_t k = 0; k < t.times.size(); ++k) m = std::max(m, deviation(t.values[k * stride + offset], ref, relative));
  return m;
}

template <class T>
bool flatTangents(const Track<T>& t, float tolerance) {
  if (t.interpolation != Interpolation::CubicSpline) return true;
  for (std::size_t k = 0; k < t.times.size(); ++k)
    for (std::size_t side : {std::size_t{0}, std::size_t{2}}) {
      const T& v = t.values[k * 3 + side];
      if constexpr (std::is_same_v<T, glm::quat>) {
        if (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z) + std::fabs(v.w) > tolerance) return false;
      } else {
        if (std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z) > tolerance) return false;
      }
    }
  return true;
}

template <class T>
T keyValue(const Track<T>& t, std::size_t k) {
  return t.values[t.interpolation == Interpolation::CubicSpline ? k * 3 + 1 : k];
}

// Removes the track (rest value) or makes it one key; records the error dropped.
template <class T>
void reduce(Track<T>& t, const T& rest, float tolerance, bool relative, float& maxError, ClipOptimizeStats& stats) {
  if (t.times.empty()) return;
  stats.keysBefore += t.times.size();
  if (flatTangents(t, tolerance)) {
    const float fromRest = maxDeviation(t, rest, relative);
    if (fromRest <= tolerance) {
      maxError = std::max(maxError, fromRest);
      t = Track<T>{};
      ++stats.tracksRemoved;
      return;
    }
    const T first = keyValue(t, 0);
    const float fromFirst = maxDeviation(t, first, relative);
    if (fromFirst <= tolerance && t.times.size() > 1) {
      maxError = std::max(maxError, fromFirst);
      const float time = t.times.front();
      t = Track<T>{};
      t.interpolation = Interpolation::Step;
      t.times = {time};
      t.values = {first};
      ++stats.tracksMadeConstant;
    }
  }
  stats.keysAfter += t.times.size();
}

}  // namespace

ClipOptimizeStats optimizeClip(Clip& clip, const Skeleton& skeleton, const ClipOptimizeOptions& options) {
  ClipOptimizeStats stats;
  for (JointTrack& jt : clip.tracks) {
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= skeleton.jointCount()) continue;
    const Transform& rest = skeleton.restPose[jt.joint];
    reduce(jt.translation, rest.translation, options.translationTolerance, false, stats.maxTranslationError, stats);
    reduce(jt.rotation, rest.rotation, options.rotationTolerance, false, stats.maxRotationError, stats);
    reduce(jt.scale, rest.scale, options.scaleTolerance, true, stats.maxScaleError, stats);
  }
  // Joints left with no track at all are dropped from the clip.
  clip.tracks.erase(std::remove_if(clip.tracks.begin(), clip.tracks.end(),
                                   [](const JointTrack& jt) {
                                     return jt.translation.empty() && jt.rotation.empty() && jt.scale.empty();
                                   }),
                    clip.tracks.end());
  return stats;
}

}  // namespace marionette
