// Idle life (behavior/idle_life.hpp): the blink emitter's interval law, determinism, the lids'
// closure and how it combines with the face; the breathing emitter's amplitude and rate
// measured from the pose, its smoothness at start, stop and extreme parameters; neither
// changes what a gaze does to the eyes and the head. On a synthetic upper body with eyes and
// two blink morphs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "joint_rotation.hpp"
#include "marionette/behavior/idle_life.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_upper_body.hpp"

using namespace marionette;
using marionette::test::modelRotation;
using marionette::test::preciseAngleBetween;

namespace {

constexpr float kRadToDeg = 57.29577951f;

// The upper body with eyes and blink morphs ("CLOSE_EYES": both at 1).
std::shared_ptr<Rig> idleRig(bool blinkMorphs = true) {
  auto asset = test::makeUpperBodyAsset();
  Skeleton& s = asset->skeleton;
  const int head = s.findJoint("Head");
  for (float side : {1.0f, -1.0f}) {
    Transform t;
    t.translation = {side * 0.03f, 0.08f, 0.08f};
    s.addJoint(side > 0 ? "LeftEye" : "RightEye", head, t);
  }
  if (blinkMorphs) asset->morphTargets = {"smile", "blink_left", "blink_right"};
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfile p = test::upperBodyProfile();
  p.leftEye = "LeftEye";
  p.rightEye = "RightEye";
  if (blinkMorphs) p.face["CLOSE_EYES"] = {{"blink_left", 1.0f}, {"blink_right", 1.0f}};
  rig->setProfile(std::move(p));
  return rig;
}

BehaviorRequest emitter(std::string id, BehaviorKind kind, BehaviorParameters parameters, double at = 0.0) {
  BehaviorRequest r{.id = std::move(id), .kind = kind, .syncs = {{"start", at}, {"end", at}}, .parameters = std::move(parameters)};
  r.persistent = true;
  return r;
}

std::vector<double> blinkIntervals(const BlinkParameters& p, std::uint64_t seed, int count) {
  BlinkState st;
  std::string warning;
  EXPECT_EQ(bindBlink(emitter("b", BehaviorKind::BlinkEmitter, p), *idleRig(), seed, st, warning), "");
  std::vector<double> out;
  double last = st.onset;
  for (int i = 0; i < count; ++i) {
    (void)advanceBlink(st, st.onset + kBlinkSeconds);  // past this blink: the next onset is drawn
    out.push_back(st.onset - last);
    last = st.onset;
  }
  return out;
}

// A character of idleRig() blinking with `p` from time 0.
Character* blinkingCharacter(Scene& scene, const BlinkParameters& p) {
  Character* c = scene.addCharacter("c", idleRig());
  EXPECT_TRUE(c->addBehavior(emitter("blink", BehaviorKind::BlinkEmitter, p)).realized);
  return c;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

TEST(IdleLife, BlinkIntervalsFollowTheDocumentedLogNormal) {
  // Mean 3.5 s, coefficient of variation 0.6: sigma^2 = ln 1.36, the median e^mu = 3.5 / sqrt 1.36.
  const std::vector<double> v = blinkIntervals(BlinkParameters{}, 42, 20000);
  double sum = 0.0, sq = 0.0;
  for (double x : v) sum += x, sq += x * x;
  const double mean = sum / static_cast<double>(v.size());
  const double sd = std::sqrt(sq / static_cast<double>(v.size()) - mean * mean);
  const double sigma = std::sqrt(std::log(1.36)), mu = std::log(3.5) - 0.5 * sigma * sigma;
  std::printf("blink intervals: mean %.3f s (3.5), cv %.3f (0.6), p10 %.3f (%.3f), median %.3f (%.3f), p90 %.3f (%.3f)\n",
              mean, sd / mean, percentile(v, 0.1), std::exp(mu - 1.2816 * sigma), percentile(v, 0.5), std::exp(mu),
              percentile(v, 0.9), std::exp(mu + 1.2816 * sigma));
  EXPECT_NEAR(mean, 3.5, 0.05);
  EXPECT_NEAR(sd / mean, 0.6, 0.03);
  EXPECT_NEAR(percentile(v, 0.1), std::exp(mu - 1.2816 * sigma), 0.06);
  EXPECT_NEAR(percentile(v, 0.5), std::exp(mu), 0.06);
  EXPECT_NEAR(percentile(v, 0.9), std::exp(mu + 1.2816 * sigma), 0.12);
  EXPECT_GE(*std::min_element(v.begin(), v.end()), kBlinkSeconds + kBlinkRefractorySeconds - 1e-9);
  // A fixed rate (variation 0) blinks every mean interval.
  const std::vector<double> fixed = blinkIntervals(BlinkParameters{.meanIntervalSeconds = 2.0f, .variation = 0.0f}, 7, 50);
  for (double x : fixed) EXPECT_NEAR(x, 2.0, 1e-9);
}

TEST(IdleLife, BlinksAreTheSameForASeedAndDifferAcrossSeeds) {
  EXPECT_EQ(blinkIntervals(BlinkParameters{}, 5, 200), blinkIntervals(BlinkParameters{}, 5, 200));
  EXPECT_NE(blinkIntervals(BlinkParameters{}, 5, 200), blinkIntervals(BlinkParameters{}, 6, 200));
  // Through the scene: two characters of different names blink at different times; the same
  // scene run twice gives the same morph weights frame by frame.
  auto run = [](const std::string& name) {
    Scene scene;
    Character* c = scene.addCharacter(name, idleRig());
    EXPECT_TRUE(c->addBehavior(emitter("blink", BehaviorKind::BlinkEmitter, BlinkParameters{})).realized);
    std::vector<float> w;
    for (int f = 0; f < 600; ++f) {
      scene.update(1.0 / 60.0);
      w.push_back(c->transformBuffer().morphWeights()[1]);
    }
    return w;
  };
  EXPECT_EQ(run("anna"), run("anna"));
  EXPECT_NE(run("anna"), run("bert"));
}

TEST(IdleLife, ABlinkClosesTheLidsFullyAndOpensThemWithoutAJump) {
  Scene scene;
  Character* c = blinkingCharacter(scene, BlinkParameters{.meanIntervalSeconds = 1.0f, .variation = 0.2f});
  const double dt = 1.0 / 120.0;
  float peak = 0.0f, previous = 0.0f, step = 0.0f;
  int closures = 0;
  for (int f = 0; f < 1200; ++f) {  // 10 s
    scene.update(dt);
    const auto w = c->transformBuffer().morphWeights();
    ASSERT_EQ(w[1], w[2]);
    EXPECT_EQ(w[0], 0.0f);  // the smile is not touched
    closures += w[1] >= 0.99f && previous < 0.99f;
    peak = std::max(peak, w[1]);
    step = std::max(step, std::fabs(w[1] - previous));
    previous = w[1];
  }
  EXPECT_GE(peak, 0.99f);
  EXPECT_GE(closures, 6);  // about 10 at one a second
  EXPECT_LE(closures, 14);
  EXPECT_LE(step, 1.5 * dt / kBlinkCloseSeconds + 1e-3);  // smoothstep's steepest slope, no jump
  // Between blinks the lids are open.
  BlinkState st;
  std::string warning;
  ASSERT_EQ(bindBlink(emitter("b", BehaviorKind::BlinkEmitter, BlinkParameters{}), c->rig(), 1, st, warning), "");
  EXPECT_EQ(advanceBlink(st, st.onset - 0.01), 0.0f);
  EXPECT_NEAR(advanceBlink(st, st.onset + kBlinkCloseSeconds + 0.5 * kBlinkHoldSeconds), 1.0f, 1e-6f);
  EXPECT_EQ(advanceBlink(st, st.onset + kBlinkSeconds + 1e-6), 0.0f);
}

TEST(IdleLife, ABlinkOverAFaceThatClosesTheEyesStaysAtMostOne) {
  std::shared_ptr<Rig> rig = idleRig();
  BlinkState st;
  std::string warning;
  ASSERT_EQ(bindBlink(emitter("b", BehaviorKind::BlinkEmitter, BlinkParameters{}), *rig, 3, st, warning), "");
  const double onset = st.onset;
  for (float face : {1.0f, 0.25f, 0.0f}) {
    float lowest = 2.0f, highest = -1.0f;
    for (double t = onset - 0.1; t < onset + kBlinkSeconds + 0.1; t += 1.0 / 240.0) {
      std::vector<float> morphs = {0.0f, face, face};  // a CLOSE_EYES (1) or an ANGER's squint (0.25)
      BlinkState copy = st;
      std::vector<Transform> pose = rig->skeleton().restPose;
      applyBlink(copy, t, 1.0f, morphs, *rig, pose, 0.0f);
      lowest = std::min(lowest, morphs[1]);
      highest = std::max(highest, morphs[1]);
    }
    SCOPED_TRACE(face);
    EXPECT_LE(highest, 1.0f);      // no double closing
    EXPECT_GE(highest, 0.999f);    // the blink still closes a half-closed lid
    EXPECT_EQ(lowest, face);       // and never opens it wider than the face holds it
  }
}

TEST(IdleLife, BlinksAndBreathingLeaveTheGazeOfTheEyesAndHead) {
  const glm::vec3 target(1.0f, 1.4f, 1.0f);
  struct Frame {
    std::vector<glm::quat> rotations;  // eyes, head
    float aimError = 0.0f;             // radians, the left eye's forward from the target
  };
  auto run = [&](bool blink, bool breathe) {
    Scene scene;
    Character* c = scene.addCharacter("c", idleRig());
    BehaviorRequest gaze{.id = "gaze", .kind = BehaviorKind::Gaze, .syncs = {{"start", 0.0}, {"end", 100.0}},
                         .parameters = GazeParameters{.target = BehaviorTarget::at(target), .influence = GazeInfluence::Head}};
    EXPECT_TRUE(c->addBehavior(gaze).realized);
    if (blink) {
      EXPECT_TRUE(c->addBehavior(emitter("blink", BehaviorKind::BlinkEmitter, BlinkParameters{.meanIntervalSeconds = 0.6f})).realized);
    }
    if (breathe) {
      EXPECT_TRUE(c->addBehavior(emitter("breath", BehaviorKind::BreathingEmitter,
                                         BreathingParameters{.breathsPerMinute = 30.0f, .amplitudeDegrees = 5.0f})).realized);
    }
    const RigJoints& j = c->rig().joints();
    std::vector<Frame> out;
    for (int f = 0; f < 300; ++f) {
      scene.update(1.0 / 60.0);
      Frame fr;
      for (int joint : {j.leftEye, j.rightEye, j.head}) fr.rotations.push_back(modelRotation(*c, joint));
      const glm::vec3 eye(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(j.leftEye)][3]);
      const glm::vec3 forward = modelRotation(*c, j.leftEye) * glm::vec3(0.0f, 0.0f, 1.0f);
      fr.aimError = std::acos(std::clamp(glm::dot(glm::normalize(forward), glm::normalize(target - eye)), -1.0f, 1.0f));
      out.push_back(fr);
    }
    return out;
  };
  const std::vector<Frame> plain = run(false, false), blinking = run(true, false), breathing = run(false, true);
  // The blinks move no joint: the eyes and the head turn exactly as without them.
  for (std::size_t i = 0; i < plain.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(plain[i].rotations[k], blinking[i].rotations[k]) << "frame " << i;
  // Breathing lifts the head a little; the gaze still aims at the target as well as without it.
  float worst = 0.0f;
  for (std::size_t i = 60; i < plain.size(); ++i) worst = std::max(worst, std::fabs(plain[i].aimError - breathing[i].aimError));
  std::printf("gaze aim with and without 5 degree breaths: %.4f degrees apart at most\n", static_cast<double>(worst * kRadToDeg));
  EXPECT_LT(worst * kRadToDeg, 0.25f);
}

TEST(IdleLife, BreathingMovesTheChestByTheAmplitudeAtTheRate) {
  Scene scene;
  Character* c = scene.addCharacter("c", idleRig());
  const int chest = c->rig().joints().spine.back();
  const int clavicle = c->skeleton().findJoint("LeftShoulder"), arm = c->skeleton().findJoint("LeftArm");
  scene.update(0.0);
  const glm::quat rest = modelRotation(*c, chest), restClavicle = modelRotation(*c, clavicle),
                  restArm = modelRotation(*c, arm);
  ASSERT_TRUE(c->addBehavior(emitter("breath", BehaviorKind::BreathingEmitter,
                                     BreathingParameters{.breathsPerMinute = 12.0f, .amplitudeDegrees = 3.0f})).realized);
  const double dt = 1.0 / 60.0;
  float peak = 0.0f, shoulder = 0.0f, armTurn = 0.0f, previous = 0.0f, step = 0.0f, blendStep = 0.0f;
  int breaths = 0;
  bool high = false;
  for (int f = 0; f < 60 * 60; ++f) {  // one minute
    scene.update(dt);
    const float a = preciseAngleBetween(rest, modelRotation(*c, chest)) * kRadToDeg;
    ASSERT_TRUE(std::isfinite(a));
    // Pitched back: the chest's up leans toward -Z (the character faces +Z).
    if (a > 0.1f) {
      EXPECT_LT((modelRotation(*c, chest) * glm::vec3(0, 1, 0)).z, 0.0f);
    }
    if (f > 120) peak = std::max(peak, a);
    shoulder = std::max(shoulder, preciseAngleBetween(restClavicle, modelRotation(*c, clavicle)) * kRadToDeg);
    armTurn = std::max(armTurn, preciseAngleBetween(restArm, modelRotation(*c, arm)) * kRadToDeg);
    (f > 61 ? step : blendStep) = std::max(f > 61 ? step : blendStep, std::fabs(a - previous));  // blended in by 1 s
    if (!high && a > 1.5f) ++breaths, high = true;
    if (high && a < 0.5f) high = false;
    previous = a;
  }
  std::printf("breathing 12/min at 3 degrees: %d breaths in 60 s, chest peak %.3f degrees, clavicle %.3f, largest frame step %.4f\n",
              breaths, static_cast<double>(peak), static_cast<double>(shoulder), static_cast<double>(step));
  EXPECT_NEAR(peak, 3.0f, 0.05f);
  EXPECT_EQ(breaths, 12);
  EXPECT_GT(shoulder, 3.0f);  // the clavicle lifts over the chest's pitch
  EXPECT_LT(armTurn, 3.05f);  // the arm keeps its direction but for the chest's pitch
  // smoothstep's steepest slope over the inhale (42 % of 5 s), plus a margin.
  EXPECT_LT(step, 3.0f * 1.5f * static_cast<float>(dt / (0.42 * 5.0)) * 1.1f);
  EXPECT_LT(blendStep, 3.0f * 1.5f * static_cast<float>(dt / (0.42 * 5.0) + dt / kBreathingBlendSeconds) * 1.1f);
}

TEST(IdleLife, BreathingStartsAndStopsWithoutAPopAtAnyParameters) {
  struct Case {
    BreathingParameters p;
    const char* warned;  // a word the warning names, or nullptr
  };
  const Case cases[] = {
      {{.breathsPerMinute = 1e6f, .amplitudeDegrees = 8.0f}, "breathsPerMinute"},
      {{.breathsPerMinute = 60.0f, .amplitudeDegrees = 1e9f}, "amplitudeDegrees"},
      {{.amplitudeDegrees = std::nanf("")}, "amplitudeDegrees"},
      {{.amplitudeDegrees = -4.0f}, "amplitudeDegrees"},
      {{.amplitudeDegrees = 0.0f}, "amplitudeDegrees"},
      {{.breathsPerMinute = std::nanf(""), .periodRangeSeconds = -1.0f}, "periodRangeSeconds"},
      {{.breathsPerMinute = 30.0f, .periodRangeSeconds = 1.0f}, nullptr},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.warned ? k.warned : "plain");
    Scene scene;
    Character* c = scene.addCharacter("c", idleRig());
    const int chest = c->rig().joints().spine.back();
    scene.update(0.0);
    const glm::quat rest = modelRotation(*c, chest);
    const BehaviorResult r = c->addBehavior(emitter("breath", BehaviorKind::BreathingEmitter, k.p, 0.5));
    ASSERT_TRUE(r.realized) << r.message;
    if (k.warned) EXPECT_NE(r.message.find(k.warned), std::string::npos) << r.message;
    else EXPECT_EQ(r.message, "");
    // Stopped at 6 s by a later request of its kind.
    bool stopped = false;
    float previous = 0.0f, step = 0.0f, last = 0.0f;
    const double dt = 1.0 / 60.0;
    for (int f = 0; f < 600; ++f) {
      if (!stopped && scene.time() >= 6.0) {
        ASSERT_TRUE(c->addBehavior(emitter("stop", BehaviorKind::BreathingEmitter, BreathingParameters{.stop = true},
                                           scene.time())).added);
        stopped = true;
      }
      scene.update(dt);
      const float a = preciseAngleBetween(rest, modelRotation(*c, chest)) * kRadToDeg;
      ASSERT_TRUE(std::isfinite(a));
      step = std::max(step, std::fabs(a - previous));
      previous = last = a;
    }
    // 60 breaths a minute at 8 degrees, the fastest and largest: 8 * 1.5 / (0.42 s) a second,
    // plus the blend's own slope (1.5 / s) at full amplitude.
    EXPECT_LT(step, static_cast<float>((8.0 * 1.5 / 0.42 + 8.0 * 1.5) * dt) * 1.2f);
    EXPECT_LT(last, 1e-3f);  // stopped: back at rest
  }
}

TEST(IdleLife, BadBlinkParametersAreNamedAndNoMorphsNoBlink) {
  BlinkState st;
  std::string warning;
  ASSERT_EQ(bindBlink(emitter("b", BehaviorKind::BlinkEmitter,
                              BlinkParameters{.meanIntervalSeconds = std::nanf(""), .variation = -1.0f}),
                      *idleRig(), 1, st, warning), "");
  EXPECT_NE(warning.find("meanIntervalSeconds 'nan' is not finite; 3.5 s is used"), std::string::npos) << warning;
  EXPECT_NE(warning.find("variation -1 is outside [0, 1.5]; 0 is used"), std::string::npos) << warning;
  for (double t = 0.0; t < 30.0; t += 0.01) ASSERT_TRUE(std::isfinite(advanceBlink(st, t)));
  warning.clear();
  const std::string why = bindBlink(emitter("b", BehaviorKind::BlinkEmitter, BlinkParameters{}), *idleRig(false), 1, st, warning);
  EXPECT_NE(why.find("no blink morphs"), std::string::npos) << why;
  EXPECT_NE(why.find("CLOSE_EYES"), std::string::npos) << why;
  Scene scene;
  Character* c = scene.addCharacter("c", idleRig(false));
  const BehaviorResult r = c->addBehavior(emitter("blink", BehaviorKind::BlinkEmitter, BlinkParameters{}));
  EXPECT_TRUE(r.added);
  EXPECT_FALSE(r.realized);
  EXPECT_EQ(r.message, why);
}

TEST(IdleLife, TheProfileTurnsThemOnWhenTheCharacterJoinsTheScene) {
  std::shared_ptr<Rig> rig = idleRig();
  CharacterProfile p = rig->profile();
  p.idleLife.blink = p.idleLife.breathing = true;
  p.idleLife.blinkMeanInterval = 0.8f;
  p.idleLife.breathingAmplitude = 2.0f;
  rig->setProfile(p);
  Scene scene;
  scene.update(3.0);  // joins at 3 s: its emitters start then, blended in
  Character* c = scene.addCharacter("c", rig);
  ASSERT_TRUE(c->behaviors().find("idleLife:blink"));
  ASSERT_TRUE(c->behaviors().find("idleLife:breathing"));
  EXPECT_EQ(c->behaviors().find("idleLife:breathing")->request.start(), 3.0);
  const int chest = c->rig().joints().spine.back();
  scene.update(0.0);
  const glm::quat rest = modelRotation(*c, chest);
  float blink = 0.0f, chestPeak = 0.0f;
  for (int f = 0; f < 600; ++f) {
    scene.update(1.0 / 60.0);
    blink = std::max(blink, c->transformBuffer().morphWeights()[1]);
    chestPeak = std::max(chestPeak, preciseAngleBetween(rest, modelRotation(*c, chest)) * kRadToDeg);
  }
  EXPECT_GE(blink, 0.99f);
  EXPECT_NEAR(chestPeak, 2.0f, 0.05f);
  // A later request of its kind replaces the profile's (here: stops it).
  ASSERT_TRUE(c->addBehavior(emitter("stop", BehaviorKind::BlinkEmitter, BlinkParameters{.stop = true}, scene.time())).added);
  for (int f = 0; f < 60; ++f) scene.update(1.0 / 60.0);
  float after = 0.0f;
  for (int f = 0; f < 600; ++f) {
    scene.update(1.0 / 60.0);
    after = std::max(after, c->transformBuffer().morphWeights()[1]);
  }
  EXPECT_EQ(after, 0.0f);
}

TEST(IdleLife, StoppingInTheMiddleOfABlinkFadesTheLidsOpen) {
  Scene scene;
  Character* c = blinkingCharacter(scene, BlinkParameters{.meanIntervalSeconds = 0.5f, .variation = 0.0f});
  const double dt = 1.0 / 120.0;
  int f = 0;
  for (; f < 600 && c->transformBuffer().morphWeights()[1] < 0.99f; ++f) scene.update(dt);
  ASSERT_LT(f, 600);  // closed
  ASSERT_TRUE(c->addBehavior(emitter("stop", BehaviorKind::BlinkEmitter, BlinkParameters{.stop = true}, scene.time())).realized);
  float previous = c->transformBuffer().morphWeights()[1], step = 0.0f;
  for (int k = 0; k < 240; ++k) {
    scene.update(dt);
    const float w = c->transformBuffer().morphWeights()[1];
    step = std::max(step, std::fabs(w - previous));
    previous = w;
  }
  EXPECT_EQ(previous, 0.0f);
  // The fade's slope (1.5 / 0.26 s) and the opening's (1.5 / 0.16 s) at most: no snap.
  EXPECT_LT(step, static_cast<float>((1.5 / kBlinkSeconds + 1.5 / kBlinkOpenSeconds) * dt) * 1.1f);
}
