#include "marionette/animation/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace marionette {

float wrapClipTime(double time, float duration, WrapMode mode) noexcept {
  if (!(duration > 0.0f) || !std::isfinite(time)) return 0.0f;
  const double d = duration;
  if (mode == WrapMode::Clamp) return static_cast<float>(std::clamp(time, 0.0, d));
  double t = std::fmod(time, d);
  if (t < 0.0) t += d;
  return static_cast<float>(std::min(t, d));
}

void SamplingCursor::reset(const Clip& c) {
  clip = &c;
  keys.assign(c.tracks.size() * 3 + c.morphTracks.size(), 0u);
}

std::uint32_t findKeyInterval(std::span<const float> times, float t, std::uint32_t hint) noexcept {
  const auto n = static_cast<std::uint32_t>(times.size());
  if (n < 2) return 0;
  const std::uint32_t last = n - 2;
  if (hint > last) hint = last;
  // Forward playback: the same interval or one of the next two.
  for (std::uint32_t i = hint, end = std::min(hint + 3, n - 1); i < end; ++i)
    if (times[i] <= t && t < times[i + 1]) return i;
  if (!(t >= times[0])) return 0;  // before the first key, or NaN: never an index from a NaN compare
  if (t >= times[last + 1]) return last;
  auto it = std::upper_bound(times.begin(), times.end(), t);
  return static_cast<std::uint32_t>(it - times.begin()) - 1;
}

namespace {

// Position in the interval: key index and fraction, with the ends clamped.
struct KeyPos {
  std::uint32_t i;
  float u;       // 0..1 inside [t_i, t_i+1]
  float span;    // t_i+1 - t_i (for cubic tangents)
  bool single;   // u is exactly key i (before first, after last, one key)
};

KeyPos locate(std::span<const float> times, float t, std::uint32_t* hint) noexcept {
  const auto n = static_cast<std::uint32_t>(times.size());
  // NaN (a time from an overflowed float) holds the first key; +-inf the first or last.
  if (n <= 1 || !(t > times[0])) return {0, 0.0f, 0.0f, true};
  if (t >= times[n - 1]) return {n - 1, 0.0f, 0.0f, true};
  std::uint32_t i = findKeyInterval(times, t, hint ? *hint : 0);
  if (hint) *hint = i;
  const float span = times[i + 1] - times[i];
  float u = span > 0.0f ? (t - times[i]) / span : 0.0f;
  return {i, std::clamp(u, 0.0f, 1.0f), span, false};
}

template <class T>
T lerpValue(const T& a, const T& b, float u) noexcept {
  return a + (b - a) * u;
}
template <>
glm::quat lerpValue(const glm::quat& a, const glm::quat& b, float u) noexcept {
  return nlerpShortest(a, b, u);
}

// glTF cubic Hermite spline: values are (in-tangent, value, out-tangent) per key.
template <class T>
T hermite(const T* v, std::uint32_t i, float u, float span) noexcept {
  const T& p0 = v[i * 3 + 1];
  const T m0 = v[i * 3 + 2] * span;
  const T& p1 = v[(i + 1) * 3 + 1];
  const T m1 = v[(i + 1) * 3 + 0] * span;
  const float u2 = u * u, u3 = u2 * u;
  return p0 * (2 * u3 - 3 * u2 + 1) + m0 * (u3 - 2 * u2 + u) + p1 * (-2 * u3 + 3 * u2) + m1 * (u3 - u2);
}

// Quaternion results are unit: nlerp normalizes, step keys are unit (importers
// normalize), and the cubic case is normalized here.
template <class T>
T evaluate(const Track<T>& track, float t, std::uint32_t* hint) noexcept {
  const KeyPos k = locate(track.times, t, hint);
  const T* v = track.values.data();
  switch (track.interpolation) {
    case Interpolation::Step:
      return v[k.i];
    case Interpolation::CubicSpline:
      if constexpr (std::is_same_v<T, glm::quat>)
        return safeNormalize(k.single ? v[k.i * 3 + 1] : hermite(v, k.i, k.u, k.span));
      else
        return k.single ? v[k.i * 3 + 1] : hermite(v, k.i, k.u, k.span);
    case Interpolation::Linear:
    default:
      return k.single ? v[k.i] : lerpValue(v[k.i], v[k.i + 1], k.u);
  }
}

bool cursorFits(const SamplingCursor* c, const Clip& clip) noexcept {
  return c && c->clip == &clip && c->keys.size() == clip.tracks.size() * 3 + clip.morphTracks.size();
}

}  // namespace

void sampleClipTracks(const Clip& clip, float time, std::span<Transform> out, SamplingCursor* cursor) noexcept {
  std::uint32_t* hints = cursorFits(cursor, clip) ? cursor->keys.data() : nullptr;
  std::uint32_t scratch[3] = {0, 0, 0};
  const std::size_t n = out.size();
  for (std::size_t k = 0; k < clip.tracks.size(); ++k) {
    const JointTrack& jt = clip.tracks[k];
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= n) continue;
    std::uint32_t* h = hints ? hints + k * 3 : scratch;
    Transform& o = out[jt.joint];
    if (!jt.translation.empty()) o.translation = evaluate(jt.translation, time, h + 0);
    if (!jt.rotation.empty()) o.rotation = evaluate(jt.rotation, time, h + 1);
    if (!jt.scale.empty()) o.scale = evaluate(jt.scale, time, h + 2);
  }
}

void sampleClip(const Clip& clip, float time, std::span<const Transform> rest, std::span<Transform> out,
                SamplingCursor* cursor) noexcept {
  const std::size_t n = std::min(rest.size(), out.size());
  std::copy_n(rest.begin(), n, out.begin());
  sampleClipTracks(clip, time, out.first(n), cursor);
}

void sampleMorphWeights(const Clip& clip, float time, std::span<float> weights) noexcept {
  for (const MorphTrack& m : clip.morphTracks) {
    const std::size_t count = m.targets.size();
    if (m.times.empty() || count == 0) continue;
    const KeyPos k = locate(m.times, time, nullptr);
    const bool cubic = m.interpolation == Interpolation::CubicSpline;
    const std::size_t stride = cubic ? count * 3 : count;
    for (std::size_t j = 0; j < count; ++j) {
      const int target = m.targets[j];
      if (target < 0 || static_cast<std::size_t>(target) >= weights.size()) continue;
      const float* w = m.weights.data();
      float value;
      if (cubic) {
        const float p0 = w[k.i * stride + count + j];
        if (k.single) {
          value = p0;
        } else {
          const float m0 = w[k.i * stride + 2 * count + j] * k.span;
          const float p1 = w[(k.i + 1) * stride + count + j];
          const float m1 = w[(k.i + 1) * stride + j] * k.span;
          const float u = k.u, u2 = u * u, u3 = u2 * u;
          value = p0 * (2 * u3 - 3 * u2 + 1) + m0 * (u3 - 2 * u2 + u) + p1 * (-2 * u3 + 3 * u2) + m1 * (u3 - u2);
        }
      } else if (m.interpolation == Interpolation::Step || k.single) {
        value = w[k.i * stride + j];
      } else {
        value = w[k.i * stride + j] + (w[(k.i + 1) * stride + j] - w[k.i * stride + j]) * k.u;
      }
      weights[target] = std::isfinite(value) ? value : 0.0f;
    }
  }
}

}  // namespace marionette
