// Head movements and face expressions: procedural controllers driven by the
// behavior timeline, with joints and morphs from the rig's profile.
#include <gtest/gtest.h>

#include <cmath>

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
