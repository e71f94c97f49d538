#include "marionette/behavior/saccade.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/core/finite.hpp"
#include "random_draws.hpp"

namespace marionette {

namespace {

constexpr float kDegree = 3.14159265358979f / 180.0f;

// Per mode: the shares (%) of the eight direction bins (0 = right, 90 = up, counter-clockwise,
// as seen by the character), the magnitude limit (degrees), and how long the eyes hold on the
// gaze and away from it (seconds, uniform in [min, max]). Bins and limits: SmartBody's
// defaults for its talk, listen and think models (from "Eyes Alive"); the holds are chosen
// here: the talker looks away more often than the listener, the thinker longest.
struct Model {
  std::array<float, 8> bins;
  float limit;
  float mutualMin, mutualMax, awayMin, awayMax;
};
constexpr Model kTalk{{15.54f, 6.46f, 17.69f, 7.44f, 16.80f, 7.89f, 20.38f, 7.79f}, 12.0f, 0.8f, 2.5f, 0.3f, 0.9f};
constexpr Model kListen{{15.54f, 6.46f, 17.69f, 7.44f, 16.80f, 7.89f, 20.38f, 7.79f}, 10.0f, 1.5f, 4.0f, 0.2f, 0.6f};
constexpr Model kThink{{5.46f, 10.54f, 24.69f, 6.44f, 6.89f, 12.80f, 26.38f, 6.79f}, 12.0f, 0.5f, 1.5f, 0.8f, 2.5f};

const Model& modelOf(SaccadeMode m) noexcept { return m == SaccadeMode::Listen ? kListen : m == SaccadeMode::Think ? kThink : kTalk; }

double uniform(std::uint64_t& s) noexcept { return detail::uniformDraw(s); }

double saccadeSeconds(float degrees) noexcept { return 0.025 + 0.0024 * static_cast<double>(degrees); }

// The offset of a saccade of `degrees` toward `direction` (degrees: 0 right, 90 up).
glm::vec2 offsetOf(float direction, float degrees) noexcept {
  const float d = direction * kDegree, a = degrees * kDegree;
  return {-a * std::cos(d), -a * std::sin(d)};  // right is yaw < 0, up is pitch < 0
}

glm::vec2 offsetAt(const SaccadeState& s, double clock) noexcept {
  if (clock <= s.start) return s.from;
  if (!(s.duration > 0.0) || clock >= s.start + s.duration) return s.to;
  const float u = static_cast<float>((clock - s.start) / s.duration);
  return glm::mix(s.from, s.to, u * u * (3.0f - 2.0f * u));
}

// The model's next saccade, starting at `at`.
void draw(SaccadeState& s, double at) noexcept {
  const Model& m = modelOf(s.mode);
  s.from = offsetAt(s, at);
  if (s.away) {  // back onto the gaze
    s.to = glm::vec2(0.0f);
  } else {
    double pick = uniform(s.random) * 100.0;
    int bin = 0;
    for (; bin < 7 && pick >= m.bins[static_cast<std::size_t>(bin)]; ++bin) pick -= m.bins[static_cast<std::size_t>(bin)];
    const float magnitude = std::min(m.limit, static_cast<float>(-5.0 * std::log(1.0 - uniform(s.random))));
    s.to = offsetOf(45.0f * static_cast<float>(bin), std::max(magnitude, 1.0f));
  }
  const float degrees = glm::length(s.to - s.from) / kDegree;
  s.start = at;
  s.duration = saccadeSeconds(degrees);
  s.away = !s.away;
  const double hold = s.away ? m.awayMin + (m.awayMax - m.awayMin) * uniform(s.random)
                             : m.mutualMin + (m.mutualMax - m.mutualMin) * uniform(s.random);
  s.next = at + s.duration + hold;
}

}  // namespace

std::string bindSaccade(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton, SaccadeState& st,
                        std::string& warning) {
  const SaccadeParameters* p = request.as<SaccadeParameters>();
  if (!p) return "a saccade needs SaccadeParameters (a mode, a finish, or a direction and magnitude)";
  const RigJoints& j = rig.joints();
  st.eye[0] = j.leftEye;
  st.eye[1] = j.rightEye;
  if (st.eye[0] < 0 && st.eye[1] < 0) return "the character has no eye joints to saccade with (set them in its profile)";
  st.head = j.head;
  st.headRest = modelRotationOf(skeleton, skeleton.restPose, j.head);
  st.left = glm::length(j.leftAxis) > 1e-6f ? glm::normalize(j.leftAxis) : glm::vec3(1.0f, 0.0f, 0.0f);
  st.mode = p->mode;
  st.start = st.next = request.start();
  st.random = detail::textSeed(request.id);  // the same draws every run
  if (st.mode == SaccadeMode::None) {
    float magnitude = p->magnitudeDegrees, direction = p->directionDegrees;
    if (!std::isfinite(magnitude) || !std::isfinite(direction)) {
      warning = "a saccade's direction and magnitude must be finite; it stays on the gaze";
      magnitude = 0.0f, direction = 0.0f;
    } else if (std::fabs(magnitude) > SaccadeParameters::kMaxMagnitudeDegrees) {
      warning = "saccade magnitude " + std::to_string(magnitude) + " degrees is clamped to " +
                std::to_string(SaccadeParameters::kMaxMagnitudeDegrees);
      magnitude = std::copysign(SaccadeParameters::kMaxMagnitudeDegrees, magnitude);
    }
    st.to = offsetOf(direction, magnitude);
    st.duration = saccadeSeconds(std::fabs(magnitude));
    st.next = std::numeric_limits<double>::infinity();
  }
  return {};
}

glm::vec2 advanceSaccade(SaccadeState& st, double clock) noexcept {
  if (st.mode != SaccadeMode::None) {
    // A long step (a paused scene): the draws up to it are skipped, not replayed.
    int steps = 0;
    while (clock >= st.next && steps++ < 16) draw(st, st.next);
    if (clock >= st.next) draw(st, clock);
  }
  return offsetAt(st, clock);
}

void updateSaccade(SaccadeState& st, double clock, float weight, const Skeleton& skeleton,
                   std::span<Transform> pose) noexcept {
  const glm::vec2 offset = advanceSaccade(st, clock) * std::clamp(weight, 0.0f, 1.0f);
  if (offset == glm::vec2(0.0f)) return;
  // About the character's up and left as the head carries them now.
  const glm::quat headTurn = modelRotationOf(skeleton, pose, st.head) * glm::inverse(st.headRest);
  const glm::vec3 up = headTurn * glm::vec3(0.0f, 1.0f, 0.0f), left = headTurn * st.left;
  const glm::quat delta = glm::angleAxis(offset.x, up) * glm::angleAxis(offset.y, left);
  for (int eye : st.eye) {
    if (eye < 0 || static_cast<std::size_t>(eye) >= pose.size()) continue;
    const int parent = skeleton.parents[static_cast<std::size_t>(eye)];
    const glm::quat above = modelRotationOf(skeleton, pose, parent);
    Transform& t = pose[static_cast<std::size_t>(eye)];
    const glm::quat turned = glm::inverse(above) * delta * above * t.rotation;
    if (isFinite(turned)) t.rotation = glm::normalize(turned);
  }
}

}  // namespace marionette
