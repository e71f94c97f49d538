// The behavior timeline (the C++ API for timed requests, no BML) and the clip
// controller that realizes requests naming a clip.
#include <gtest/gtest.h>

#include <cmath>

#include "determinism_digest.hpp"
#include "marionette/behavior/behavior_timeline.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using marionette::test::angleBetween;

namespace {
BehaviorRequest request(std::string id, std::vector<BehaviorSync> syncs, BehaviorKind kind = BehaviorKind::Gesture) {
  BehaviorRequest r;
  r.id = std::move(id);
  r.kind = kind;
  r.syncs = std::move(syncs);
  return r;
}

BehaviorRequest gesture(std::string id, double start, double end, std::string clip = {}) {
  BehaviorRequest r = request(std::move(id), {{"start", start}, {"ready", start + 0.2}, {"relax", end - 0.2}, {"end", end}});
  r.clip = std::move(clip);
  return r;
}
}  // namespace

TEST(BehaviorTimeline, CheckNamesTheRequestAndTheProblem) {
  BehaviorTimeline tl;
  EXPECT_NE(tl.check(request("", {{"start", 0}, {"end", 1}})).find("needs an id"), std::string::npos);
  EXPECT_NE(tl.check(request("a", {})).find("'a' has no sync points"), std::string::npos);
  const std::string nan = tl.check(request("a", {{"start", 0}, {"end", std::nan("")}}));
  EXPECT_NE(nan.find("'end' has a time that is not finite"), std::string::npos) << nan;
  const std::string order = tl.check(request("a", {{"start", 2}, {"end", 0}}));
  EXPECT_NE(order.find("'end' (0 s) comes before 'start' (2 s)"), std::string::npos) << order;
  BehaviorRequest heavy = request("a", {{"start", 0}, {"end", 1}});
  heavy.weight = 1.5f;
  EXPECT_NE(tl.check(heavy).find("weight"), std::string::npos);
  heavy.weight = std::nanf("");
  EXPECT_NE(tl.check(heavy).find("weight"), std::string::npos);
  tl.add(request("a", {{"start", 0}, {"end", 1}}));
  EXPECT_NE(tl.check(request("a", {{"start", 0}, {"end", 1}})).find("still on the character's timeline"), std::string::npos);
  EXPECT_EQ(tl.check(request("b", {{"start", 0}, {"end", 1}})), "");
}

TEST(BehaviorTimeline, EnvelopeRisesToReadyHoldsAndFallsFromRelax) {
  BehaviorTimeline tl;
  const auto& e = tl.add(gesture("g", 1.0, 3.0));
  EXPECT_EQ(BehaviorTimeline::weightAt(e, 0.99), 0.0f);
  EXPECT_EQ(BehaviorTimeline::weightAt(e, 1.0), 0.0f);
  EXPECT_NEAR(BehaviorTimeline::weightAt(e, 1.1), 0.5f, 1e-6);  // smoothstep midpoint
  EXPECT_NEAR(BehaviorTimeline::weightAt(e, 1.05), 0.15625f, 1e-6);  // 3u^2 - 2u^3 at u = 1/4
  EXPECT_EQ(BehaviorTimeline::weightAt(e, 2.0), 1.0f);
  EXPECT_NEAR(BehaviorTimeline::weightAt(e, 2.9), 0.5f, 1e-6);
  EXPECT_EQ(BehaviorTimeline::weightAt(e, 3.0), 0.0f);
  // Without ready/relax: a default blend of min(0.3 s, a quarter of the duration).
  const auto& d = tl.add(request("d", {{"start", 0}, {"end", 0.4}}));
  EXPECT_NEAR(BehaviorTimeline::weightAt(d, 0.05), 0.5f, 1e-6);
  EXPECT_EQ(BehaviorTimeline::weightAt(d, 0.2), 1.0f);
  // A zero-length request never weighs anything; a persistent one holds after its end.
  const auto& z = tl.add(request("z", {{"start", 5}, {"end", 5}}));
  EXPECT_EQ(BehaviorTimeline::weightAt(z, 5.0), 0.0f);
  BehaviorRequest p = request("p", {{"start", 0}, {"end", 1}}, BehaviorKind::PostureShift);
  p.persistent = true;
  p.weight = 0.5f;
  const auto& pe = tl.add(p);
  EXPECT_EQ(BehaviorTimeline::weightAt(pe, 100.0), 0.5f);
}

TEST(BehaviorTimeline, CancelBlendsOutFromTheCurrentWeight) {
  BehaviorTimeline tl;
  tl.add(gesture("b1:g", 0.0, 10.0));
  tl.add(gesture("b1:h", 20.0, 30.0));
  tl.add(gesture("b2:g", 0.0, 10.0));
  EXPECT_EQ(tl.cancelPrefix("b1:", 5.0, 0.5), 2u);
  EXPECT_EQ(tl.find("b1:h"), nullptr);  // had not started: removed at once
  const auto* e = tl.find("b1:g");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(BehaviorTimeline::weightAt(*e, 5.0), 1.0f);
  EXPECT_NEAR(BehaviorTimeline::weightAt(*e, 5.25), 0.5f, 1e-6);
  EXPECT_EQ(BehaviorTimeline::weightAt(*e, 5.5), 0.0f);
  EXPECT_DOUBLE_EQ(e->finishTime(), 5.5);
  // Blend-out is monotone: no bump back up.
  float last = 1.0f;
  for (double t = 5.0; t <= 5.6; t += 0.01) {
    const float w = BehaviorTimeline::weightAt(*e, t);
    EXPECT_LE(w, last + 1e-7f);
    last = w;
  }
  EXPECT_FALSE(tl.cancel("nope", 1.0, 0.1));
  tl.prune(5.5);
  EXPECT_EQ(tl.find("b1:g"), nullptr);
  EXPECT_NE(tl.find("b2:g"), nullptr);
}

TEST(BehaviorTimeline, LaterRequestOwnsOverlappingChannelsEarlierResurfaces) {
  BehaviorTimeline tl;
  BehaviorRequest left = gesture("left", 0.0, 4.0);
  left.channels = BodyChannel::LeftHand;
  tl.add(left);
  tl.add(gesture("both", 1.0, 2.0));  // default: both hands
  BehaviorRequest head = request("nod", {{"start", 0}, {"end", 4}}, BehaviorKind::Head);
  tl.add(head);
  EXPECT_EQ(tl.owner(BodyChannel::LeftHand, 0.5)->id, "left");
  EXPECT_EQ(tl.owner(BodyChannel::LeftHand, 1.5)->id, "both");
  EXPECT_EQ(tl.owner(BodyChannel::RightHand, 1.5)->id, "both");
  EXPECT_EQ(tl.owner(BodyChannel::LeftHand, 2.5)->id, "left");
  EXPECT_EQ(tl.owner(BodyChannel::RightHand, 2.5), nullptr);
  EXPECT_EQ(tl.owner(BodyChannel::Head, 2.5)->id, "nod");
  EXPECT_EQ(channelNames(BodyChannel::Hands | BodyChannel::Head), "hands+head");
  EXPECT_EQ(channelNames(BodyChannel::RightHand), "rightHand");
  EXPECT_EQ(behaviorKindFromName("headDirectionShift"), BehaviorKind::HeadDirectionShift);
  EXPECT_EQ(toString(BehaviorKind::FaceLexeme), "faceLexeme");
  EXPECT_FALSE(behaviorKindFromName("dance"));
}

TEST(BehaviorTimeline, PruneDropsFinishedAndCoveredPersistentRequests) {
  BehaviorTimeline tl;
  BehaviorRequest first = request("first", {{"start", 0}, {"end", 1}}, BehaviorKind::PostureShift);
  first.persistent = true;
  tl.add(first);
  tl.add(request("temp", {{"start", 2}, {"end", 3}}, BehaviorKind::Posture));
  tl.prune(2.5);
  EXPECT_NE(tl.find("first"), nullptr);  // a temporary posture does not replace a shifted one
  tl.prune(3.0);
  EXPECT_EQ(tl.find("temp"), nullptr);
  BehaviorRequest second = first;
  second.id = "second";
  second.syncs = {{"start", 4}, {"end", 5}};
  tl.add(second);
  tl.prune(4.1);  // still blending in (until 4.25): the first shows through
  EXPECT_NE(tl.find("first"), nullptr);
  tl.prune(4.25);
  EXPECT_EQ(tl.find("first"), nullptr);
  EXPECT_NE(tl.find("second"), nullptr);
}

// The clip controller: a request naming a clip moves the joints the clip
// animates, leaves the others to the layers below, and a cancellation (BML
// REPLACE, interrupt) blends back smoothly.
TEST(BehaviorTimeline, ClipRequestBlendsOverLayersAndCancelReturnsSmoothly) {
  auto rig = marionette::test::makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  ASSERT_TRUE(c->play(0, "walk"));
  Scene reference;  // the same character without the behavior
  Character* r = reference.addCharacter("c", rig);
  r->play(0, "walk");
  const double dt = 1.0 / 60.0;
  scene.update(dt);
  reference.update(dt);
  const double t0 = scene.time();
  BehaviorResult res = c->addBehavior(gesture("wave1", t0, t0 + 3.0, "wave"));
  ASSERT_TRUE(res.added) << res.message;
  EXPECT_TRUE(res.realized);
  EXPECT_EQ(res.message, "");
  float maxStep = 0.0f, maxWaveOffset = 0.0f;
  glm::quat previous = c->localPose()[3].rotation;
  for (int f = 0; f < 90; ++f) {  // 1.5 s: blend in, then full weight
    scene.update(dt);
    reference.update(dt);
    // Joints the wave does not animate follow the walk exactly.
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(c->localPose()[j].rotation, r->localPose()[j].rotation) << "joint " << j << " frame " << f;
      EXPECT_EQ(c->localPose()[j].translation, r->localPose()[j].translation);
    }
    maxStep = std::max(maxStep, angleBetween(previous, c->localPose()[3].rotation));
    maxWaveOffset = std::max(maxWaveOffset, angleBetween(r->localPose()[3].rotation, c->localPose()[3].rotation));
    previous = c->localPose()[3].rotation;
  }
  EXPECT_GT(maxWaveOffset, 0.5f);  // the wave moved the top joint
  ASSERT_TRUE(c->cancelBehavior("wave1", 0.4));
  for (int f = 0; f < 30; ++f) {  // 0.5 s: blends back within 0.4 s
    scene.update(dt);
    reference.update(dt);
    maxStep = std::max(maxStep, angleBetween(previous, c->localPose()[3].rotation));
    previous = c->localPose()[3].rotation;
  }
  // Back on the layers below exactly, and never a jump: the wave clip moves at most
  // 1.2 rad per 0.25 s (0.08 rad per frame); the blends add little to that.
  EXPECT_EQ(c->localPose()[3].rotation, r->localPose()[3].rotation);
  EXPECT_LT(maxStep, 0.12f);
  EXPECT_TRUE(c->behaviors().empty());
}

TEST(BehaviorTimeline, CharacterRejectsUnknownClipsAndReportsUnrealizedKinds) {
  auto rig = marionette::test::makeSyntheticRig();
  Scene scene;
  struct Log : SceneListener {
    std::string last;
    void onLog(LogLevel, std::string_view m) override { last = m; }
  } log;
  scene.addListener(&log);
  Character* c = scene.addCharacter("c", rig);
  BehaviorResult missing = c->addBehavior(gesture("g", 0, 1, "dance"));
  EXPECT_FALSE(missing.added);
  EXPECT_NE(missing.message.find("no clip named 'dance' (it has 'walk', 'wave')"), std::string::npos) << missing.message;
  EXPECT_EQ(log.last, missing.message);
  scene.speech().useDefaultSynthesizer(false);  // no backend: as a build without TTS
  BehaviorRequest words = request("speak", {{"start", 0}, {"end", 1}}, BehaviorKind::Speech);
  words.parameters = SpeechParameters{.text = "Hello there."};
  BehaviorResult speak = c->addBehavior(words);
  EXPECT_TRUE(speak.added);
  EXPECT_FALSE(speak.realized);
  EXPECT_NE(speak.message.find("speech cannot be said: no speech backend"), std::string::npos) << speak.message;
  // Nothing to say is said as much, before any backend is asked.
  BehaviorResult empty = c->addBehavior(request("silent", {{"start", 0}, {"end", 1}}, BehaviorKind::Speech));
  EXPECT_FALSE(empty.realized);
  EXPECT_NE(empty.message.find("speech cannot be said: the text is empty"), std::string::npos) << empty.message;
  // A locomotion without a target is not added at all, and says what is missing.
  BehaviorResult walk = c->addBehavior(request("walk", {{"start", 0}, {"end", 1}}, BehaviorKind::Locomotion));
  EXPECT_FALSE(walk.added);
  EXPECT_NE(walk.message.find("needs a target"), std::string::npos) << walk.message;
  BehaviorRequest clipless = request("k", {{"start", 0}, {"end", 1}}, BehaviorKind::Clip);
  EXPECT_FALSE(c->addBehavior(clipless).added);
  EXPECT_TRUE(c->addBehavior(request("w", {{"start", 0}, {"end", 1}}, BehaviorKind::Wait)).realized);
}

// Stiff and extreme steps: dt of 0 and of 1 s, a request far in the future and
// one at t = 1e7 s, all finite and bit-identical across two runs.
TEST(BehaviorTimeline, ExtremeStepsAndTimesStayFiniteAndDeterministic) {
  auto run = [] {
    auto rig = marionette::test::makeSyntheticRig();
    Scene scene;
    Character* c = scene.addCharacter("c", rig);
    BehaviorRequest loop = gesture("loop", 0.0, 2e7, "walk");
    loop.loop = true;
    c->addBehavior(loop);
    c->addBehavior(gesture("w", 0.5, 1.5, "wave"));
    std::vector<float> out;
    for (double dt : {0.0, 1.0, 0.0, 1.0 / 60.0, 1.0, 1e7, 0.5}) {
      scene.update(dt);
      for (const Transform& t : c->localPose()) {
        EXPECT_TRUE(marionette::test::finite(t));
        out.push_back(t.rotation.x);
        out.push_back(t.translation.z);
      }
    }
    return out;
  };
  const std::vector<float> first = run();
  EXPECT_EQ(first, run());
  marionette::test::recordDigest(first);  // and across two processes: determinism.two_processes
}
