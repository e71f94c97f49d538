#include "marionette/animation/foot_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "marionette/core/finite.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/core/easing.hpp"
#include "marionette/animation/animation_clip.hpp"

namespace marionette {

namespace {


float horizontalLength(const glm::vec3& v) { return std::sqrt(v.x * v.x + v.z * v.z); }

// Phase in [0, 1); NaN stays NaN.
float wrapPhase(float p) noexcept {
  p -= std::floor(p);
  return p >= 1.0f ? 0.0f : p;
}

// Maximal runs (start, length) of `value` in a cyclic sequence; empty when the
// sequence is all `value` or has none of it.
std::vector<std::pair<int, int>> cyclicRuns(const std::vector<char>& c, char value) {
  std::vector<std::pair<int, int>> runs;
  const int n = static_cast<int>(c.size());
  auto at = [&](int k) { return c[static_cast<std::size_t>(((k % n) + n) % n)]; };
  int first = -1;
  for (int k = 0; k < n && first < 0; ++k)
    if (at(k) == value && at(k - 1) != value) first = k;
  if (first < 0) return runs;
  for (int i = 0; i < n;) {
    const int k = first + i;
    if (at(k) == value && at(k - 1) != value) {
      int len = 0;
      while (len < n && at(k + len) == value) ++len;
      runs.emplace_back(k % n, len);
      i += len;
    } else {
      ++i;
    }
  }
  return runs;
}

void fill(std::vector<char>& c, std::pair<int, int> run, char value) {
  const int n = static_cast<int>(c.size());
  for (int i = 0; i < run.second; ++i) c[static_cast<std::size_t>((run.first + i) % n)] = value;
}

}  // namespace

FootContactOptions footContactOptionsForLeg(float legLength, FootContactOptions base) noexcept {
  if (!(legLength > 0.0f) || !std::isfinite(legLength)) return base;
  const float scale = legLength / 0.9f;  // a human's hip-to-ankle length
  base.heightAboveLowest *= scale;
  base.maxSpeed *= scale;
  return base;
}

std::vector<ContactInterval> detectFootContacts(const AnimationClip& clip, const Skeleton& skeleton, int footJoint,
                                                const FootContactOptions& settings) {
  const Clip& authored = clip.clip;
  const std::size_t joints = skeleton.jointCount();
  const float duration = authored.duration;
  if (footJoint < 0 || static_cast<std::size_t>(footJoint) >= joints || skeleton.restPose.size() != joints ||
      !(duration > 0.0f) || !std::isfinite(duration))
    return {};
  const double rate = settings.samplesPerSecond > 0 ? settings.samplesPerSecond : 240;
  const int n = static_cast<int>(std::clamp(std::ceil(static_cast<double>(duration) * rate), 8.0, 1048576.0));
  const float dt = duration / static_cast<float>(n);

  // The foot (model space) at n + 1 times, the last one at the end of the cycle,
  // and where root motion has carried the root by then.
  std::vector<glm::vec3> foot(static_cast<std::size_t>(n) + 1), carried(foot.size(), glm::vec3(0.0f));
  std::vector<Transform> pose(joints);
  std::vector<glm::mat4> model(joints);
  SamplingCursor cursor;
  cursor.reset(authored);
  for (int k = 0; k <= n; ++k) {
    const float t = k == n ? duration : dt * static_cast<float>(k);
    sampleClip(authored, t, skeleton.restPose, pose, &cursor);
    localToModel(skeleton, pose, model);
    foot[static_cast<std::size_t>(k)] = glm::vec3(model[static_cast<std::size_t>(footJoint)][3]);
    if (!clip.rootMotion.empty()) {
      float yaw = 0.0f;
      clip.rootMotion.evaluate(t, carried[static_cast<std::size_t>(k)], yaw);
    }
  }
  auto ok = [&](int k) { return isFinite(foot[static_cast<std::size_t>(k)]); };

  // Horizontal velocity (central differences; one-sided at the first sample) and height.
  std::vector<glm::vec3> velocity(static_cast<std::size_t>(n), glm::vec3(std::nanf("")));
  float lowest = INFINITY;
  for (int k = 0; k < n; ++k) {
    const int a = std::max(k - 1, 0), b = k + 1;
    if (ok(a) && ok(b)) {
      glm::vec3 v = (foot[static_cast<std::size_t>(b)] - foot[static_cast<std::size_t>(a)]) / (dt * static_cast<float>(b - a));
      v.y = 0.0f;
      velocity[static_cast<std::size_t>(k)] = v;
    }
    if (ok(k)) lowest = std::min(lowest, foot[static_cast<std::size_t>(k)].y);
  }
  if (!std::isfinite(lowest)) return {};

  // In place, or travelling? Compare the root's net travel with the foot's stride
  // relative to the root.
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (int k = 0; k < n; ++k)
    if (ok(k)) {
      const glm::vec3 rel = foot[static_cast<std::size_t>(k)] - carried[static_cast<std::size_t>(k)];
      lo = glm::min(lo, rel), hi = glm::max(hi, rel);
    }
  const float stride = horizontalLength(hi - lo);
  const float travel = horizontalLength(carried.back() - carried.front());
  glm::vec3 ground(0.0f);
  float tolerance = settings.maxSpeed;
  if (clip.rootMotion.empty() || !(travel >= 0.2f * stride)) {
    // The ground's velocity under an in-place character: the foot's median
    // velocity over its lowest 30 % of frames (it stands on the ground then and
    // is carried backward). The median, not the mean: a foot may also pass low
    // while swinging forward (RobotExpressive's Running), which drags a mean to
    // a third of the ground speed.
    std::vector<int> order;
    for (int k = 0; k < n; ++k)
      if (ok(k) && isFinite(velocity[static_cast<std::size_t>(k)])) order.push_back(k);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return foot[static_cast<std::size_t>(a)].y < foot[static_cast<std::size_t>(b)].y;
    });
    order.resize(std::min(order.size(), std::max<std::size_t>(1, order.size() * 3 / 10)));
    if (!order.empty()) {
      std::vector<float> xs, zs;
      for (int k : order) {
        xs.push_back(velocity[static_cast<std::size_t>(k)].x);
        zs.push_back(velocity[static_cast<std::size_t>(k)].z);
      }
      const auto mid = static_cast<std::ptrdiff_t>(xs.size() / 2);
      std::nth_element(xs.begin(), xs.begin() + mid, xs.end());
      std::nth_element(zs.begin(), zs.begin() + mid, zs.end());
      ground = glm::vec3(xs[static_cast<std::size_t>(mid)], 0.0f, zs[static_cast<std::size_t>(mid)]);
    }
    const float allowance = std::isfinite(settings.inPlaceSpeedAllowance) ? std::max(settings.inPlaceSpeedAllowance, 0.0f) : 0.0f;
    tolerance += allowance * horizontalLength(ground);
  }

  std::vector<char> contact(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    const glm::vec3& v = velocity[static_cast<std::size_t>(k)];
    contact[static_cast<std::size_t>(k)] = ok(k) && isFinite(v) &&
                                           foot[static_cast<std::size_t>(k)].y <= lowest + settings.heightAboveLowest &&
                                           horizontalLength(v - ground) <= tolerance;
  }
  // Noise: gaps shorter than minDuration inside a contact close; then contacts
  // shorter than that go.
  const int minFrames = std::isfinite(settings.minDuration) && settings.minDuration > 0.0f
                            ? static_cast<int>(std::ceil(settings.minDuration / dt))
                            : 0;
  for (const auto& gap : cyclicRuns(contact, 0))
    if (gap.second < minFrames) fill(contact, gap, 1);
  for (const auto& run : cyclicRuns(contact, 1))
    if (run.second < minFrames) fill(contact, run, 0);

  const auto runs = cyclicRuns(contact, 1);
  if (runs.empty()) {
    if (contact[0]) return {{0.0f, 1.0f}};  // never lifts
    return {};
  }
  // A contact from the middle of the frame before its first sample to the middle
  // of the one after its last.
  std::vector<ContactInterval> out;
  for (const auto& [start, length] : runs) {
    const float begin = wrapPhase((static_cast<float>(start) - 0.5f) / static_cast<float>(n));
    const float end = wrapPhase((static_cast<float>(start + length) - 0.5f) / static_cast<float>(n));
    out.push_back({begin, end});
  }
  std::sort(out.begin(), out.end(), [](const ContactInterval& a, const ContactInterval& b) { return a.begin < b.begin; });
  return out;
}

bool inContact(std::span<const ContactInterval> contacts, float phase) noexcept {
  if (!std::isfinite(phase)) return false;
  const float p = wrapPhase(phase);
  for (const ContactInterval& c : contacts) {
    if (c.begin <= c.end ? (p >= c.begin && p < c.end) : (p >= c.begin || p < c.end)) return true;
  }
  return false;
}

float contactWeight(std::span<const ContactInterval> contacts, float phase, float blendPhase) noexcept {
  if (!std::isfinite(phase)) return 0.0f;
  if (!(blendPhase > 0.0f)) return inContact(contacts, phase) ? 1.0f : 0.0f;
  const float blend = std::min(blendPhase, 0.5f);
  const float p = wrapPhase(phase);
  float weight = 0.0f;
  for (const ContactInterval& c : contacts) {
    if (!std::isfinite(c.begin) || !std::isfinite(c.end)) continue;
    const float length = c.begin == 0.0f && c.end >= 1.0f ? 1.0f : wrapPhase(c.end - c.begin);
    const float into = wrapPhase(p - c.begin);  // how far past the contact's begin, around the cycle
    if (into <= length) return 1.0f;
    const float afterEnd = into - length, beforeBegin = 1.0f - into;
    const float near = std::min(afterEnd, beforeBegin);
    weight = std::max(weight, static_cast<float>(smoothstep(1.0 - static_cast<double>(near / blend))));
  }
  return weight;
}

}  // namespace marionette
