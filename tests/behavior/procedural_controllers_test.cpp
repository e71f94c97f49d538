// Head movements and face expressions: procedural controllers driven by the
// behavior timeline, with joints and morphs from the rig's profile.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include "marionette/animation/pose.hpp"
#include "marionette/behavior/procedural_controllers.hpp"
#include "determinism_digest.hpp"
#include "joint_rotation.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic.hpp"

using namespace marionette;
using marionette::test::modelRotation;
using marionette::test::preciseAngleBetween;
namespace {
// hips j0, spine j1, neck j2, head j3; morphs smile and blink. `rootTransform`
// turns the file's Z-up, centimetre space into the model frame, so the nod axis
// must be taken in the model frame, not the joints' own.
std::shared_ptr<Rig> headRig(bool zUpCentimetres) {
  auto asset = std::make_shared<Asset>();
  asset->skeleton = test::makeChain(4);
  if (zUpCentimetres)
    asset->skeleton.rootTransform = glm::scale(glm::mat4_cast(glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0))),
                                               glm::vec3(0.01f));
  asset->morphTargets = {"smile", "blink"};
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfile p;
  p.hips = "j0";
  p.spine = {"j1"};
  p.neck = "j2";
  p.head = "j3";
  p.face["SMILE"] = {{"smile", 1.0f}};
  p.face["AU45"] = {{"blink", 0.5f}};
  rig->setProfile(p);
  return rig;
}

BehaviorRequest headRequest(std::string id, HeadLexeme lexeme, double start,
                            float amount = HeadParameters::kDefaultAmount) {
  BehaviorRequest r;
  r.id = std::move(id);
  r.kind = BehaviorKind::Head;
  r.parameters = HeadParameters{lexeme, amount};
  // BML's default single nod over 1 s: ready .1, strokeStart .2, stroke .3, strokeEnd .5, relax .8.
  for (auto [name, at] : std::initializer_list<std::pair<const char*, double>>{
           {"start", 0}, {"ready", .1}, {"strokeStart", .2}, {"stroke", .3}, {"strokeEnd", .5}, {"relax", .8}, {"end", 1}})
    r.syncs.push_back({name, start + at});
  return r;
}

void stepTo(Scene& scene, double t) { scene.update(t - scene.time()); }
}  // namespace

TEST(HeadMotion, ShapesPeakAtTheStrokeAndVanishOutside) {
  const HeadStroke s{1.0, 1.1, 1.3};
  const HeadStroke one[] = {s};
  EXPECT_EQ(headShape(HeadLexeme::Nod, one, 0.99), 0.0f);
  EXPECT_EQ(headShape(HeadLexeme::Nod, one, 1.1), 1.0f);
  EXPECT_NEAR(headShape(HeadLexeme::Nod, one, 1.05), 0.5f, 1e-6);
  EXPECT_NEAR(headShape(HeadLexeme::Nod, one, 1.2), 0.5f, 1e-6);
  EXPECT_EQ(headShape(HeadLexeme::Nod, one, 1.3), 0.0f);
  float lo = 0.0f, hi = 0.0f;
  for (double t = 1.0; t <= 1.3; t += 0.001) {
    const float v = headShape(HeadLexeme::Shake, one, t);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_NEAR(hi, 1.0f, 1e-3);   // one way ...
  EXPECT_NEAR(lo, -1.0f, 1e-3);  // ... then the other
}

// At the stroke the head has turned by the peak angle about the model frame's
// +X (a nod), whatever the file's axes and units; the neck took 40 %.
TEST(HeadMotion, NodTurnsTheHeadAboutTheModelFrameLateralAxis) {
  for (bool zUp : {false, true}) {
    SCOPED_TRACE(zUp ? "Z-up centimetre file" : "Y-up metre file");
    Scene scene;
    Character* c = scene.addCharacter("c", headRig(zUp));
    scene.update(0.0);
    const glm::quat restHead = modelRotation(*c, 3), restNeck = modelRotation(*c, 2);
    const glm::mat4 restMatrix = c->transformBuffer().modelMatrices()[3];
    BehaviorResult r = c->addBehavior(headRequest("nod", HeadLexeme::Nod, 0.0, 1.0f));
    ASSERT_TRUE(r.realized) << r.message;
    EXPECT_EQ(r.message, "");
    stepTo(scene, 0.3);  // the stroke
    const glm::quat headDelta = modelRotation(*c, 3) * glm::inverse(restHead);
    const glm::quat neckDelta = modelRotation(*c, 2) * glm::inverse(restNeck);
    EXPECT_LT(preciseAngleBetween(headDelta, glm::angleAxis(headPeakAngle(HeadLexeme::Nod), glm::vec3(1, 0, 0))), 1e-3f);
    EXPECT_LT(preciseAngleBetween(neckDelta, glm::angleAxis(0.4f * headPeakAngle(HeadLexeme::Nod), glm::vec3(1, 0, 0))), 1e-3f);
    stepTo(scene, 0.6);  // after strokeEnd: back to rest, exactly
    EXPECT_EQ(c->transformBuffer().modelMatrices()[3], restMatrix);
  }
}

TEST(HeadMotion, RepetitionsAmountAndCancellation) {
  Scene scene;
  Character* c = scene.addCharacter("c", headRig(false));
  scene.update(0.0);
  const glm::quat rest = modelRotation(*c, 3);
  BehaviorRequest shake = headRequest("shake", HeadLexeme::Shake, 0.0, -0.5f);
  shake.syncs = {{"start", 0.0}, {"ready", 0.1}, {"strokeStart", 0.2}, {"stroke", 0.3}, {"strokeEnd", 0.6},
                 {"strokeStart:2", 0.7}, {"stroke:2", 0.8}, {"strokeEnd:2", 1.1}, {"relax", 1.2}, {"end", 1.3}};
  ASSERT_TRUE(c->addBehavior(shake).realized);
  const auto* e = c->behaviors().find("shake");
  ASSERT_NE(e->as<HeadMotionState>(), nullptr);
  ASSERT_EQ(e->as<HeadMotionState>()->strokes.size(), 2u);
  float peak1 = 0.0f, peak2 = 0.0f, between = 0.0f;
  for (int f = 1; f <= 130; ++f) {
    stepTo(scene, f * 0.01);
    const float a = preciseAngleBetween(modelRotation(*c, 3), rest);
    if (scene.time() < 0.6) peak1 = std::max(peak1, a);
    else if (scene.time() > 0.62 && scene.time() < 0.68) between = std::max(between, a);
    else if (scene.time() > 0.7) peak2 = std::max(peak2, a);
  }
  EXPECT_NEAR(peak1, 0.5f * headPeakAngle(HeadLexeme::Shake), 0.01f);  // |amount| 0.5
  EXPECT_NEAR(peak2, peak1, 0.01f);
  EXPECT_LT(between, 1e-4f);
  // Cancelled at the stroke: back to rest within the blend-out, without a jump.
  Scene s2;
  Character* d = s2.addCharacter("d", headRig(false));
  s2.update(0.0);
  const glm::mat4 restMatrix = d->transformBuffer().modelMatrices()[3];
  d->addBehavior(headRequest("nod", HeadLexeme::Nod, 0.0, 1.0f));
  stepTo(s2, 0.3);
  ASSERT_TRUE(d->cancelBehavior("nod", 0.2));
  glm::quat prev = modelRotation(*d, 3);
  float maxStep = 0.0f;
  for (int f = 1; f <= 25; ++f) {
    stepTo(s2, 0.3 + f * 0.01);
    maxStep = std::max(maxStep, preciseAngleBetween(prev, modelRotation(*d, 3)));
    prev = modelRotation(*d, 3);
  }
  EXPECT_LT(maxStep, 0.05f);
  EXPECT_EQ(d->transformBuffer().modelMatrices()[3], restMatrix);
}

TEST(HeadMotion, WhatCannotBeDoneIsSaidNotDropped) {
  Scene scene;
  Character* c = scene.addCharacter("c", headRig(false));
  // BML's lexeme and amount text are read by the realizer (tests/bml/behavior_parameters_test.cpp).
  BehaviorRequest odd = headRequest("a", HeadLexeme::Nod, 0.0);
  odd.parameters = FaceParameters{"SMILE"};  // parameters of another kind
  BehaviorResult wrong = c->addBehavior(odd);
  EXPECT_TRUE(wrong.added);
  EXPECT_FALSE(wrong.realized);
  EXPECT_NE(wrong.message.find("a head behavior needs HeadParameters"), std::string::npos) << wrong.message;
  BehaviorResult bad = c->addBehavior(headRequest("b", HeadLexeme::Nod, 0.0, std::nanf("")));
  EXPECT_TRUE(bad.realized);
  EXPECT_NE(bad.message.find("amount 'nan' is not a number in [-1, 1]; 0.5 is used"), std::string::npos) << bad.message;
  EXPECT_NE(c->addBehavior(headRequest("c", HeadLexeme::Nod, 0.0, 2.0f)).message.find("amount '2' is not a number in [-1, 1]"),
            std::string::npos);
  auto headless = std::make_shared<Rig>(Asset{});
  Character* h = scene.addCharacter("h", headless);
  BehaviorResult none = h->addBehavior(headRequest("n", HeadLexeme::Nod, 0.0));
  EXPECT_FALSE(none.realized);
  EXPECT_NE(none.message.find("no head or neck joint"), std::string::npos);
}

TEST(FaceExpressions, LexemesAndUnitsDriveMorphsThroughTheProfile) {
  Scene scene;
  Character* c = scene.addCharacter("c", headRig(false));
  BehaviorRequest smile;
  smile.id = "smile";
  smile.kind = BehaviorKind::FaceLexeme;
  smile.parameters = FaceParameters{"smile", 0.8f};
  smile.syncs = {{"start", 0.0}, {"attackPeak", 0.2}, {"relax", 1.0}, {"end", 1.5}};
  ASSERT_TRUE(c->addBehavior(smile).realized);
  BehaviorRequest blink = smile;
  blink.id = "blink";
  blink.kind = BehaviorKind::FaceFacs;
  blink.parameters = FaceParameters{"AU45"};
  ASSERT_TRUE(c->addBehavior(blink).realized);
  stepTo(scene, 0.1);
  EXPECT_NEAR(c->transformBuffer().morphWeights()[0], 0.4f, 1e-5);  // attack: half way (smoothstep), x 0.8
  stepTo(scene, 0.5);
  EXPECT_NEAR(c->transformBuffer().morphWeights()[0], 0.8f, 1e-6);
  EXPECT_NEAR(c->transformBuffer().morphWeights()[1], 0.5f, 1e-6);  // AU45 maps to blink at 0.5
  // A second smile adds up, clamped at 1.
  smile.id = "smile2";
  smile.syncs = {{"start", 0.5}, {"attackPeak", 0.6}, {"relax", 0.9}, {"end", 1.0}};
  c->addBehavior(smile);
  stepTo(scene, 0.7);
  EXPECT_EQ(c->transformBuffer().morphWeights()[0], 1.0f);
  stepTo(scene, 2.0);  // all ended: weights back to 0 (recomputed every frame)
  EXPECT_EQ(c->transformBuffer().morphWeights()[0], 0.0f);
  EXPECT_EQ(c->transformBuffer().morphWeights()[1], 0.0f);
  BehaviorRequest frown = smile;
  frown.id = "frown";
  frown.parameters = FaceParameters{"LOWER_BROWS"};
  BehaviorResult r = c->addBehavior(frown);
  EXPECT_FALSE(r.realized);
  EXPECT_NE(r.message.find("no morphs for face expression 'LOWER_BROWS' (its profile maps AU45, SMILE)"), std::string::npos)
      << r.message;
}

// dt from 0 to 1 s over nods, shakes and smiles: finite, and identical across runs.
TEST(HeadMotion, ExtremeStepsStayFiniteAndDeterministic) {
  auto run = [] {
    Scene scene;
    Character* c = scene.addCharacter("c", headRig(true));
    c->addBehavior(headRequest("n", HeadLexeme::Nod, 0.0));
    c->addBehavior(headRequest("s", HeadLexeme::Shake, 0.25, 1.0f));
    c->addBehavior(headRequest("t", HeadLexeme::Tilt, 0.5, -1.0f));
    std::vector<float> out;
    for (double dt : {0.0, 1.0 / 240, 0.3, 0.0, 0.05, 1.0, 0.001}) {
      scene.update(dt);
      for (const Transform& t : c->localPose()) {
        EXPECT_TRUE(test::finite(t));
        out.push_back(t.rotation.x);
      }
    }
    return out;
  };
  const std::vector<float> first = run();
  EXPECT_EQ(first, run());
  marionette::test::recordDigest(first);  // and across two processes: determinism.two_processes
}

namespace {
// A head request of `repeats` strokes evenly over the middle of [0, duration] (BML's proportions).
BehaviorRequest repeatedHead(HeadParameters p, int repeats, double duration) {
  BehaviorRequest r;
  r.id = "h";
  r.kind = BehaviorKind::Head;
  r.parameters = p;
  r.syncs = {{"start", 0.0}, {"ready", 0.1 * duration}};  // in time order
  const double from = 0.2 * duration, each = 0.6 * duration / repeats;
  for (int k = 0; k < repeats; ++k) {
    const std::string suffix = k == 0 ? "" : ":" + std::to_string(k + 1);
    r.syncs.push_back({"strokeStart" + suffix, from + k * each});
    r.syncs.push_back({"stroke" + suffix, from + (k + 0.3) * each});
    r.syncs.push_back({"strokeEnd" + suffix, from + (k + 1) * each});
  }
  r.syncs.push_back({"relax", 0.9 * duration});
  r.syncs.push_back({"end", duration});
  return r;
}

// The largest head rotation from one frame to the next over the request, and what was said.
float worstHeadStep(const BehaviorRequest& request, double dt, std::string& said) {
  Scene scene;
  Character* c = scene.addCharacter("c", headRig(false));
  scene.update(0.0);
  const BehaviorResult added = c->addBehavior(request);
  said = added.message;
  glm::quat before = modelRotation(*c, 3);
  float worst = 0.0f;
  const int frames = static_cast<int>(std::ceil((request.end() + 0.05) / dt));
  for (int f = 1; f <= frames; ++f) {
    scene.update(dt);
    const glm::quat now = modelRotation(*c, 3);
    if (!std::isfinite(now.w)) return 1e9f;
    worst = std::max(worst, preciseAngleBetween(before, now));
    before = now;
  }
  return worst;
}
}  // namespace

// Each lexeme of the catalogue turns the head the way head_motion.hpp says, the held directions
// included (Greta's DOWN_ASIDE_RIGHT: down and to the character's right, held from ready to relax).
TEST(HeadMotion, TheCatalogueTurnsTheHeadAsItSays) {
  const struct {
    HeadParameters p;
    double at;             // a time at the move's peak
    glm::vec3 degrees;     // the head's turn there (amount 1)
  } peaks[] = {{{HeadLexeme::Toss, 1.0f}, 0.3, {0, 0, 15}},
               {{HeadLexeme::Orient, 1.0f, {40, -50, 0}}, 0.5, {40, -50, 0}},
               {{HeadLexeme::Orient, 0.5f, {-30, 0, 30}}, 0.5, {-15, 0, 15}}};
  for (const auto& k : peaks) {
    SCOPED_TRACE(static_cast<int>(k.p.lexeme));
    Scene scene;
    Character* c = scene.addCharacter("c", headRig(false));
    scene.update(0.0);
    const glm::quat rest = modelRotation(*c, 3);
    BehaviorRequest r = headRequest("h", k.p.lexeme, 0.0, k.p.amount);
    r.parameters = k.p;
    if (k.p.lexeme == HeadLexeme::Orient)  // a held turn of up to 64 degrees: time to get there and back
      r.syncs = {{"start", 0}, {"ready", .3}, {"strokeStart", .35}, {"stroke", .4}, {"strokeEnd", .5}, {"relax", .6}, {"end", 1}};
    const BehaviorResult added = c->addBehavior(r);
    ASSERT_TRUE(added.realized) << added.message;
    EXPECT_EQ(added.message, "");
    stepTo(scene, k.at);
    const glm::quat delta = modelRotation(*c, 3) * glm::inverse(rest);
    EXPECT_LT(preciseAngleBetween(delta, headRotation(glm::radians(k.degrees))), glm::radians(1.0f));
    stepTo(scene, 1.05);
    EXPECT_LT(preciseAngleBetween(modelRotation(*c, 3), rest), 1e-5f);  // back at rest after the end
  }
  // WIGGLE and WAGGLE: small quick moves, two each way per stroke.
  for (const auto& [lexeme, axis, degrees] :
       {std::tuple{HeadLexeme::Wiggle, glm::vec3(1, 0, 0), 8.0f}, std::tuple{HeadLexeme::Waggle, glm::vec3(0, 0, 1), 10.0f}}) {
    Scene scene;
    Character* c = scene.addCharacter("c", headRig(false));
    scene.update(0.0);
    const glm::quat rest = modelRotation(*c, 3);
    const BehaviorResult added = c->addBehavior(repeatedHead(HeadParameters{lexeme, 1.0f}, 1, 1.5));  // a 0.9 s stroke
    ASSERT_TRUE(added.realized);
    EXPECT_EQ(added.message, "");
    float largest = 0.0f, previous = 0.0f;
    int turns = 0;
    for (int f = 1; f <= 150; ++f) {
      stepTo(scene, f * 0.01);
      const glm::quat d = modelRotation(*c, 3) * glm::inverse(rest);
      const float signedAngle = 2.0f * glm::dot(glm::vec3(d.x, d.y, d.z), axis) * (d.w < 0 ? -1.0f : 1.0f);
      largest = std::max(largest, std::abs(signedAngle));
      if (std::abs(signedAngle) > 0.02f && std::abs(previous) > 0.02f && signedAngle * previous < 0.0f) ++turns;
      if (std::abs(signedAngle) > 0.02f) previous = signedAngle;
    }
    EXPECT_NEAR(largest, glm::radians(degrees), glm::radians(0.5f));
    EXPECT_EQ(turns, 3);  // + - + -: three changes of side
  }
}

// Timing no body can follow (issue 45, 10): a stroke shorter than a head can make is thinned, a
// rise too quick for its angle slowed, an oscillation too fast made smaller, each said; swept over
// repetitions, durations and frame steps, no frame turns the head faster than it can turn.
TEST(HeadMotion, TimingNoBodyCanFollowIsFittedAndSaid) {
  float worstRate = 0.0f;
  for (HeadLexeme lexeme : {HeadLexeme::Nod, HeadLexeme::Shake, HeadLexeme::Wiggle})
    for (int repeats : {1, 3, 10, 100, 1000})
      for (double duration : {0.01, 0.1, 0.5, 2.0, 10.0})
        for (double dt : {1.0 / 1000.0, 1.0 / 60.0}) {
          SCOPED_TRACE(testing::Message() << static_cast<int>(lexeme) << " x" << repeats << " over " << duration << " s, dt "
                                          << dt);
          std::string said;
          const float step = worstHeadStep(repeatedHead(HeadParameters{lexeme, 1.0f}, repeats, duration), dt, said);
          const float rate = glm::degrees(step) / static_cast<float>(dt);
          worstRate = std::max(worstRate, rate);
          // The envelope's blend in and out adds to the shape's speed: within a quarter over the limit.
          EXPECT_LE(rate, 1.25 * kMaxHeadDegreesPerSecond);
          const double each = 0.6 * duration / repeats;
          if (repeats > 1 && each < kMinHeadStrokeSeconds) {
            EXPECT_NE(said.find("thinned"), std::string::npos) << said;
          }
          if (lexeme == HeadLexeme::Nod && duration >= 2.0 && each >= 0.3) {  // a full nod in 0.3 s: within reach
            EXPECT_EQ(said, "");
          }
        }
  std::printf("the fastest head turn over the sweep: %.0f degrees/s (limit %.0f)\n", worstRate, kMaxHeadDegreesPerSecond);
  // The case: 1000 nods in 10 ms at 1000 fps (a one-frame pop of 2.4 degrees before).
  std::string said;
  const float pop = worstHeadStep(repeatedHead(HeadParameters{HeadLexeme::Nod, 0.5f}, 1000, 0.01), 0.001, said);
  EXPECT_LT(glm::degrees(pop), 0.5f);
  EXPECT_NE(said.find("1000 repetitions in 0.006 s"), std::string::npos) << said;
}
