// Locomotion steering and plan parsing (kinematic part; the gait on real
// characters is in tests/behavior/locomotion_real_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "marionette/behavior/locomotion.hpp"

using namespace marionette;

namespace {
constexpr float kPi = 3.14159265f;

LocomotionPlan planTo(std::vector<glm::vec2> waypoints, float speed = 1.2f) {
  LocomotionPlan p;
  p.waypoints = std::move(waypoints);
  p.speed = speed;
  return p;
}

// Runs steering at a fixed dt with travel along the heading; returns steps taken.
int simulate(SteeringState& s, const LocomotionPlan& plan, const LocomotionSettings& settings, float dt,
             int maxSteps, float* maxTurnRate = nullptr, float* maxSpeed = nullptr, bool* finite = nullptr) {
  int steps = 0;
  while (!s.done && steps < maxSteps) {
    const float heading0 = s.heading;
    const float limit = steer(s, plan, plan.waypoints, settings, dt);
    advance(s, plan, plan.waypoints, settings, glm::vec2(std::sin(s.heading), std::cos(s.heading)) * limit);
    if (maxTurnRate && dt > 0.0f)
      *maxTurnRate = std::max(*maxTurnRate, std::fabs(std::remainder(s.heading - heading0, 2.0f * kPi)) / dt);
    if (maxSpeed) *maxSpeed = std::max(*maxSpeed, s.speed);
    if (finite && !(std::isfinite(s.position.x) && std::isfinite(s.position.y) && std::isfinite(s.heading) &&
                    std::isfinite(s.speed)))
      *finite = false;
    ++steps;
  }
  return steps;
}

LocomotionParameters to(std::vector<glm::vec2> waypoints, LocomotionManner manner = LocomotionManner::Walk) {
  LocomotionParameters p;
  p.waypoints = std::move(waypoints);
  p.manner = manner;
  return p;
}

LocomotionSet fakeSet() {
  LocomotionSet set;
  set.walk.groundSpeed = 1.2f;
  set.run.groundSpeed = 3.0f;
  return set;
}
}  // namespace

// A target 5 m away, behind and to the side: arrives within the arrive radius,
// turning no faster than the turn speed, never faster than the cruise speed,
// for every dt from 1/240 s to 1 s.
TEST(LocomotionSteering, ArrivesAtTheTargetForAnyTimeStep) {
  LocomotionSettings settings;
  for (float dt : {1.0f / 240.0f, 1.0f / 60.0f, 1.0f / 30.0f, 0.1f, 0.25f, 0.5f, 1.0f}) {
    SteeringState s;
    s.heading = 0.0f;  // faces +Z; the target is behind-left
    const LocomotionPlan plan = planTo({{3.0f, -4.0f}});
    float turn = 0.0f, speed = 0.0f;
    bool finite = true;
    simulate(s, plan, settings, dt, 100000, &turn, &speed, &finite);
    EXPECT_TRUE(s.done) << "dt " << dt;
    EXPECT_TRUE(finite) << "dt " << dt;
    EXPECT_LE(glm::length(s.position - glm::vec2(3.0f, -4.0f)), settings.arriveRadius + 1e-4f) << "dt " << dt;
    EXPECT_LE(turn, settings.turnSpeed * 1.0001f) << "dt " << dt;
    EXPECT_LE(speed, plan.speed * 1.0001f) << "dt " << dt;
    EXPECT_EQ(s.speed, 0.0f);
  }
}

// Acceleration and braking are bounded: the speed changes by at most a dt per step.
TEST(LocomotionSteering, AcceleratesAndBrakesWithinTheLimits) {
  LocomotionSettings settings;
  SteeringState s;
  const LocomotionPlan plan = planTo({{0.0f, 10.0f}}, 2.0f);
  const float dt = 1.0f / 60.0f;
  float previous = 0.0f, peak = 0.0f;
  while (!s.done) {
    const float limit = steer(s, plan, plan.waypoints, settings, dt);
    EXPECT_LE(s.speed - previous, settings.acceleration * dt + 1e-5f);
    // Braking follows sqrt(2 a d): within a step of the limit.
    EXPECT_LE(previous - s.speed, settings.deceleration * dt * 1.5f + 0.05f);
    previous = s.speed;
    peak = std::max(peak, s.speed);
    advance(s, plan, plan.waypoints, settings, {0.0f, limit});
  }
  EXPECT_NEAR(peak, 2.0f, 1e-4f);  // reached the cruise speed on 10 m
  EXPECT_NEAR(s.position.y, 10.0f, settings.arriveRadius);
}

// Facing at arrival: the final heading is within the tolerance of the one asked.
TEST(LocomotionSteering, EndsFacingAsAsked) {
  LocomotionSettings settings;
  for (float facing : {0.0f, 1.0f, -2.5f, kPi}) {
    SteeringState s;
    LocomotionPlan plan = planTo({{-2.0f, 3.0f}});
    plan.hasFacing = true;
    plan.facing = facing;
    simulate(s, plan, settings, 1.0f / 60.0f, 100000);
    ASSERT_TRUE(s.done);
    EXPECT_LE(std::fabs(std::remainder(s.heading - facing, 2.0f * kPi)), settings.facingTolerance + 1e-5f);
  }
}

// Waypoints are passed in order (within the waypoint radius) and the last one is reached.
TEST(LocomotionSteering, FollowsWaypoints) {
  LocomotionSettings settings;
  SteeringState s;
  const LocomotionPlan plan = planTo({{0.0f, 3.0f}, {3.0f, 3.0f}, {3.0f, 0.0f}});
  const float dt = 1.0f / 60.0f;
  float closest[3] = {1e9f, 1e9f, 1e9f};
  int steps = 0;
  while (!s.done && steps++ < 100000) {
    const float limit = steer(s, plan, plan.waypoints, settings, dt);
    advance(s, plan, plan.waypoints, settings, glm::vec2(std::sin(s.heading), std::cos(s.heading)) * limit);
    for (int i = 0; i < 3; ++i) closest[i] = std::min(closest[i], glm::length(s.position - plan.waypoints[i]));
  }
  ASSERT_TRUE(s.done);
  EXPECT_LE(closest[0], settings.waypointRadius);
  EXPECT_LE(closest[1], settings.waypointRadius);
  EXPECT_LE(closest[2], settings.arriveRadius + 1e-4f);
}

// Stopping short of a character: proximity is kept.
TEST(LocomotionSteering, StopsAtTheProximity) {
  LocomotionSettings settings;
  SteeringState s;
  LocomotionPlan plan = planTo({{0.0f, 4.0f}});
  plan.proximity = 1.0f;
  simulate(s, plan, settings, 1.0f / 60.0f, 100000);
  ASSERT_TRUE(s.done);
  EXPECT_NEAR(s.position.y, 3.0f, settings.arriveRadius + 1e-4f);
}

// Degenerate plans: a target at the character's own place, NaN dt, and a huge
// distance all stay finite; the estimate of a 10 km walk is its length / speed.
TEST(LocomotionSteering, ExtremeCases) {
  LocomotionSettings settings;
  SteeringState here;
  const LocomotionPlan same = planTo({{0.0f, 0.0f}});
  simulate(here, same, settings, 1.0f / 60.0f, 10);
  EXPECT_TRUE(here.done);
  EXPECT_EQ(here.position, glm::vec2(0.0f));

  SteeringState s;
  const LocomotionPlan plan = planTo({{0.0f, 5.0f}});
  EXPECT_EQ(steer(s, plan, plan.waypoints, settings, std::nanf("")), 0.0f);
  EXPECT_TRUE(std::isfinite(s.heading) && std::isfinite(s.speed));

  const LocomotionPlan far = planTo({{0.0f, 10000.0f}}, 1.25f);
  const double seconds = estimateLocomotionSeconds({}, far, far.waypoints, settings);
  // Plus about 0.6 s of acceleration and braking; float positions 10 km out round
  // each 2 cm step by up to 0.5 mm, which adds up to a few seconds (0.1 %).
  EXPECT_NEAR(seconds, 10000.0 / 1.25, 8.0);
}

// The estimate used for BML sync points matches a simulation at another rate.
TEST(LocomotionSteering, EstimateMatchesTheSimulation) {
  LocomotionSettings settings;
  const LocomotionPlan plan = planTo({{4.0f, 3.0f}});
  const double estimate = estimateLocomotionSeconds({}, plan, plan.waypoints, settings);
  SteeringState s;
  const int steps = simulate(s, plan, settings, 1.0f / 240.0f, 1000000);
  EXPECT_NEAR(estimate, steps / 240.0, 0.05);
}

// The plan from typed parameters (BML's spelling of them: tests/bml/behavior_parameters_test.cpp).
TEST(LocomotionPlanParsing, TargetsMannersAndBadValues) {
  const LocomotionSet set = fakeSet();  // no run clip: RUN is twice the walk, unless set
  {
    LocomotionPlan p;
    std::string warning;
    EXPECT_EQ(makeLocomotionPlan(to({{1, 2}}, LocomotionManner::Run), set, {}, p, warning), "");
    EXPECT_FLOAT_EQ(p.speed, 2.4f);
  }
  LocomotionSettings settings;
  settings.runSpeed = 3.0f;
  {
    LocomotionPlan p;
    std::string warning;
    EXPECT_EQ(makeLocomotionPlan(to({{1, 2}}, LocomotionManner::Run), set, settings, p, warning), "");
    ASSERT_EQ(p.waypoints.size(), 1u);
    EXPECT_EQ(p.waypoints[0], glm::vec2(1.0f, 2.0f));
    EXPECT_FLOAT_EQ(p.speed, 3.0f);
    EXPECT_EQ(warning, "");
  }
  {
    LocomotionPlan p;
    std::string warning;
    LocomotionParameters facing = to({{1, 2}});
    facing.facing = kPi / 2;
    EXPECT_EQ(makeLocomotionPlan(facing, set, settings, p, warning), "");
    EXPECT_EQ(p.waypoints[0], glm::vec2(1.0f, 2.0f));
    EXPECT_TRUE(p.hasFacing);
    EXPECT_NEAR(p.facing, kPi / 2, 1e-6f);
    EXPECT_FLOAT_EQ(p.speed, 1.2f);
  }
  {
    LocomotionPlan p;
    std::string warning;
    EXPECT_EQ(makeLocomotionPlan(to({{0, 1}, {2, 3}, {4, 5}}), set, settings, p, warning), "");
    EXPECT_EQ(p.waypoints.size(), 3u);
  }
  {
    LocomotionPlan p;
    std::string warning;
    LocomotionParameters bob;
    bob.targetCharacter = "Bob";
    bob.manner = LocomotionManner::Stroll;
    bob.speed = -3.0f;
    EXPECT_EQ(makeLocomotionPlan(bob, set, settings, p, warning), "");
    EXPECT_EQ(p.targetCharacter, "Bob");
    EXPECT_TRUE(p.faceTargetCharacter);
    EXPECT_NE(warning.find("speed '-3'"), std::string::npos) << warning;
    EXPECT_FLOAT_EQ(p.speed, 0.6f);  // the stroll's, the bad speed ignored
  }
  const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
  for (const LocomotionParameters& bad : {to({{nan, 1}}), to({{1, inf}}), LocomotionParameters{},
                                          to(std::vector<glm::vec2>(LocomotionParameters::kMaxWaypoints + 1))}) {
    LocomotionPlan p;
    std::string warning;
    const std::string why = makeLocomotionPlan(bad, set, settings, p, warning);
    EXPECT_NE(why, "");
    EXPECT_TRUE(p.waypoints.empty()) << why;
  }
  LocomotionPlan p;
  std::string warning;
  EXPECT_NE(makeLocomotionPlan(to({{nan, 1}}), set, settings, p, warning).find("'nan 1' is not finite"), std::string::npos);
}
