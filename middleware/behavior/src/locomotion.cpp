#include "marionette/behavior/locomotion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "marionette/animation/blending.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/core/angles.hpp"

namespace marionette {

namespace {
constexpr std::size_t kMaxWaypoints = LocomotionParameters::kMaxWaypoints;

glm::vec2 forwardOf(float heading) noexcept { return {std::sin(heading), std::cos(heading)}; }

// Clip-local time of a gait clip at an unwrapped phase (cycles), strike-aligned.
double gaitTime(const GaitClip& g, double phase) noexcept { return (phase + g.strikePhase) * g.duration(); }

// Distance left along the path from `position` through waypoints[from..].
float pathRemaining(const glm::vec2& position, std::span<const glm::vec2> waypoints, std::size_t from) noexcept {
  if (from >= waypoints.size()) return 0.0f;
  float d = glm::length(waypoints[from] - position);
  for (std::size_t i = from + 1; i < waypoints.size(); ++i) d += glm::length(waypoints[i] - waypoints[i - 1]);
  return d;
}

// The heading the character must end with, or false when any will do.
bool finalFacing(const SteeringState& s, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
                 float& facing) noexcept {
  if (plan.hasFacing) {
    facing = plan.facing;
    return true;
  }
  if (plan.faceTargetCharacter && !waypoints.empty()) {
    const glm::vec2 to = waypoints.back() - s.position;
    if (glm::dot(to, to) < 1e-8f) return false;
    facing = std::atan2(to.x, to.y);
    return true;
  }
  return false;
}
}  // namespace

float GaitClip::duration() const noexcept { return clip ? clip->clip.duration : 0.0f; }

glm::vec3 GaitClip::footAt(int foot, double phase) const noexcept {
  const std::vector<glm::vec3>& path = footPath[foot];
  if (path.empty()) return glm::vec3(0.0f);
  const double u = phase + strikePhase;
  const double x = (u - std::floor(u)) * static_cast<double>(path.size());
  const std::size_t i = std::min(static_cast<std::size_t>(x), path.size() - 1);
  const float a = static_cast<float>(x - static_cast<double>(i));
  return glm::mix(path[i], path[(i + 1) % path.size()], a);
}

GaitClip analyzeGait(std::shared_ptr<const AnimationClip> clip, const Skeleton& skeleton, int leftFoot, int rightFoot) {
  GaitClip g;
  g.clip = std::move(clip);
  if (!g.clip || !(g.clip->clip.duration > 0.0f)) return g;
  const AnimationClip& ac = *g.clip;
  const float T = ac.clip.duration;
  if (!ac.rootMotion.empty()) {
    glm::vec3 travel;
    float yaw;
    ac.rootMotion.evaluate(ac.rootMotion.duration, travel, yaw);
    if (glm::length(travel) > 0.01f) {
      g.hasRootMotion = true;
      g.lateralDrift = travel.x;
      g.groundSpeed = glm::length(travel) / T;
    }
  }
  const int n = static_cast<int>(skeleton.jointCount());
  if (leftFoot < 0 || rightFoot < 0 || leftFoot >= n || rightFoot >= n) return g;
  // Sample the cycle; the stance foot is the lower one.
  const int samples = std::max(64, static_cast<int>(std::ceil(240.0f * T)));
  const float h = T / static_cast<float>(samples);
  std::vector<Transform> pose(skeleton.jointCount());
  std::vector<glm::mat4> model(skeleton.jointCount());
  std::vector<glm::vec3> left(static_cast<std::size_t>(samples)), right(static_cast<std::size_t>(samples));
  for (int k = 0; k < samples; ++k) {
    sampleClip(ac.clip, h * static_cast<float>(k), skeleton.restPose, pose);
    if (g.hasRootMotion) sampleClipTracks(ac.inPlaceRoot, h * static_cast<float>(k), pose);
    localToModel(skeleton, pose, model);
    left[static_cast<std::size_t>(k)] = glm::vec3(model[static_cast<std::size_t>(leftFoot)][3]);
    right[static_cast<std::size_t>(k)] = glm::vec3(model[static_cast<std::size_t>(rightFoot)][3]);
  }
  g.floor[0] = g.floor[1] = INFINITY;
  for (int k = 0; k < samples; ++k) {
    g.floor[0] = std::min(g.floor[0], left[static_cast<std::size_t>(k)].y);
    g.floor[1] = std::min(g.floor[1], right[static_cast<std::size_t>(k)].y);
  }
  auto at = [&](const std::vector<glm::vec3>& v, int k) { return v[static_cast<std::size_t>((k + samples) % samples)]; };
  auto leftStance = [&](int k) { return at(left, k).y <= at(right, k).y; };
  // The stance foot's horizontal path over the cycle, per second of stance: what
  // the ground must cover for the feet to stay put on average (cartoon gaits move
  // the stance foot unevenly; foot planting takes out the rest).
  double stancePath = 0.0;
  int stanceSteps = 0;
  for (int k = 0; k < samples; ++k) {
    if (leftStance(k) != leftStance(k + 1)) continue;
    const std::vector<glm::vec3>& foot = leftStance(k) ? left : right;
    const glm::vec3 d = at(foot, k + 1) - at(foot, k);
    stancePath += std::hypot(d.x, d.z);
    ++stanceSteps;
  }
  for (int k = 0; k < samples; ++k)
    if (leftStance(k) && !leftStance(k - 1)) {
      g.strikePhase = static_cast<float>(k) / static_cast<float>(samples);
      break;
    }
  if (!g.hasRootMotion && stanceSteps > 0) {
    const double speed = stancePath / (stanceSteps * static_cast<double>(h));
    g.groundSpeed = std::isfinite(speed) ? static_cast<float>(speed) : 0.0f;
  }
  g.footPath[0] = std::move(left);
  g.footPath[1] = std::move(right);
  return g;
}

namespace {
// A foot's height above its floor at a clip phase (cycles from clip time 0).
float heightAt(const GaitClip& g, int foot, double clipPhase) noexcept {
  const std::vector<glm::vec3>& path = g.footPath[foot];
  const double x = (clipPhase - std::floor(clipPhase)) * static_cast<double>(path.size());
  const std::size_t i = std::min(static_cast<std::size_t>(x), path.size() - 1);
  const float a = static_cast<float>(x - static_cast<double>(i));
  return glm::mix(path[i].y, path[(i + 1) % path.size()].y, a) - g.floor[foot];
}

// The walk and run are played at one phase, so where the run's cycle starts
// decides which of its poses blends with which of the walk's. Aligned by each
// clip's left-foot "strike" (the lower foot changing), a run whose swing foot
// dips near the ground (RobotExpressive's) put its stance against the walk's
// swing: halfway between the two speeds the right foot never came lower than
// 0.19 above the ground. The run's start is chosen instead so that, blended half
// and half with the walk, each foot comes down as close to its floor as it can
// (the worse of the two feet, minimised): the two clips' footfalls coincide.
void alignRunToWalk(LocomotionSet& set) {
  const GaitClip& walk = set.walk;
  GaitClip& run = set.run;
  for (int f = 0; f < 2; ++f)
    if (walk.footPath[f].empty() || run.footPath[f].empty()) return;
  constexpr int kOffsets = 240, kPhases = 240;
  // How close each foot comes to its floor with the run started at `start`.
  auto lowest = [&](double start, float low[2]) {
    low[0] = low[1] = INFINITY;
    for (int j = 0; j < kPhases; ++j) {
      const double p = static_cast<double>(j) / kPhases;
      for (int f = 0; f < 2; ++f)
        low[f] = std::min(low[f], 0.5f * (heightAt(walk, f, p + walk.strikePhase) + heightAt(run, f, p + start)));
    }
  };
  // The strike alignment stays unless another start brings the feet down by more
  // than a millimetre (Pab's walk and jog already come down together from it).
  constexpr float kBetter = 1e-3f;
  float strikeLow[2];
  lowest(run.strikePhase, strikeLow);
  float best = std::max(strikeLow[0], strikeLow[1]), bestLow[2] = {strikeLow[0], strikeLow[1]};
  double bestStart = run.strikePhase;
  for (int k = 0; k < kOffsets; ++k) {
    const double start = static_cast<double>(k) / kOffsets;
    float low[2];
    lowest(start, low);
    const float worse = std::max(low[0], low[1]);
    if (worse < best - kBetter) best = worse, bestStart = start, bestLow[0] = low[0], bestLow[1] = low[1];
  }
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "run clip aligned to the walk from phase %.3f: blended half and half, the feet come down to %.3f and "
                "%.3f above their floors (from its left strike, %.3f: %.3f and %.3f)",
                bestStart, static_cast<double>(bestLow[0]), static_cast<double>(bestLow[1]),
                static_cast<double>(run.strikePhase), static_cast<double>(strikeLow[0]),
                static_cast<double>(strikeLow[1]));
  set.notes.push_back(buf);
  run.strikePhase = static_cast<float>(bestStart);
}
}  // namespace

LocomotionSet makeLocomotionSet(const Rig& rig) {
  LocomotionSet set;
  const CharacterProfile& p = rig.profile();
  const RigJoints& j = rig.joints();
  const int left = j.leftLeg.end, right = j.rightLeg.end;
  if (left < 0 || right < 0)
    set.notes.push_back("no feet in the profile (legs): gait speed from root motion only, phases unaligned");
  auto load = [&](const std::string& name, const char* what) {
    GaitClip g;
    if (name.empty()) {
      set.notes.push_back(std::string("no ") + what + " clip in the profile");
      return g;
    }
    auto clip = rig.findClip(name);
    if (!clip) {
      set.notes.push_back(std::string("the profile's ") + what + " clip '" + name + "' is not in the rig");
      return g;
    }
    g = analyzeGait(std::move(clip), rig.skeleton(), left, right);
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s clip '%s': %.3f m/s over the ground (%s), left strike at phase %.3f", what,
                  name.c_str(), static_cast<double>(g.groundSpeed),
                  g.hasRootMotion ? "root motion" : "stance foot speed", static_cast<double>(g.strikePhase));
    set.notes.push_back(buf);
    if (!(g.groundSpeed > 0.0f)) g.clip.reset();
    return g;
  };
  set.walk = load(p.walk, "walk");
  set.run = load(p.run, "run");
  if (!set.walk.clip && set.run.clip) std::swap(set.walk, set.run);  // a run alone is the only gait
  if (set.run.clip && set.run.groundSpeed <= set.walk.groundSpeed) {
    set.notes.push_back("the run clip is not faster than the walk clip; it is not used");
    set.run = {};
  }
  if (set.run.clip) alignRunToWalk(set);
  return set;
}

std::string makeLocomotionPlan(const LocomotionParameters& p, const LocomotionSet& set,
                               const LocomotionSettings& settings, LocomotionPlan& plan, std::string& warning) {
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (!p.waypoints.empty()) {
    if (p.waypoints.size() > kMaxWaypoints)
      return "locomotion target has " + std::to_string(p.waypoints.size()) + " waypoints; at most " +
             std::to_string(kMaxWaypoints) + " are taken";
    for (const glm::vec2& w : p.waypoints)
      if (!isFinite(w)) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%g %g", static_cast<double>(w.x), static_cast<double>(w.y));
        return "locomotion target '" + std::string(buf) + "' is not finite (NaN or infinite); nothing moves";
      }
    plan.waypoints = p.waypoints;
  } else if (!p.targetCharacter.empty()) {
    plan.targetCharacter = p.targetCharacter;
    plan.proximity = settings.characterProximity;
    plan.faceTargetCharacter = true;
  } else {
    return "a locomotion needs a target: waypoints on the ground (x, z) or a character";
  }
  // Speed: the manner's preset, unless given.
  const float walk = settings.walkSpeed > 0.0f ? settings.walkSpeed : set.walk.groundSpeed;
  const float run = settings.runSpeed > 0.0f ? settings.runSpeed
                    : set.run.clip         ? set.run.groundSpeed
                                           : 2.0f * walk;
  plan.speed = p.manner == LocomotionManner::Run      ? run
               : p.manner == LocomotionManner::Stroll ? 0.5f * walk
               : p.manner == LocomotionManner::Sprint ? 1.3f * run
                                                      : walk;
  auto number = [&](const std::optional<float>& value, const char* name, float lo, float hi, float& out) {
    if (!value) return false;
    if (!std::isfinite(*value) || *value < lo || *value > hi) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "%s '%g' is not a number in [%g, %g]; ignored", name, static_cast<double>(*value),
                    static_cast<double>(lo), static_cast<double>(hi));
      note(buf);
      return false;
    }
    out = *value;
    return true;
  };
  number(p.speed, "speed", LocomotionParameters::kMinSpeed, LocomotionParameters::kMaxSpeed, plan.speed);
  float facing = 0.0f;
  if (number(p.facing, "facing", -2.0f * kTwoPi, 2.0f * kTwoPi, facing)) {
    plan.hasFacing = true;
    plan.facing = wrapAngle(facing);
    plan.faceTargetCharacter = false;
  }
  number(p.proximity, "proximity", 0.0f, LocomotionParameters::kMaxProximity, plan.proximity);
  if (!(plan.speed > 0.0f)) return "the character has no usable walk clip, so no speed for the locomotion";
  return {};
}

float steer(SteeringState& s, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
            const LocomotionSettings& settings, float dt) noexcept {
  if (s.done || !(dt >= 0.0f)) return 0.0f;
  const float maxTurn = settings.turnSpeed * dt;
  if (s.arrived || waypoints.empty() || s.waypoint >= waypoints.size()) {
    s.arrived = true;
    s.speed = 0.0f;
    float facing = 0.0f;
    if (!finalFacing(s, plan, waypoints, facing)) {
      s.done = true;
      return 0.0f;
    }
    const float error = wrapAngle(facing - s.heading);
    s.heading = wrapAngle(s.heading + std::clamp(error, -maxTurn, maxTurn));
    if (std::fabs(wrapAngle(facing - s.heading)) <= settings.facingTolerance) s.done = true;
    return 0.0f;
  }
  const glm::vec2 to = waypoints[s.waypoint] - s.position;
  const float distance = glm::length(to);
  const bool last = s.waypoint + 1 == waypoints.size();
  float error = 0.0f;
  if (distance > 1e-4f) {
    error = wrapAngle(std::atan2(to.x, to.y) - s.heading);
    s.heading = wrapAngle(s.heading + std::clamp(error, -maxTurn, maxTurn));
    error = wrapAngle(std::atan2(to.x, to.y) - s.heading);
  }
  const float remaining = std::max(0.0f, pathRemaining(s.position, waypoints, s.waypoint) - plan.proximity);
  // Cruise, slowed while the target is off to the side (turning in place when it
  // is beside or behind), and braking so as to stop at the destination.
  const float brake = std::sqrt(2.0f * settings.deceleration * std::max(0.0f, remaining - settings.arriveRadius));
  const float wanted = std::min(plan.speed * std::max(0.0f, std::cos(error)), brake);
  if (s.speed < wanted) s.speed = std::min(wanted, s.speed + settings.acceleration * dt);
  else s.speed = std::max(wanted, s.speed - settings.deceleration * dt);
  s.speed = std::min(s.speed, brake);
  float limit = s.speed * dt;
  if (last) limit = std::min(limit, std::max(0.0f, distance - plan.proximity));
  return limit;
}

void advance(SteeringState& s, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
             const LocomotionSettings& settings, const glm::vec2& travel) noexcept {
  if (std::isfinite(travel.x) && std::isfinite(travel.y)) s.position += travel;
  while (!s.arrived && s.waypoint < waypoints.size()) {
    const bool last = s.waypoint + 1 == waypoints.size();
    const float distance = glm::length(waypoints[s.waypoint] - s.position);
    if (!last) {
      if (distance > settings.waypointRadius) break;
      ++s.waypoint;
      continue;
    }
    if (distance - plan.proximity <= settings.arriveRadius) {
      s.arrived = true;
      s.speed = 0.0f;
    }
    break;
  }
  if (waypoints.empty()) s.arrived = true;
}

double estimateLocomotionSeconds(SteeringState s, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
                                 const LocomotionSettings& settings) {
  constexpr float dt = 1.0f / 60.0f;
  constexpr int kMaxSteps = 4 * 3600 * 60;
  int steps = 0;
  while (!s.done && steps < kMaxSteps) {
    const float limit = steer(s, plan, waypoints, settings, dt);
    advance(s, plan, waypoints, settings, forwardOf(s.heading) * limit);
    ++steps;
  }
  return steps * static_cast<double>(dt);
}

LocomotionController::LocomotionController(std::shared_ptr<const LocomotionSet> set, const Skeleton& skeleton,
                                           const RigJoints& joints)
    : set_(std::move(set)), gaitPose_(skeleton.jointCount()), planter_(skeleton, joints) {
  feetJoints_[0] = joints.leftLeg.end;
  feetJoints_[1] = joints.rightLeg.end;
  if (set_->walk.clip) {
    walkCursor_.reset(set_->walk.clip->clip);
    walkRootCursor_.reset(set_->walk.clip->inPlaceRoot);
  }
  if (set_->run.clip) {
    runCursor_.reset(set_->run.clip->clip);
    runRootCursor_.reset(set_->run.clip->inPlaceRoot);
  }
}

void LocomotionController::start(std::shared_ptr<const LocomotionPlan> plan, const glm::vec3& position,
                                 float heading) noexcept {
  plan_ = std::move(plan);
  const float speed = state_.speed;
  state_ = {};
  state_.position = {position.x, position.z};
  drawnAt_ = position;
  state_.heading = heading;
  state_.speed = speed;
  if (plan_ && plan_->targetCharacter.empty() && plan_->waypoints.empty()) state_.arrived = true;
}

void LocomotionController::stop() noexcept {
  plan_.reset();
  state_.done = true;
}

std::span<const glm::vec2> LocomotionController::waypoints() const noexcept {
  // A target character's place (resolved before the frame) stands in for the plan's waypoints.
  if (!plan_->targetCharacter.empty()) return {&targetPosition_, 1};
  return plan_->waypoints;
}

double LocomotionController::stanceMatchingPhase(const Skeleton& skeleton,
                                                 std::span<const Transform> posture) const noexcept {
  const int n = static_cast<int>(skeleton.jointCount());
  if (feetJoints_[0] < 0 || feetJoints_[1] < 0 || feetJoints_[0] >= n || feetJoints_[1] >= n ||
      set_->walk.footPath[0].empty())
    return phase_;
  const glm::vec3 stand[2] = {glm::vec3(modelMatrixOf(skeleton, posture, feetJoints_[0])[3]),
                              glm::vec3(modelMatrixOf(skeleton, posture, feetJoints_[1])[3])};
  const GaitClip& walk = set_->walk;
  const GaitClip& run = set_->run;
  const bool blendRun = runWeight_ > 0.0f && !run.footPath[0].empty();
  constexpr int kCandidates = 64;
  double best = phase_;
  float bestDistance = INFINITY;
  for (int k = 0; k < kCandidates; ++k) {
    const double p = static_cast<double>(k) / kCandidates;
    glm::vec3 foot[2];
    for (int f = 0; f < 2; ++f) {
      foot[f] = walk.footAt(f, p);
      if (blendRun) foot[f] = glm::mix(foot[f], run.footAt(f, p), runWeight_);
    }
    const int stance = foot[0].y <= foot[1].y ? 0 : 1;
    const float d = std::hypot(foot[stance].x - stand[stance].x, foot[stance].z - stand[stance].z);
    if (d < bestDistance) bestDistance = d, best = p;
  }
  return best;
}

void LocomotionController::setTargetPosition(const glm::vec3& world) noexcept {
  if (std::isfinite(world.x) && std::isfinite(world.z)) targetPosition_ = {world.x, world.z};
}

void LocomotionController::update(float dt, double clock, glm::vec3& position, float& heading,
                                  const Skeleton& skeleton, std::span<Transform> pose,
                                  std::span<Transform> scratch) noexcept {
  if (!set_->usable() || (!plan_ && weight_ <= 0.0f && state_.speed <= 0.0f && !planter_.active())) return;
  // Someone else moved the character (setPosition, a layer's root motion): steer from there.
  if (position != drawnAt_) state_.position = {position.x, position.z};
  state_.heading = heading;
  const bool wasDone = state_.done;
  float limit = 0.0f;
  if (plan_ && !state_.done) {
    limit = steer(state_, *plan_, waypoints(), settings_, dt);
  } else {  // stopped: brake where it is
    state_.speed = std::max(0.0f, state_.speed - settings_.deceleration * dt);
    limit = state_.speed * dt;
  }

  // Gait blend and phase: the run's weight from the speed; one cycle covers D metres.
  const GaitClip& walk = set_->walk;
  const GaitClip& run = set_->run;
  const float v = state_.speed;
  // Turning on the spot steps too: the gait runs as if at the speed of a foot
  // circling the body (a tenth of a walk cycle's length away), but travels only v.
  const float turnRate = dt > 0.0f ? std::fabs(wrapAngle(state_.heading - heading)) / dt : 0.0f;
  const float gaitSpeed = std::max(v, turnRate * 0.1f * walk.cycleDistance());
  runWeight_ = run.clip ? std::clamp((v - walk.groundSpeed) / (run.groundSpeed - walk.groundSpeed), 0.0f, 1.0f) : 0.0f;
  const float cycle = (1.0f - runWeight_) * walk.cycleDistance() + runWeight_ * run.cycleDistance();
  // Setting out from the posture: the gait starts where its stance foot is where
  // the posture has that foot, so that blending the gait in does not carry a
  // planted foot away (from its left-foot strike, the gait's weight rising over an
  // idle stance moved the left foot 1.4 m forward while it stayed on the ground).
  if (weight_ <= 0.0f && gaitSpeed > 0.0f) phase_ = stanceMatchingPhase(skeleton, pose);
  const double phase0 = phase_;
  phase_ += static_cast<double>(gaitSpeed * dt / cycle);
  const float travelShare = gaitSpeed > 0.0f ? v / gaitSpeed : 0.0f;

  // Travel: the clips' root motion over the step (or their ground speed). The
  // forward part moves the steering along its path; the sideways sway of the
  // root (detrended, so a cycle comes back to the path) is added to the place the
  // character is drawn at but not steered from, so the heading does not wobble.
  float forward = 0.0f, lateral = 0.0f;
  auto addTravel = [&](const GaitClip& g, float w) {
    if (w <= 0.0f) return;
    const double t0 = gaitTime(g, phase0), t1 = gaitTime(g, phase_);
    if (!g.hasRootMotion) {
      forward += travelShare * w * static_cast<float>(t1 - t0) * g.groundSpeed;
      return;
    }
    glm::vec3 d;
    float turn;
    g.clip->rootMotion.between(t0, t1, WrapMode::Loop, d, turn);
    forward += travelShare * w * d.z;
    const RootMotion& rm = g.clip->rootMotion;
    glm::vec3 now;
    float yaw;
    const float t = wrapClipTime(t1, rm.duration, WrapMode::Loop);
    rm.evaluate(t, now, yaw);
    lateral += w * (now.x - g.lateralDrift * t / rm.duration);
  };
  addTravel(walk, 1.0f - runWeight_);
  addTravel(run, runWeight_);
  const glm::vec2 step = forwardOf(state_.heading) * std::clamp(forward, 0.0f, limit);
  if (plan_ && !state_.done) {
    advance(state_, *plan_, waypoints(), settings_, step);
  } else {
    state_.position += step;
  }
  if (plan_ && state_.done && !wasDone) doneTime_ = clock;
  heading = state_.heading;

  // The gait's weight over the posture follows the speed (exact first-order lag).
  const float target = std::clamp(gaitSpeed / (0.3f * walk.groundSpeed), 0.0f, 1.0f);
  weight_ += (target - weight_) * (1.0f - std::exp(-dt / settings_.blendTimeConstant));
  // The lag reaches its ends (a float lag stalls an ulp short of 1): at 1 the gait
  // replaces the posture outright, which blendOver does as a copy.
  if (weight_ < 1e-4f && target == 0.0f) weight_ = 0.0f;
  if (weight_ > 1.0f - 1e-4f && target == 1.0f) weight_ = 1.0f;
  const glm::vec3 sway = glm::angleAxis(state_.heading, glm::vec3(0, 1, 0)) * glm::vec3(lateral * weight_, 0.0f, 0.0f);
  position.x = state_.position.x + sway.x;
  position.z = state_.position.y + sway.z;
  drawnAt_ = position;
  Transform placement;
  placement.translation = position;
  placement.rotation = glm::angleAxis(heading, glm::vec3(0, 1, 0));
  if (weight_ <= 0.0f) {  // the posture alone; planted feet ease into it
    const float none[2] = {0.0f, 0.0f};
    if (planter_.active()) planter_.apply(skeleton, pose, placement.matrix(), none, 0.0f, dt, settings_.feet);
    return;
  }
  const std::span<Transform> gait(gaitPose_);
  const float walkTime = static_cast<float>(gaitTime(walk, phase_) - std::floor(phase_ + walk.strikePhase) * walk.duration());
  // A clip that travels plays in place (its travel moves the character). An
  // in-place clip is played as it is, as analyzeGait measured it: taking its
  // root's sway and hip turn out would move the legs away from feet that do not
  // hang from that root (RobotExpressive's IK feet went 20 cm off the shins
  // walking and 36 cm running, against the clips' own 5 and 3 cm).
  sampleAnimationClip(*walk.clip, walkTime, walk.hasRootMotion, gait, &walkCursor_, &walkRootCursor_);
  if (runWeight_ > 0.0f) {
    const float runTime = static_cast<float>(gaitTime(run, phase_) - std::floor(phase_ + run.strikePhase) * run.duration());
    sampleAnimationClip(*run.clip, runTime, run.hasRootMotion, scratch, &runCursor_, &runRootCursor_);
    blendOver(gait, scratch, runWeight_, {});
  }
  blendOver(pose, gait, weight_, {});
  // Plant the feet where they touch down, in this frame's placement.
  const float floor[2] = {walk.floor[0] + runWeight_ * (run.floor[0] - walk.floor[0]),
                          walk.floor[1] + runWeight_ * (run.floor[1] - walk.floor[1])};
  planter_.apply(skeleton, pose, placement.matrix(), floor, weight_, dt, settings_.feet);
}

}  // namespace marionette
