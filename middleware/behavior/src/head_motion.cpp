#include "marionette/behavior/head_motion.hpp"

#include "marionette/core/easing.hpp"
#include "marionette/core/text.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace marionette {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

float headPeakAngle(HeadLexeme lexeme) noexcept {
  switch (lexeme) {
    case HeadLexeme::Nod: return 0.4363323f;    // 25 degrees
    case HeadLexeme::Shake: return 0.5235988f;  // 30 degrees
    case HeadLexeme::Tilt: return 0.3490659f;   // 20 degrees
  }
  return 0.0f;
}

glm::vec3 headAxis(HeadLexeme lexeme) noexcept {
  switch (lexeme) {
    case HeadLexeme::Nod: return {1, 0, 0};
    case HeadLexeme::Shake: return {0, 1, 0};
    case HeadLexeme::Tilt: return {0, 0, 1};
  }
  return {1, 0, 0};
}

float headShape(HeadLexeme lexeme, std::span<const HeadStroke> strokes, double t) noexcept {
  for (const HeadStroke& s : strokes) {
    if (!(t > s.start && t < s.end)) continue;
    if (lexeme == HeadLexeme::Shake) {
      const double u = (t - s.start) / (s.end - s.start);
      return static_cast<float>(std::sin(2.0 * kPi * u) * std::sin(kPi * u) / 0.7698);  // peak |.| = 1
    }
    if (t <= s.peak) return static_cast<float>(s.peak > s.start ? smoothstep((t - s.start) / (s.peak - s.start)) : 1.0);
    return static_cast<float>(s.end > s.peak ? smoothstep((s.end - t) / (s.end - s.peak)) : 0.0);
  }
  return 0.0f;
}

void rotateInModelFrame(const Skeleton& skeleton, std::span<Transform> pose, int joint, const glm::quat& delta) noexcept {
  if (joint < 0 || static_cast<std::size_t>(joint) >= pose.size()) return;
  // Parent model rotation: the root space's rotation, then the chain's local rotations.
  // The root space may scale (centimetre files): take its rotation only.
  glm::mat3 root(skeleton.rootTransform);
  for (int c = 0; c < 3; ++c) root[c] = glm::length(root[c]) > 0.0f ? glm::normalize(root[c]) : root[c];
  glm::quat parent = safeNormalize(glm::quat_cast(root));
  int chain[256];
  int n = 0;
  for (int p = skeleton.parents[static_cast<std::size_t>(joint)]; p >= 0 && n < 256; p = skeleton.parents[static_cast<std::size_t>(p)])
    chain[n++] = p;
  for (int i = n - 1; i >= 0; --i) parent = parent * pose[static_cast<std::size_t>(chain[i])].rotation;
  Transform& t = pose[static_cast<std::size_t>(joint)];
  t.rotation = safeNormalize(glm::inverse(parent) * delta * parent * t.rotation);
}

}  // namespace marionette
