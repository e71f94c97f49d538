#include "marionette/behavior/reach.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/behavior_request.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/text.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

namespace {

constexpr const char* kSide[2] = {"left", "right"};

glm::vec3 originOf(const Skeleton& s, std::span<const Transform> pose, int joint) noexcept {
  return glm::vec3(modelMatrixOf(s, pose, joint)[3]);
}

bool descends(const Skeleton& s, int ancestor, int j) noexcept {
  for (int p = s.parents[static_cast<std::size_t>(j)]; p >= 0 && p < j; p = s.parents[static_cast<std::size_t>(p)])
    if (p == ancestor) return true;
  return false;
}

// The palm in the end joint's frame: halfway from the end joint to the first joint below
// it named like a middle finger ("Middle1.L", "J_Bip_L_Middle1", "leftMiddleProximal").
glm::vec3 palmInEnd(const Skeleton& s, const LimbIk& limb) {
  if (limb.upper < 0 || !limb.endIsDescendant) return glm::vec3(0.0f);
  const std::span<const Transform> rest(s.restPose);
  for (std::size_t j = static_cast<std::size_t>(limb.end) + 1; j < s.parents.size() && j < s.names.size(); ++j) {
    if (toUpper(s.names[j]).find("MIDDLE") == std::string::npos || !descends(s, limb.end, static_cast<int>(j)))
      continue;
    const glm::mat4 end = modelMatrixOf(s, rest, limb.end);
    const glm::vec3 middle = originOf(s, rest, static_cast<int>(j));
    const glm::vec3 palm = 0.5f * (glm::vec3(end[3]) + middle);
    const float det = glm::determinant(glm::mat3(end));
    if (!(std::fabs(det) > 1e-30f) || !std::isfinite(det)) return glm::vec3(0.0f);
    const glm::vec3 local(glm::inverse(end) * glm::vec4(palm, 1.0f));
    return isFinite(local) ? local : glm::vec3(0.0f);
  }
  return glm::vec3(0.0f);
}

// The arm's reach for the palm: upper arm and elbow-to-palm with the least bend.
float palmReach(const ReachState& st, int side, const ReachSettings& settings, const Skeleton& s,
                std::span<const Transform> pose, glm::vec3& shoulder) noexcept {
  const LimbIk& limb = st.limb[side];
  shoulder = originOf(s, pose, limb.upper);
  const glm::vec3 elbow = originOf(s, pose, limb.lower);
  return armReach(glm::length(elbow - shoulder), glm::length(reachPalmModel(st, side, s, pose) - elbow),
                  std::clamp(settings.minElbowBend, 0.02f, 1.2f));
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

}  // namespace

ReachTiming reachTiming(const BehaviorRequest& r, const ReachSettings& settings, std::string& warning) {
  ReachTiming t;
  const double start = r.start(), end = r.end(), span = end - start;
  const double move = std::max(static_cast<double>(settings.minMoveSeconds), 0.0);
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  std::optional<double> ready = r.time("ready") ? r.time("ready") : r.time("stroke");
  std::optional<double> relax = r.time("relax");
  const double wantIn = ready && *ready >= start && *ready <= end ? *ready - start : span / 3.0;
  const double wantOut = relax && *relax >= start && *relax <= end ? end - *relax : span / 3.0;
  double in = std::max(wantIn, move), out = std::max(wantOut, move);
  if (!(span > 0.0)) {
    in = out = 0.0;
    t.peak = 0.0f;
    note("the reach lasts 0 s: the hand does not move");
  } else if (span < 2.0 * move) {
    in = out = 0.5 * span;
    t.peak = static_cast<float>(span / (2.0 * move));
    note("the reach lasts " + seconds(span) + ", less than a hand needs to get there and back (" + seconds(2.0 * move) +
         "): the hand goes only part of the way (peak weight " + std::to_string(t.peak).substr(0, 4) + ")");
  } else {
    if (in + out > span) {  // the hold is gone: each move keeps at least `move`
      in = std::max(move, in * span / (in + out));
      out = std::max(move, span - in);
      in = span - out;
    }
    if (wantIn < move)
      note("ready comes " + seconds(wantIn) + " after start, but a hand needs " + seconds(move) + " to get there: it arrives at " +
           seconds(start + in));
    if (wantOut < move)
      note("relax comes " + seconds(wantOut) + " before end, but a hand needs " + seconds(move) + " to get back: it leaves at " +
           seconds(end - out));
  }
  t.blendInEnd = start + in;
  t.blendOutStart = std::max(end - out, t.blendInEnd);
  return t;
}

std::string bindReach(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                      const TargetJointFinder& findJoint, ReachState& st, std::string& warning) {
  if (!makeArms(rig.joints(), skeleton, st.limb))
    return "the character has no arm to reach with (set leftArm / rightArm in its profile)";
  const bool usable[2] = {st.limb[0].upper >= 0, st.limb[1].upper >= 0};
  const ReachParameters* p = request.as<ReachParameters>();
  if (std::string why = resolveSpatialTarget(p ? p->target : BehaviorTarget{}, "reach", findJoint, st.target); !why.empty())
    return why;
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (p->arm == PointingArms::Both) note("a reach moves one hand: the arm on the target's side reaches");
  const int named = p->arm == PointingArms::Left ? 0 : p->arm == PointingArms::Right ? 1 : -1;
  if (named >= 0 && usable[named]) st.side = named;
  else if (named >= 0) {
    st.side = 1 - named;
    note(std::string("the character has no usable ") + kSide[named] + " arm; the " + kSide[1 - named] + " one reaches");
  } else if (!usable[0] || !usable[1]) {
    st.side = usable[0] ? 0 : 1;
  }
  if (p->action == ReachAction::PickUp)
    note("pick-up is a reach here: the hand goes to the object and back; it is not grasped or carried");
  else if (p->action == ReachAction::PutDown)
    note("put-down is a reach here: the hand goes to the place and back; nothing is carried there");
  for (int side = 0; side < 2; ++side) st.palmInEnd[side] = palmInEnd(skeleton, st.limb[side]);
  return {};
}

void chooseReachArm(ReachState& st, const glm::vec3& target, const Skeleton& s, std::span<const Transform> pose) noexcept {
  if (st.side >= 0 || !isFinite(target)) return;
  float d[2];
  for (int side = 0; side < 2; ++side)
    d[side] = st.limb[side].upper >= 0 ? glm::length(originOf(s, pose, st.limb[side].upper) - target)
                                       : std::numeric_limits<float>::infinity();
  st.side = d[1] < d[0] ? 1 : 0;
}

std::string reachDistanceNote(const ReachState& st, std::string_view id, const glm::vec3& target,
                              const ReachSettings& settings, const Skeleton& s, std::span<const Transform> pose) {
  if (st.side < 0 || st.limb[st.side].upper < 0 || !isFinite(target)) return {};
  glm::vec3 shoulder;
  const float reach = palmReach(st, st.side, settings, s, pose, shoulder);
  const float distance = glm::length(target - shoulder);
  const glm::vec3 elbow = originOf(s, pose, st.limb[st.side].lower);
  const float nearest = std::fabs(glm::length(elbow - shoulder) - glm::length(reachPalmModel(st, st.side, s, pose) - elbow));
  char buf[320];
  if (distance < 0.98f * nearest) {
    std::snprintf(buf, sizeof buf,
                  "reach '%.60s': the target is %.3g m from the %s shoulder, nearer than the arm folds (%.3g m); the hand "
                  "stops short of it on the line toward it",
                  std::string(id).c_str(), static_cast<double>(distance), kSide[st.side], static_cast<double>(nearest));
    return buf;
  }
  if (!(distance > reach)) return {};
  std::snprintf(buf, sizeof buf,
                "reach '%.60s': the target is %.3g m from the %s shoulder but the arm reaches %.3g m; the hand stops on "
                "the line toward it, the arm extended (the character does not lean or step)",
                std::string(id).c_str(), static_cast<double>(distance), kSide[st.side], static_cast<double>(reach));
  return buf;
}

glm::vec3 reachPalmModel(const ReachState& st, int side, const Skeleton& s, std::span<const Transform> pose) noexcept {
  if (side < 0 || side > 1) return glm::vec3(0.0f);
  const LimbIk& limb = st.limb[side];
  if (limb.upper < 0 || !limb.endIsDescendant) return limbEndModel(s, pose, limb);
  const glm::vec3 p(modelMatrixOf(s, pose, limb.end) * glm::vec4(st.palmInEnd[side], 1.0f));
  return isFinite(p) ? p : limbEndModel(s, pose, limb);
}

void updateReach(ReachState& st, const glm::vec3& targetModel, bool known, float weight, const ReachSettings& settings,
                 const Skeleton& s, std::span<Transform> pose) noexcept {
  if (known && isFinite(targetModel)) st.lastTarget = targetModel;
  else if (!st.started) return;
  if (!st.started) {
    st.started = true;
    chooseReachArm(st, st.lastTarget, s, pose);
  }
  const int side = st.side;
  if (side < 0 || st.limb[side].upper < 0) return;
  const LimbIk& limb = st.limb[side];
  const float bend = std::clamp(settings.minElbowBend, 0.02f, 1.2f);
  const float w = std::isfinite(weight) ? std::clamp(weight, 0.0f, 1.0f) : 0.0f;

  // Where the palm goes: the target, or the nearest point the arm reaches on the line to it
  // (a hair inside the reach, so the folded triangle never clamps the palm short).
  glm::vec3 shoulder;
  st.reach = palmReach(st, side, settings, s, pose, shoulder);
  glm::vec3 toTarget = st.lastTarget - shoulder;
  st.distance = glm::length(toTarget);
  if (!(st.distance > 1e-4f)) {  // at the shoulder itself: fold toward where the hand is now
    toTarget = reachPalmModel(st, side, s, pose) - shoulder;
    if (!(glm::length(toTarget) > 1e-6f)) return;
    toTarget = glm::normalize(toTarget) * 1e-3f;
  }
  st.outOfReach = st.distance > st.reach;
  const glm::vec3 palmGoal =
      st.outOfReach ? shoulder + glm::normalize(toTarget) * (0.999f * st.reach) : shoulder + toTarget;

  // The wrist goal that puts the palm there: the palm's offset from the wrist turns with the
  // forearm, so it is corrected from where the palm lands (three rounds: well under a mm).
  const auto upper = static_cast<std::size_t>(limb.upper), lower = static_cast<std::size_t>(limb.lower);
  const glm::quat upperBefore = pose[upper].rotation, lowerBefore = pose[lower].rotation;
  glm::vec3 wristGoal = palmGoal - (reachPalmModel(st, side, s, pose) - limbEndModel(s, pose, limb));
  const LimbIk& other = st.limb[1 - side];
  bool placed = false;
  for (int round = 0; round < 3; ++round) {
    pose[upper].rotation = upperBefore;
    pose[lower].rotation = lowerBefore;
    ArmAim aim;
    if (!isFinite(wristGoal) || !measureArm(s, pose, limb, other, side, wristGoal, st.memory[side], aim)) break;
    glm::vec3 wrist;
    const glm::vec3 elbow = foldedElbow(aim, aim.distance, bend, wrist);
    placeArm(s, pose, limb, aim, elbow, wrist, 1.0f, st.memory[side]);
    placed = true;
    wristGoal += palmGoal - reachPalmModel(st, side, s, pose);
  }
  const glm::quat upperReached = pose[upper].rotation, lowerReached = pose[lower].rotation;
  pose[upper].rotation = placed ? slerpShortest(upperBefore, upperReached, w) : upperBefore;
  pose[lower].rotation = placed ? slerpShortest(lowerBefore, lowerReached, w) : lowerBefore;
}

}  // namespace marionette
