// Pointing on a hand-made upper body: the forearm's line passes through the
// target, the arm on the target's side is picked (or the one asked for), near
// targets are reached for, and the stiff cases (straight up, straight down,
// behind, at the shoulder, 1000 km away, NaN) give a finite pose with no flip
// between frames. Then through a Character: BML-style requests, a character
// target, bad requests as messages, --stats.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "joint_rotation.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/behavior/pointing.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic.hpp"
#include "synthetic_upper_body.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

constexpr float kDeg = 0.017453293f;

struct Bench {
  std::shared_ptr<Rig> rig = makeUpperBodyRig();
  const Skeleton& s = rig->skeleton();
  std::vector<Transform> pose{s.restPose.begin(), s.restPose.end()};

  PointingState bind(const glm::vec3& target, PointingArms arms = PointingArms::Nearest) {
    BehaviorRequest r;
    r.id = "p";
    r.kind = BehaviorKind::Pointing;
    r.parameters = PointingParameters{BehaviorTarget::at(target), arms};
    PointingState st;
    std::string warning;
    const std::string why = bindPointing(r, *rig, s, [](std::string_view, std::string_view) { return -2; }, st, warning);
    EXPECT_EQ(why, "");
    EXPECT_EQ(warning, "");
    return st;
  }
  glm::vec3 origin(int joint) const { return glm::vec3(modelMatrixOf(s, pose, joint)[3]); }
};

bool finitePose(const std::vector<Transform>& pose) {
  for (const Transform& t : pose)
    if (!finite(t)) return false;
  return true;
}

bool samePose(const std::vector<Transform>& a, const std::vector<Transform>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Transform)) == 0;
}

}  // namespace

TEST(Pointing, ForearmLinePassesThroughTheTargetOnTheTargetsSide) {
  Bench b;
  const glm::vec3 target(1.5f, 1.6f, 2.0f);  // ahead and to the left
  PointingState st = b.bind({1.5f, 1.6f, 2.0f});
  const std::vector<Transform> before = b.pose;
  updatePointing(st, target, true, 1.0f, {}, b.s, b.pose);
  EXPECT_TRUE(st.arm[0]);
  EXPECT_FALSE(st.arm[1]);
  EXPECT_LT(pointingErrorRadians(b.s, b.pose, st.limb[0], target), 0.2f * kDeg);
  // The right arm did not move; the elbow keeps its bend and hangs below the aim line.
  const int right = b.s.findJoint("RightArm"), rightFore = b.s.findJoint("RightForeArm");
  EXPECT_TRUE(std::memcmp(&b.pose[static_cast<std::size_t>(right)], &before[static_cast<std::size_t>(right)], sizeof(Transform)) == 0);
  EXPECT_TRUE(std::memcmp(&b.pose[static_cast<std::size_t>(rightFore)], &before[static_cast<std::size_t>(rightFore)], sizeof(Transform)) == 0);
  const glm::vec3 shoulder = b.origin(st.limb[0].upper), elbow = b.origin(st.limb[0].lower);
  const glm::vec3 wrist = b.origin(st.limb[0].end);
  const float bend = std::acos(glm::dot(glm::normalize(elbow - shoulder), glm::normalize(wrist - elbow)));
  EXPECT_NEAR(bend, PointingSettings{}.elbowBend, 0.5f * kDeg);
  const glm::vec3 aim = glm::normalize(target - shoulder);
  const glm::vec3 offLine = (elbow - shoulder) - aim * glm::dot(elbow - shoulder, aim);
  EXPECT_LT(offLine.y, 0.0f) << "the elbow hangs down";
  // Bone lengths are kept.
  EXPECT_NEAR(glm::length(elbow - shoulder), std::hypot(0.3f, 0.02f), 1e-5f);
}

TEST(Pointing, ModeChoosesTheArmEvenAcrossTheBody) {
  for (const auto& [mode, left, right] : {std::tuple{PointingArms::Right, false, true}, std::tuple{PointingArms::Left, true, false},
                                          std::tuple{PointingArms::Both, true, true}}) {
    Bench b;
    const glm::vec3 target(1.0f, 1.2f, 1.5f);
    PointingState st = b.bind({1.0f, 1.2f, 1.5f}, mode);
    updatePointing(st, target, true, 1.0f, {}, b.s, b.pose);
    EXPECT_EQ(st.arm[0], left) << static_cast<int>(mode);
    EXPECT_EQ(st.arm[1], right) << static_cast<int>(mode);
    for (int side = 0; side < 2; ++side) {
      if (!st.arm[side]) continue;
      EXPECT_LT(pointingErrorRadians(b.s, b.pose, st.limb[side], target), 0.2f * kDeg) << static_cast<int>(mode);
    }
  }
}

TEST(Pointing, ANearTargetIsReachedFor) {
  Bench b;
  PointingState st = b.bind({0.3f, 1.3f, 0.3f});
  const glm::vec3 target(0.3f, 1.3f, 0.3f);  // nearer than the hand would be when pointing
  updatePointing(st, target, true, 1.0f, {}, b.s, b.pose);
  EXPECT_LT(glm::length(b.origin(st.limb[0].end) - target), 1e-3f);
}

TEST(Pointing, WeightZeroLeavesThePoseAndHalfWeightBlends) {
  Bench b;
  PointingState st = b.bind({1.0f, 2.0f, 1.0f});
  const std::vector<Transform> before = b.pose;
  updatePointing(st, {1.0f, 2.0f, 1.0f}, true, 0.0f, {}, b.s, b.pose);
  EXPECT_TRUE(samePose(b.pose, before));
  updatePointing(st, {1.0f, 2.0f, 1.0f}, true, 0.5f, {}, b.s, b.pose);
  const float half = pointingErrorRadians(b.s, b.pose, st.limb[0], {1.0f, 2.0f, 1.0f});
  EXPECT_GT(half, 5.0f * kDeg);  // between the hanging arm and the aim
  Bench full;
  PointingState st2 = full.bind({1.0f, 2.0f, 1.0f});
  updatePointing(st2, {1.0f, 2.0f, 1.0f}, true, 1.0f, {}, full.s, full.pose);
  const float rest = pointingErrorRadians(full.s, before, st2.limb[0], {1.0f, 2.0f, 1.0f});
  EXPECT_LT(half, rest);
}

// Straight up, straight down, behind, along the elbow's own direction, at the
// shoulder, very far: a finite pose; the forearm on the target wherever the
// target is beyond the hand.
TEST(Pointing, ExtremeTargetsGiveAFinitePose) {
  Bench probe;
  const glm::vec3 shoulder = probe.origin(probe.s.findJoint("LeftArm"));
  const glm::vec3 targets[] = {shoulder + glm::vec3(0, 5, 0),     shoulder + glm::vec3(0, -5, 0),
                               shoulder + glm::vec3(0, 0, -5),    shoulder + glm::vec3(2.2f, -5, 0),
                               shoulder + glm::vec3(-3, 0, 0.01f), shoulder + glm::vec3(0, 0, 1e6f),
                               shoulder + glm::vec3(1e-5f, 0, 0), shoulder};
  for (const glm::vec3& t : targets) {
    Bench b;
    PointingState st = b.bind({0.0f, 0.0f, 0.0f}, PointingArms::Left);
    for (int frame = 0; frame < 3; ++frame) updatePointing(st, t, true, 1.0f, {}, b.s, b.pose);
    EXPECT_TRUE(finitePose(b.pose)) << t.x << " " << t.y << " " << t.z;
    if (glm::length(t - shoulder) > 1.0f) {
      EXPECT_LT(pointingErrorRadians(b.s, b.pose, st.limb[0], t), 0.5f * kDeg) << t.x << " " << t.y << " " << t.z;
    }
  }
  // A NaN target (a lost character) holds the last aim.
  Bench b;
  PointingState st = b.bind({0.0f, 0.0f, 0.0f}, PointingArms::Left);
  const glm::vec3 t(1, 2, 1);
  updatePointing(st, t, true, 1.0f, {}, b.s, b.pose);
  b.pose.assign(b.s.restPose.begin(), b.s.restPose.end());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  updatePointing(st, {nan, 0.0f, 0.0f}, true, 1.0f, {}, b.s, b.pose);
  EXPECT_TRUE(finitePose(b.pose));
  EXPECT_LT(pointingErrorRadians(b.s, b.pose, st.limb[0], t), 0.2f * kDeg);
  // Never started and the target unknown: nothing moves.
  Bench c;
  PointingState idle = c.bind({0.0f, 0.0f, 0.0f});
  updatePointing(idle, t, false, 1.0f, {}, c.s, c.pose);
  EXPECT_TRUE(samePose(c.pose, Bench{}.pose));
}

// A target circling the shoulder at 1.5 m through every direction (including
// the elbow's down-and-out direction, where the bend plane is undefined): the
// arm turns smoothly, never flipping between two frames.
TEST(Pointing, ATargetCirclingTheShoulderNeverFlipsTheArm) {
  Bench b;
  PointingState st = b.bind({0.0f, 0.0f, 0.0f}, PointingArms::Left);
  const glm::vec3 shoulder = b.origin(b.s.findJoint("LeftArm"));
  const int upper = b.s.findJoint("LeftArm"), lower = b.s.findJoint("LeftForeArm");
  std::vector<Transform> last;
  float worst = 0.0f, worstStep = 0.0f;
  const int steps = 2000;
  for (int k = 0; k <= steps; ++k) {
    const float a = 6.2831853f * 3.0f * static_cast<float>(k) / steps;  // three turns, tilted circles
    const glm::vec3 dir = glm::normalize(glm::vec3(std::cos(a), std::sin(a) * std::cos(0.7f * a), std::sin(a) * std::sin(0.7f * a)));
    b.pose.assign(b.s.restPose.begin(), b.s.restPose.end());
    updatePointing(st, shoulder + 1.5f * dir, true, 1.0f, {}, b.s, b.pose);
    ASSERT_TRUE(finitePose(b.pose));
    if (!last.empty()) {
      for (int j : {upper, lower})
        worst = std::max(worst, preciseAngleBetween(last[static_cast<std::size_t>(j)].rotation, b.pose[static_cast<std::size_t>(j)].rotation));
    }
    last = b.pose;
  }
  worstStep = 6.2831853f * 3.0f / steps;  // the target's own angular step
  std::printf("pointing circle: worst joint step %.3f deg for a target step of %.3f deg\n",
              static_cast<double>(worst / kDeg), static_cast<double>(worstStep / kDeg));
  EXPECT_LT(worst, 10.0f * worstStep);
}

TEST(PointingCharacter, ARequestAimsTheArmAndShowsInStats) {
  Scene scene;
  scene.setStatsEnabled(true);
  auto rig = makeUpperBodyRig();
  Character* c = scene.addCharacter("c", rig);
  c->setPosition({1.0f, 0.0f, 2.0f});
  c->setHeading(0.5f);
  BehaviorRequest r;
  r.id = "p";
  r.kind = BehaviorKind::Pointing;
  r.syncs = {{"start", 0.0}, {"ready", 0.3}, {"relax", 1.5}, {"end", 2.0}};
  r.parameters = PointingParameters{BehaviorTarget::at({3.0f, 1.5f, 4.0f}), PointingArms::Right};
  const BehaviorResult added = c->addBehavior(r);
  ASSERT_TRUE(added.realized) << added.message;
  EXPECT_EQ(added.message, "");
  EXPECT_FALSE(c->stats().used(Controller::Pointing));
  for (int f = 0; f < 60; ++f) scene.update(1.0 / 60.0);  // to t = 1 s: full weight
  EXPECT_TRUE(c->stats().used(Controller::Pointing));
  const auto model = c->transformBuffer().modelMatrices();
  const glm::mat4 world = c->transformBuffer().worldMatrix();
  auto at = [&](const char* joint) { return glm::vec3(world * model[static_cast<std::size_t>(rig->skeleton().findJoint(joint))][3]); };
  const glm::vec3 elbow = at("RightForeArm"), wrist = at("RightHand"), target(3.0f, 1.5f, 4.0f);
  EXPECT_LT(std::acos(std::clamp(glm::dot(glm::normalize(wrist - elbow), glm::normalize(target - elbow)), -1.0f, 1.0f)), 0.2f * kDeg);
  for (int f = 0; f < 90; ++f) scene.update(1.0 / 60.0);  // past the end: back to the rest pose
  const auto after = c->transformBuffer().modelMatrices();
  const int fore = rig->skeleton().findJoint("RightForeArm");
  EXPECT_LT(glm::length(glm::vec3(after[static_cast<std::size_t>(fore)][3]) -
                        glm::vec3(modelMatrixOf(rig->skeleton(), rig->skeleton().restPose, fore)[3])), 1e-5f);
}

TEST(PointingCharacter, PointsAtAnotherCharactersChestOrJoint) {
  Scene scene;
  auto rig = makeUpperBodyRig();
  Character* c = scene.addCharacter("c", rig);
  Character* bob = scene.addCharacter("bob", rig);
  bob->setPosition({-2.0f, 0.0f, 3.0f});
  for (const char* target : {"bob", "bob:Head"}) {
    BehaviorRequest r;
    r.id = std::string("p_") + target;
    r.kind = BehaviorKind::Pointing;
    r.syncs = {{"start", scene.time()}, {"end", scene.time() + 5.0}};
    r.parameters = PointingParameters{std::strcmp(target, "bob") == 0 ? BehaviorTarget::of("bob") : BehaviorTarget::of("bob", "Head")};
    const BehaviorResult added = c->addBehavior(r);
    ASSERT_TRUE(added.realized) << added.message;
    for (int f = 0; f < 120; ++f) scene.update(1.0 / 60.0);
    const auto model = c->transformBuffer().modelMatrices();
    auto at = [&](Character* who, const char* joint) {
      return glm::vec3(who->transformBuffer().worldMatrix() *
                       who->transformBuffer().modelMatrices()[static_cast<std::size_t>(rig->skeleton().findJoint(joint))][3]);
    };
    const glm::vec3 aim = at(bob, std::strcmp(target, "bob") == 0 ? "Chest" : "Head");
    const glm::vec3 elbow = at(c, "RightForeArm"), wrist = at(c, "RightHand");  // bob is on c's right (-X)
    EXPECT_LT(std::acos(std::clamp(glm::dot(glm::normalize(wrist - elbow), glm::normalize(aim - elbow)), -1.0f, 1.0f)), 0.3f * kDeg) << target;
    (void)model;
    c->cancelBehavior(r.id, 0.0);
    scene.update(1.0 / 60.0);
  }
}

TEST(PointingCharacter, BadRequestsAreMessagesNotCrashes) {
  Scene scene;
  auto rig = makeUpperBodyRig();
  Character* c = scene.addCharacter("c", rig);
  auto request = [&](const std::string& id, BehaviorParameters params) {
    BehaviorRequest r;
    r.id = id;
    r.kind = BehaviorKind::Pointing;
    r.syncs = {{"start", 0.0}, {"end", 1.0}};
    r.parameters = std::move(params);
    return c->addBehavior(r);
  };
  BehaviorResult r = request("none", PointingParameters{});
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("a pointing needs a target"), std::string::npos) << r.message;
  r = request("nan", PointingParameters{BehaviorTarget::at({std::nanf(""), 1.0f, 2.0f})});
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("pointing target 'nan 1 2' is not finite"), std::string::npos) << r.message;
  r = request("who", PointingParameters{BehaviorTarget::of("nobody")});
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("the scene has no character or object 'nobody'"), std::string::npos) << r.message;
  r = request("joint", PointingParameters{BehaviorTarget::of("c", "Tail")});
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("character 'c' has no joint 'Tail'"), std::string::npos) << r.message;
  r = request("kind", HeadParameters{});  // parameters of another kind: no target
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("a pointing needs a target"), std::string::npos) << r.message;
  // BML's mode text is read by the realizer (tests/bml/behavior_parameters_test.cpp).
  // A character without arms.
  auto armless = std::make_shared<Rig>(*makeUpperBodyAsset());
  CharacterProfile p = upperBodyProfile();
  p.leftArm = p.rightArm = {};
  armless->setProfile(p);
  Character* d = scene.addCharacter("d", armless);
  BehaviorRequest q;
  q.id = "q";
  q.kind = BehaviorKind::Pointing;
  q.syncs = {{"start", 0.0}, {"end", 1.0}};
  q.parameters = PointingParameters{BehaviorTarget::at({1.0f, 1.0f, 1.0f})};
  r = d->addBehavior(q);
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("no arm to point with"), std::string::npos) << r.message;
  for (int f = 0; f < 30; ++f) scene.update(1.0 / 30.0);
  for (const glm::mat4& m : c->transformBuffer().modelMatrices()) EXPECT_TRUE(std::isfinite(m[3].x + m[3].y + m[3].z));
}
