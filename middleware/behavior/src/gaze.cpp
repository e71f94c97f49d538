#include "marionette/behavior/gaze.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/head_motion.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/text.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/core/angles.hpp"

namespace marionette {

namespace {

// The chain an influence turns, root-most first (missing joints skipped), with
// each joint's yaw and pitch limits. At most hips + spine + neck + head.
struct Chain {
  int joint[16];
  float yawLimit[16], pitchLimit[16];
  int size = 0;
  float totalYaw = 0.0f, totalPitch = 0.0f;
  void add(int j, float yaw, float pitch) {
    if (j < 0 || size == 16) return;
    joint[size] = j;
    yawLimit[size] = yaw;
    pitchLimit[size] = pitch;
    totalYaw += yaw;
    totalPitch += pitch;
    ++size;
  }
};

Chain chainOf(GazeInfluence influence, const RigJoints& j, const GazeSettings& s) {
  Chain c;
  if (influence == GazeInfluence::Eyes) return c;
  if (influence == GazeInfluence::Whole) c.add(j.hips, s.hipsYaw, 0.0f);
  if (influence == GazeInfluence::Waist || influence == GazeInfluence::Whole)
    for (int k : j.spine) c.add(k, s.spineYaw, s.spinePitch);
  if (influence == GazeInfluence::Shoulder && !j.spine.empty()) c.add(j.spine.back(), s.spineYaw, s.spinePitch);
  if (influence != GazeInfluence::Head) c.add(j.neck, s.neckYaw, s.neckPitch);
  c.add(j.head, s.headYaw, s.headPitch);
  return c;
}

bool hasEyes(const RigJoints& j) { return j.leftEye >= 0 || j.rightEye >= 0; }

glm::quat lookRotation(float yaw, float pitch) {
  return glm::angleAxis(yaw, glm::vec3(0, 1, 0)) * glm::angleAxis(pitch, glm::vec3(1, 0, 0));
}

// The rotation that turns unit vector `from` onto `to` by the shortest arc (identity when
// they agree; about any perpendicular axis when they are opposite).
glm::quat shortestArc(const glm::vec3& from, const glm::vec3& to) {
  const float d = glm::dot(from, to);
  if (d > 1.0f - 1e-7f) return glm::quat(1, 0, 0, 0);
  if (d < -1.0f + 1e-6f) {
    glm::vec3 axis = glm::cross(glm::vec3(1, 0, 0), from);
    if (glm::dot(axis, axis) < 1e-6f) axis = glm::cross(glm::vec3(0, 1, 0), from);
    return glm::angleAxis(3.14159265f, glm::normalize(axis));
  }
  const glm::vec3 c = glm::cross(from, to);
  return glm::normalize(glm::quat(1.0f + d, c.x, c.y, c.z));
}

glm::vec3 modelPosition(const Skeleton& s, std::span<const Transform> pose, int joint) {
  int chain[256];
  int n = 0;
  for (int p = joint; p >= 0 && n < 256; p = s.parents[static_cast<std::size_t>(p)]) chain[n++] = p;
  glm::mat4 m = s.rootTransform;
  for (int i = n - 1; i >= 0; --i) m = m * pose[static_cast<std::size_t>(chain[i])].matrix();
  return glm::vec3(m[3]);
}
}  // namespace

YawPitch yawPitchOf(const glm::vec3& d, float hint) noexcept {
  YawPitch out;
  const float horizontal = std::sqrt(d.x * d.x + d.z * d.z);
  out.yaw = std::atan2(d.x, d.z);
  out.pitch = std::atan2(-d.y, horizontal);
  // The branch nearest the current yaw: behind the character, keep the side it is on.
  if (std::isfinite(hint)) out.yaw += kTwoPi * std::round((hint - out.yaw) / kTwoPi);
  return out;
}

void DampedAngle::step(float target, float dt, float timeConstant, float maxSpeed) noexcept {
  if (!(dt > 0.0f) || !std::isfinite(target)) return;
  // x(t) = (x0 + (v0 + w x0) t) e^(-w t) about the target: exact for any dt.
  const double w = 1.0 / std::max(1e-4, static_cast<double>(timeConstant));
  const double x0 = static_cast<double>(value) - target, v0 = velocity;
  const double e = std::exp(-w * dt);
  const double x = (x0 + (v0 + w * x0) * dt) * e;
  const double v = (v0 - w * (v0 + w * x0) * dt) * e;
  const double maxStep = static_cast<double>(maxSpeed) * dt;
  const double stepTaken = std::clamp((target + x) - value, -maxStep, maxStep);
  value = static_cast<float>(value + stepTaken);
  velocity = static_cast<float>(std::clamp(v, -static_cast<double>(maxSpeed), static_cast<double>(maxSpeed)));
}

void DampedAngle::stepRamp(float from, float to, float dt, float timeConstant, float maxSpeed) noexcept {
  if (!(dt > 0.0f) || !std::isfinite(from) || !std::isfinite(to)) return;
  // About the ramp's particular solution p(t) = g(t) - 2 r / w, the rest is the
  // homogeneous critically damped motion: y(t) = (y0 + (y0' + w y0) t) e^(-w t).
  const double w = 1.0 / std::max(1e-4, static_cast<double>(timeConstant));
  const double r = (static_cast<double>(to) - from) / dt;
  const double y0 = static_cast<double>(value) - (from - 2.0 * r / w), dy0 = static_cast<double>(velocity) - r;
  const double e = std::exp(-w * dt);
  const double y = (y0 + (dy0 + w * y0) * dt) * e;
  const double dy = (dy0 - w * (dy0 + w * y0) * dt) * e;
  const double maxStep = static_cast<double>(maxSpeed) * dt;
  const double stepTaken = std::clamp((to - 2.0 * r / w + y) - value, -maxStep, maxStep);
  value = static_cast<float>(value + stepTaken);
  velocity = static_cast<float>(std::clamp(r + dy, -static_cast<double>(maxSpeed), static_cast<double>(maxSpeed)));
}

namespace {
// Where gaze is measured from: between the eyes, else the head, else the neck.
glm::vec3 gazeOrigin(const Skeleton& s, const RigJoints& j, std::span<const Transform> pose) noexcept {
  if (j.leftEye >= 0 && j.rightEye >= 0)
    return 0.5f * (modelPosition(s, pose, j.leftEye) + modelPosition(s, pose, j.rightEye));
  const int at = j.leftEye >= 0 ? j.leftEye : j.rightEye >= 0 ? j.rightEye : j.head >= 0 ? j.head : j.neck;
  return at >= 0 ? modelPosition(s, pose, at) : glm::vec3(0.0f);
}

void stepGaze(GazeState& g, const Chain& c, const glm::vec3& target, const glm::vec3& origin, bool eyes,
              const GazeSettings& s, float dt) noexcept {
  const glm::vec3 d = target - origin;
  const float hint = g.chainYaw.value + g.eyeYaw.value;
  YawPitch want{hint, g.chainPitch.value + g.eyePitch.value};  // at the eyes: hold the direction
  if (glm::dot(d, d) > 1e-6f) want = yawPitchOf(d, hint);
  want.yaw += g.offsetYaw;
  want.pitch += g.offsetPitch;
  const float chainYaw = std::clamp(want.yaw, -c.totalYaw, c.totalYaw);
  const float chainPitch = std::clamp(want.pitch, -c.totalPitch, c.totalPitch);
  // Each angle follows its target as a ramp from the last frame's value (exact
  // for a target moving steadily; the first frame has no last value: held).
  auto follow = [&](DampedAngle& a, int slot, float goal, float tau, float speed) {
    const float from = g.started ? g.lastTarget[slot] : goal;
    a.stepRamp(from, goal, dt, tau, speed);
    if (dt > 0.0f) g.lastTarget[slot] = goal;
  };
  follow(g.chainYaw, 0, chainYaw, s.timeConstant, s.maxSpeed);
  follow(g.chainPitch, 1, chainPitch, s.timeConstant, s.maxSpeed);
  // The eyes lead: they take what the chain has not turned yet, four times faster.
  const float eyeYaw = eyes ? std::clamp(want.yaw - g.chainYaw.value, -s.eyeYaw, s.eyeYaw) : 0.0f;
  const float eyePitch = eyes ? std::clamp(want.pitch - g.chainPitch.value, -s.eyePitch, s.eyePitch) : 0.0f;
  follow(g.eyeYaw, 2, eyeYaw, 0.25f * s.timeConstant, s.eyeMaxSpeed);
  follow(g.eyePitch, 3, eyePitch, 0.25f * s.timeConstant, s.eyeMaxSpeed);
  if (dt > 0.0f) g.started = true;
}

// The gaze holds in the model frame whatever the pose below does: the chain turns from where
// the pose below has the head facing to the damped aim (blended by the weight), shared
// along the chain in proportion to the limits; a last turn of the chain's top joint by the
// shortest arc puts its facing exactly on the aim (the yaw-then-pitch shares compose
// exactly only from a head that faces ahead).
void applyGaze(GazeState& g, const Chain& c, bool eyes, float weight, const Skeleton& skeleton,
               const RigJoints& joints, std::span<Transform> pose) noexcept {
  float baseYaw = 0.0f, basePitch = 0.0f, yaw = 0.0f, pitch = 0.0f;
  // Where the chain's top joint faces in the pose below: its rest forward (+Z, the
  // character's) carried by the rotation it has gained over its rest pose (cached).
  glm::vec3 facingBelow(0, 0, 1);
  glm::quat topBelow(1, 0, 0, 0);  // its model rotation in the pose below
  const int top = c.size > 0 ? c.joint[c.size - 1] : -1;
  if (top >= 0) {
    if (g.restTopJoint != top) {
      g.restTop = modelRotationOf(skeleton, skeleton.restPose, top);
      g.restTopJoint = top;
    }
    topBelow = modelRotationOf(skeleton, pose, top);
    facingBelow = (topBelow * glm::inverse(g.restTop)) * glm::vec3(0, 0, 1);
    const YawPitch below = yawPitchOf(facingBelow, g.chainYaw.value);
    baseYaw = below.yaw;
    basePitch = below.pitch;
    yaw = weight * (g.chainYaw.value - below.yaw);
    pitch = weight * (g.chainPitch.value - below.pitch);
  }
  const float aimYaw = baseYaw + yaw, aimPitch = basePitch + pitch;
  // Shared in proportion to the limits: every joint reaches its limit together.
  float cumYaw = 0.0f, cumPitch = 0.0f;
  glm::quat previous(1, 0, 0, 0);
  for (int i = 0; i + 1 < c.size; ++i) {
    cumYaw += c.totalYaw > 0.0f ? c.yawLimit[i] / c.totalYaw : 0.0f;
    cumPitch += c.totalPitch > 0.0f ? c.pitchLimit[i] / c.totalPitch : 0.0f;
    const glm::quat q = lookRotation(cumYaw * yaw, cumPitch * pitch);
    rotateInModelFrame(skeleton, pose, c.joint[i], q * glm::inverse(previous));
    previous = q;
  }
  if (top >= 0) {
    // The top joint takes the rest of the turn and a shortest arc onto the aim, set from
    // model rotations already known: the joints below it turned by `previous` in the model
    // frame, so its parent's model rotation is `previous` times what it was.
    const glm::quat whole = lookRotation(yaw, pitch);
    const glm::vec3 facing = whole * facingBelow;
    const float cp = std::cos(aimPitch);
    const glm::vec3 aim(cp * std::sin(aimYaw), -std::sin(aimPitch), cp * std::cos(aimYaw));
    const glm::quat onto = isFinite(facing) && glm::dot(facing, facing) > 0.5f
                               ? shortestArc(glm::normalize(facing), aim)
                               : glm::quat(1, 0, 0, 0);
    Transform& t = pose[static_cast<std::size_t>(top)];
    const glm::quat parentAfter = previous * (topBelow * glm::inverse(t.rotation));
    const glm::quat turned = glm::normalize(glm::inverse(parentAfter) * (onto * whole * topBelow));
    if (isFinite(turned)) t.rotation = turned;
  }
  if (!eyes) return;
  const glm::quat look = lookRotation(aimYaw + weight * g.eyeYaw.value, aimPitch + weight * g.eyePitch.value);
  const glm::quat delta = look * glm::inverse(lookRotation(aimYaw, aimPitch));
  rotateInModelFrame(skeleton, pose, joints.leftEye, delta);
  rotateInModelFrame(skeleton, pose, joints.rightEye, delta);
}
}  // namespace

void updateGaze(GazeState& g, const glm::vec3& targetModel, bool targetKnown, float weight, const GazeSettings& s,
                const Skeleton& skeleton, const RigJoints& joints, std::span<Transform> pose, float dt) noexcept {
  const Chain c = chainOf(g.influence, joints, s);  // once per frame, for the step and the pose
  const bool eyes = g.useEyes && hasEyes(joints);
  const glm::vec3 origin = gazeOrigin(skeleton, joints, pose);
  stepGaze(g, c, targetKnown ? targetModel : origin, origin, eyes, s, dt);
  applyGaze(g, c, eyes, weight, skeleton, joints, pose);
}

}  // namespace marionette
