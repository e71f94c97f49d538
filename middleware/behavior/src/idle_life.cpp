#include "marionette/behavior/idle_life.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/head_motion.hpp"
#include "marionette/core/easing.hpp"
#include "marionette/core/finite.hpp"
#include "random_draws.hpp"

namespace marionette {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxStepsPerFrame = 16;  // a longer jump (a paused scene) skips the draws, not replays them

void note(std::string& warning, const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; }

// `value` when finite and in [lo, hi]; else the fallback (not finite) or the nearest bound,
// with a warning naming the emitter, the parameter and the value used.
float checked(float value, float fallback, float lo, float hi, const char* what, const char* unit, std::string& warning) {
  char buf[200];
  if (!std::isfinite(value)) {
    std::snprintf(buf, sizeof buf, "%s '%g' is not finite; %g%s is used", what, static_cast<double>(value),
                  static_cast<double>(fallback), unit);
    note(warning, buf);
    return fallback;
  }
  const float used = std::clamp(value, lo, hi);
  if (used != value) {
    std::snprintf(buf, sizeof buf, "%s %g%s is outside [%g, %g]; %g%s is used", what, static_cast<double>(value), unit,
                  static_cast<double>(lo), static_cast<double>(hi), static_cast<double>(used), unit);
    note(warning, buf);
  }
  return used;
}

// A standard normal draw (Box-Muller; the second value is not kept, so a state is one stream).
double normalDraw(std::uint64_t& s) noexcept {
  const double u1 = 1.0 - detail::uniformDraw(s), u2 = detail::uniformDraw(s);  // u1 in (0, 1]
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

double blinkInterval(BlinkState& s) noexcept {
  const double x = std::exp(s.mu + s.sigma * normalDraw(s.random));
  return std::max(x, kBlinkSeconds + kBlinkRefractorySeconds);
}

float blinkClosure(double since) noexcept {
  if (since < 0.0 || since >= kBlinkSeconds) return 0.0f;
  if (since < kBlinkCloseSeconds) return static_cast<float>(smoothstep(since / kBlinkCloseSeconds));
  since -= kBlinkCloseSeconds;
  if (since < kBlinkHoldSeconds) return 1.0f;
  return static_cast<float>(smoothstep(1.0 - (since - kBlinkHoldSeconds) / kBlinkOpenSeconds));
}

double breathPeriod(BreathingState& s) noexcept {
  return s.period + s.range * (2.0 * detail::uniformDraw(s.random) - 1.0);
}

// A joint's model position at rest.
glm::vec3 restPosition(const Skeleton& skeleton, int joint) {
  return glm::vec3(modelMatrixOf(skeleton, skeleton.restPose, joint)[3]);
}

}  // namespace

std::uint64_t idleLifeSeed(std::string_view text) noexcept { return detail::textSeed(text); }

std::string bindBlink(const BehaviorRequest& request, const Rig& rig, std::uint64_t seed, BlinkState& st,
                      std::string& warning) {
  const BlinkParameters* p = request.as<BlinkParameters>();
  if (!p) return "a blink emitter needs BlinkParameters";
  st.stopped = p->stop;
  if (p->stop) return {};  // moves nothing: it replaces the running emitter
  // The lids' morphs: the profile's CLOSE_EYES, else a BLINK, else FACS's blink (AU45) or eyes closed (AU43).
  const auto& face = rig.joints().face;
  auto it = face.end();
  for (const char* name : {"CLOSE_EYES", "BLINK", "AU45", "AU43"})
    if (it = face.find(name); it != face.end() && !it->second.empty()) break;
  if (it != face.end() && !it->second.empty()) {
    st.morphs = it->second;
  } else {
    const auto& facs = rig.joints().facs;
    auto unit = facs.find("AU45");
    if (unit == facs.end()) unit = facs.find("AU43");
    if (unit == facs.end())
      return "the character has no blink morphs (its profile's face table has no CLOSE_EYES, BLINK, AU45 or AU43, and "
             "no ARKit, VRM or expression morph shows FACS's AU45 or AU43) and no upper eyelid joints; blinking needs one "
             "of them";
    st.morphs = unit->second.morphs;
    for (const RigJoints::FacsJoint& lid : unit->second.joints)
      if (lid.rule.part == FacsFacePart::UpperLid) st.lids.emplace_back(lid.joint, glm::radians(lid.rule.closeDegrees));
  }
  const float mean = checked(p->meanIntervalSeconds, BlinkParameters::kDefaultMeanInterval, BlinkParameters::kMinMeanInterval,
                             BlinkParameters::kMaxMeanInterval, "blink emitter meanIntervalSeconds", " s", warning);
  const float cv = checked(p->variation, BlinkParameters::kDefaultVariation, 0.0f, BlinkParameters::kMaxVariation,
                           "blink emitter variation", "", warning);
  st.amount = checked(p->amount, 1.0f, 0.0f, 1.0f, "blink emitter amount", "", warning);
  // Log-normal of mean m and coefficient of variation c: sigma^2 = ln(1 + c^2), mu = ln m - sigma^2 / 2.
  const double var = std::log(1.0 + static_cast<double>(cv) * cv);
  st.sigma = std::sqrt(var);
  st.mu = std::log(static_cast<double>(mean)) - 0.5 * var;
  st.random = p->seed ? p->seed : seed;
  st.onset = request.start() + blinkInterval(st);
  return {};
}

float advanceBlink(BlinkState& st, double clock) noexcept {
  if (st.stopped || !std::isfinite(clock)) return 0.0f;
  int steps = 0;
  while (clock >= st.onset + kBlinkSeconds && steps++ < kMaxStepsPerFrame) st.onset += blinkInterval(st);
  if (clock >= st.onset + kBlinkSeconds) st.onset = clock + blinkInterval(st);
  return blinkClosure(clock - st.onset);
}

void applyBlink(BlinkState& st, double clock, float weight, std::span<float> morphWeights, const Rig& rig,
                std::span<Transform> pose, float lidsClosed) noexcept {
  const float closure = advanceBlink(st, clock) * st.amount * std::clamp(weight, 0.0f, 1.0f);
  if (closure <= 0.0f) return;
  for (const auto& [morph, full] : st.morphs)
    if (morph >= 0 && static_cast<std::size_t>(morph) < morphWeights.size()) {
      float& w = morphWeights[static_cast<std::size_t>(morph)];
      w = std::clamp(std::max(w, closure * full), 0.0f, 1.0f);
    }
  // Lid joints as morphs: the larger of the blink and the face, about the character's left axis.
  for (const auto& [joint, full] : st.lids)
    if (const float extra = closure * full - std::max(lidsClosed, 0.0f); extra > 0.0f)
      rotateInModelFrame(rig.skeleton(), pose, joint, glm::angleAxis(extra, rig.joints().leftAxis));
}

std::string bindBreathing(const BehaviorRequest& request, const Rig& rig, std::uint64_t seed, BreathingState& st,
                          std::string& warning) {
  const BreathingParameters* p = request.as<BreathingParameters>();
  if (!p) return "a breathing emitter needs BreathingParameters";
  st.stopped = p->stop;
  if (p->stop) return {};
  const RigJoints& j = rig.joints();
  const Skeleton& skeleton = rig.skeleton();
  if (j.spine.empty()) return "the character has no spine joints to breathe with (set \"spine\" in its joint map)";
  // The chest (the top spine joint) takes 60 %, the joint below it the rest.
  const std::size_t n = j.spine.size();
  st.chest[0] = j.spine[n - 1];
  st.chest[1] = n >= 2 ? j.spine[n - 2] : -1;
  st.chestShare[0] = n >= 2 ? 0.6f : 1.0f;
  st.chestShare[1] = n >= 2 ? 0.4f : 0.0f;
  st.neck = j.neck >= 0 ? j.neck : j.head;
  st.frame = j.spine.front();
  st.frameRest = modelRotationOf(skeleton, skeleton.restPose, st.frame);
  const glm::vec3 left = glm::length(j.leftAxis) > 1e-6f ? glm::normalize(j.leftAxis) : glm::vec3(1.0f, 0.0f, 0.0f);
  st.chestAxis = -left;  // the chest's up tilts toward its back
  // The clavicles: the upper arm's parent, when it is neither the spine nor the neck.
  const RigJoints::LimbJoints* arms[2] = {&j.leftArm, &j.rightArm};
  for (int side = 0; side < 2; ++side) {
    st.clavicle[side] = st.upperArm[side] = -1;
    const int upper = arms[side]->upper;
    if (upper < 0) continue;
    const int parent = skeleton.parents[static_cast<std::size_t>(upper)];
    if (parent < 0 || parent == j.neck || parent == j.head || parent == j.hips ||
        std::find(j.spine.begin(), j.spine.end(), parent) != j.spine.end())
      continue;
    const glm::vec3 out = restPosition(skeleton, upper) - restPosition(skeleton, parent);
    const glm::vec3 axis = glm::cross(out, glm::vec3(0.0f, 1.0f, 0.0f));  // turns `out` toward up
    if (glm::length(axis) < 1e-6f * std::max(glm::length(out), 1e-6f)) continue;
    st.clavicle[side] = parent;
    st.upperArm[side] = upper;
    st.liftAxis[side] = glm::normalize(axis);
  }
  const float rate = checked(p->breathsPerMinute, BreathingParameters::kDefaultRate, BreathingParameters::kMinRate,
                             BreathingParameters::kMaxRate, "breathing emitter breathsPerMinute", "", warning);
  st.period = 60.0 / static_cast<double>(rate);
  st.range = checked(p->periodRangeSeconds, 0.0f, 0.0f, static_cast<float>(0.5 * st.period),
                     "breathing emitter periodRangeSeconds", " s", warning);
  float amplitude = checked(p->amplitudeDegrees, BreathingParameters::kDefaultAmplitudeDegrees, 0.0f,
                            BreathingParameters::kMaxAmplitudeDegrees, "breathing emitter amplitudeDegrees", " degrees",
                            warning);
  if (amplitude == 0.0f && p->amplitudeDegrees == 0.0f) note(warning, "breathing emitter amplitudeDegrees 0: the chest stays still");
  st.amplitude = static_cast<float>(amplitude * kPi / 180.0);
  st.random = p->seed ? p->seed : seed;
  st.cycleStart = request.start();
  st.cycleEnd = st.cycleStart + breathPeriod(st);
  return {};
}

float advanceBreathing(BreathingState& st, double clock) noexcept {
  if (st.stopped || !std::isfinite(clock)) return 0.0f;
  int steps = 0;
  while (clock >= st.cycleEnd && steps++ < kMaxStepsPerFrame) {
    st.cycleStart = st.cycleEnd;
    st.cycleEnd += breathPeriod(st);
  }
  if (clock >= st.cycleEnd) {
    st.cycleStart = clock;
    st.cycleEnd = clock + breathPeriod(st);
  }
  if (clock <= st.cycleStart) return 0.0f;
  const double phase = (clock - st.cycleStart) / (st.cycleEnd - st.cycleStart);
  return static_cast<float>(phase < kBreathInhaleShare ? smoothstep(phase / kBreathInhaleShare)
                                                       : smoothstep((1.0 - phase) / (1.0 - kBreathInhaleShare)));
}

void applyBreathing(BreathingState& st, double clock, float weight, const Skeleton& skeleton,
                    std::span<Transform> pose) noexcept {
  const float angle = advanceBreathing(st, clock) * st.amplitude * std::clamp(weight, 0.0f, 1.0f);
  if (!(angle > 0.0f)) return;
  // The axes turn with the body: a leaning posture breathes about its own left.
  const glm::quat turn = modelRotationOf(skeleton, pose, st.frame) * glm::inverse(st.frameRest);
  const glm::vec3 chestAxis = turn * st.chestAxis;
  for (int k = 0; k < 2; ++k)
    if (st.chest[k] >= 0) rotateInModelFrame(skeleton, pose, st.chest[k], glm::angleAxis(angle * st.chestShare[k], chestAxis));
  if (st.neck >= 0) rotateInModelFrame(skeleton, pose, st.neck, glm::angleAxis(-angle, chestAxis));
  for (int side = 0; side < 2; ++side) {
    if (st.clavicle[side] < 0) continue;
    const glm::quat lift = glm::angleAxis(angle, turn * st.liftAxis[side]);
    rotateInModelFrame(skeleton, pose, st.clavicle[side], lift);
    rotateInModelFrame(skeleton, pose, st.upperArm[side], glm::inverse(lift));
  }
}

}  // namespace marionette
