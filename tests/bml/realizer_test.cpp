#include <gtest/gtest.h>

#include "marionette/bml/realizer.hpp"
#include "marionette/bml/timed_files.hpp"
#include "synthetic.hpp"
#include "synthetic_rig.hpp"
#include "synthetic_upper_body.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace marionette {
// A failed expectation prints a channel set as its bits (found by ADL).
inline void PrintTo(BodyChannel channels, std::ostream* os) { *os << static_cast<std::uint32_t>(channels); }
}  // namespace marionette

namespace {
struct Recorder {
  std::vector<Feedback> all;
  std::vector<const Feedback*> of(Feedback::Kind kind) const {
    std::vector<const Feedback*> out;
    for (const Feedback& f : all)
      if (f.kind == kind) out.push_back(&f);
    return out;
  }
  std::vector<const Feedback*> warnings(WarningType type) const {
    std::vector<const Feedback*> out;
    for (const Feedback* f : of(Feedback::Kind::Warning))
      if (f->warning.type == type) out.push_back(f);
    return out;
  }
  // Channel conflicts (IMPOSSIBLE_TO_SCHEDULE warnings).
  std::vector<const Feedback*> conflicts() const { return warnings(WarningType::ImpossibleToSchedule); }
};

struct ProgressListener : SceneListener {
  std::vector<std::string> events;
  void onBehaviorProgress(const Character&, std::string_view block, std::string_view sync, double) override {
    events.push_back(std::string(block) + ":" + std::string(sync));
  }
};

// A scene with one character, a realizer, and a recorder of its feedback.
struct RealizerWithRobot : ::testing::Test {
  Scene scene;
  Realizer r{scene};
  Recorder rec;
  RealizerWithRobot() {
    r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
    scene.addCharacter("robot", test::makeSyntheticRig());
    r.addFeedbackListener([this](const Feedback& f) { rec.all.push_back(f); });
  }
};

void step(Scene& scene, Realizer& r, double seconds, double dt = 0.05) {
  for (double t = 0; t < seconds - 1e-9; t += dt) {
    scene.update(dt);
    r.update();
  }
}
}  // namespace

TEST(Realizer, UnknownCharacterAndBrokenBlocksFailWithWarningFeedback) {
  Scene scene;
  Realizer r(scene);
  Recorder rec;
  r.addFeedbackListener([&](const Feedback& f) { rec.all.push_back(f); });
  Schedule s = r.perform("<bml id='b'><head id='h' lexeme='NOD'/></bml>", "nobody");
  EXPECT_TRUE(s.failed);
  ASSERT_EQ(rec.of(Feedback::Kind::Warning).size(), 1u);
  EXPECT_NE(rec.all[0].xml().find("type=\"NO_SUCH_TARGET\""), std::string::npos);
  EXPECT_EQ(r.activeBlocks(), 0u);
  scene.addCharacter("robot", test::makeSyntheticRig());
  EXPECT_TRUE(r.perform("<bml id='b'><head id='h'</bml>").failed);
  EXPECT_EQ(r.activeBlocks(), 0u);
}

TEST_F(RealizerWithRobot, PredictionsThenProgressInOrderThenBlockEnd) {
  ProgressListener progress;
  scene.addListener(&progress);
  Schedule s = r.perform("<bml id='b1'><head id='h' lexeme='NOD' start='0.5'/><gaze id='g' target='x' start='h:end'/></bml>");
  ASSERT_FALSE(s.failed);
  EXPECT_EQ(rec.of(Feedback::Kind::Prediction).size(), 7u + 4u);  // head: 7 sync points, gaze: 4
  step(scene, r, 5.0);
  const auto syncs = rec.of(Feedback::Kind::SyncPointProgress);
  ASSERT_EQ(syncs.size(), 11u);
  for (std::size_t i = 1; i < syncs.size(); ++i) EXPECT_LE(syncs[i - 1]->sceneTime, syncs[i]->sceneTime);
  EXPECT_EQ(syncs.front()->behaviorId, "h");
  EXPECT_DOUBLE_EQ(syncs.front()->blockTime, 0.5);
  const auto blocks = rec.of(Feedback::Kind::BlockProgress);
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[0]->syncPoint, "start");
  EXPECT_EQ(blocks[1]->syncPoint, "end");
  EXPECT_NEAR(blocks[1]->sceneTime, 0.5 + 1.0 + 2.0, 1e-9);
  EXPECT_EQ(r.activeBlocks(), 0u);
  // The scene listener heard the same progress.
  EXPECT_EQ(progress.events.front(), "b1:start");
  EXPECT_EQ(progress.events.back(), "b1:end");
  EXPECT_EQ(progress.events.size(), 13u);
}

TEST_F(RealizerWithRobot, AppendWaitsReplaceEndsInterruptStops) {
  r.perform("<bml id='a'><gesture id='g' lexeme='BEAT'/></bml>");  // 0..2 s
  r.perform("<bml id='b' composition='APPEND'><head id='h' lexeme='NOD'/></bml>");
  EXPECT_DOUBLE_EQ(*r.blockStart("b"), 2.0);
  step(scene, r, 1.0);
  r.perform("<bml id='c' composition='REPLACE'><head id='h2' lexeme='NOD'/></bml>");
  EXPECT_FALSE(r.blockStart("a"));
  EXPECT_FALSE(r.blockStart("b"));
  EXPECT_NEAR(*r.blockStart("c"), 1.0, 1e-9);
  int ends = 0;
  for (const auto* f : rec.of(Feedback::Kind::BlockProgress)) ends += f->syncPoint == "end";
  EXPECT_EQ(ends, 2);  // a and b ended by REPLACE
  EXPECT_TRUE(r.interrupt("c"));
  EXPECT_FALSE(r.interrupt("c"));
  EXPECT_EQ(r.activeBlocks(), 0u);
}

TEST(Realizer, FeedbackXmlEscapesIds) {
  Feedback f;
  f.kind = Feedback::Kind::SyncPointProgress;
  f.blockId = "b\"<&>";
  f.behaviorId = "h'1";
  f.syncPoint = "stroke";
  f.blockTime = 0.3;
  const std::string x = f.xml();
  EXPECT_NE(x.find("id=\"b&quot;&lt;&amp;&gt;:h&apos;1:stroke\""), std::string::npos) << x;
  EXPECT_NE(x.find("time=\"0.3\""), std::string::npos);
  EXPECT_EQ(x.find("<&"), std::string::npos);
}

TEST_F(RealizerWithRobot, MergeConflictsOnABodyChannelLaterWinsWithAWarning) {
  r.perform("<bml id='a'><head id='nod' lexeme='NOD' start='0' end='2'/></bml>");
  EXPECT_TRUE(rec.conflicts().empty());
  r.perform("<bml id='b'><head id='shake' lexeme='SHAKE' start='1' end='3'/>"
            "<faceLexeme id='smile' lexeme='SMILE' start='1'/></bml>");
  const auto warnings = rec.conflicts();
  ASSERT_EQ(warnings.size(), 1u);  // the face lexeme combines; the heads conflict
  EXPECT_EQ(warnings[0]->warning.type, WarningType::ImpossibleToSchedule);
  EXPECT_EQ(warnings[0]->behaviorId, "shake");
  EXPECT_NE(warnings[0]->warning.message.find("'nod' of block 'a' on the head channel"), std::string::npos)
      << warnings[0]->warning.message;
  // Who drives the head: nod before the overlap, shake during and after it.
  EXPECT_EQ(r.channelOwner("robot", "head", 0.5)->second, "nod");
  EXPECT_EQ(r.channelOwner("robot", "head", 1.5)->second, "shake");
  EXPECT_EQ(r.channelOwner("robot", "head", 2.5)->second, "shake");
  EXPECT_FALSE(r.channelOwner("robot", "head", 3.5));
  EXPECT_FALSE(r.channelOwner("robot", "gaze", 1.0));
}

TEST_F(RealizerWithRobot, HandsConflictOnlyWhenTheyShareAHand) {
  r.perform("<bml id='a'><gesture id='l' lexeme='BEAT' mode='LEFT_HAND' start='0'/>"
            "<gesture id='rr' lexeme='BEAT' mode='RIGHT_HAND' start='0'/></bml>");
  EXPECT_TRUE(rec.conflicts().empty());
  r.perform("<bml id='b'><gesture id='both' lexeme='BEAT' start='1'/></bml>");
  ASSERT_EQ(rec.conflicts().size(), 1u);  // one warning per behavior, naming the latest overlap
  EXPECT_NE(rec.conflicts()[0]->warning.message.find("overlaps behavior 'rr' of block 'a' (and 1 other) on the rightHand channel"),
            std::string::npos)
      << rec.conflicts()[0]->warning.message;
  EXPECT_EQ(r.channelOwner("robot", "leftHand", 1.5)->second, "both");
  EXPECT_EQ(r.channelOwner("robot", "leftHand", 0.5)->second, "l");
  // Within one block, the later behavior in the text wins.
  r.perform("<bml id='c' composition='REPLACE'><head id='h1' lexeme='NOD' start='0'/><head id='h2' lexeme='TILT' start='0.5'/></bml>");
  EXPECT_EQ(r.channelOwner("robot", "head", scene.time() + 0.75)->second, "h2");
}

// Every scheduled behavior reaches the character's timeline as a request, the
// same C++ API an engine uses without BML.
TEST_F(RealizerWithRobot, BehaviorsBecomeTimelineRequestsOnTheSceneClock) {
  scene.speech().useDefaultSynthesizer(false);  // as a build without TTS: the speech cannot be said
  step(scene, r, 1.0);
  Schedule s = r.perform("<bml id='b1'><gesture id='g' lexeme='wave' mode='RIGHT_HAND' start='0.5' amount='2'/>"
                         "<speech id='s'><text>hi there</text></speech><faceLexeme id='f' lexeme='SMILE'/></bml>");
  ASSERT_FALSE(s.failed);
  const Character& robot = *scene.findCharacter("robot");
  const auto* g = robot.behaviors().find("b1:g");
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->request.kind, BehaviorKind::Gesture);
  EXPECT_EQ(g->request.channelBits(), BodyChannel::RightHand);
  EXPECT_EQ(g->request.clip, "wave");
  // A gesture played by its clip has no parameters (amount is not one of a clip's); sync
  // attributes are times.
  EXPECT_TRUE(std::holds_alternative<std::monostate>(g->request.parameters));
  EXPECT_NEAR(g->request.start(), 1.5, 1e-9);   // scene time = block start (1 s) + 0.5
  ASSERT_TRUE(s.time("g", "end"));
  EXPECT_NEAR(g->request.end(), 1.0 + *s.time("g", "end"), 1e-9);
  const auto* sp = robot.behaviors().find("b1:s");
  ASSERT_NE(sp, nullptr);
  ASSERT_NE(sp->request.as<SpeechParameters>(), nullptr);
  EXPECT_EQ(sp->request.as<SpeechParameters>()->text, "hi there");
  EXPECT_EQ(sp->request.channelBits(), BodyChannel::Voice);
  EXPECT_EQ(robot.behaviors().find("b1:f")->request.channelBits(), BodyChannel::None);
  // The gesture has a clip and the smile a morph (guessed profile: "smile"); the
  // speech has no backend: reported, its timing and feedback still run.
  ASSERT_NE(robot.behaviors().find("b1:f")->as<FaceExpressionState>(), nullptr);
  EXPECT_FALSE(robot.behaviors().find("b1:f")->as<FaceExpressionState>()->morphs.empty());
  const auto unrealized = rec.warnings(WarningType::CannotCreateBehavior);
  ASSERT_EQ(unrealized.size(), 1u);
  EXPECT_EQ(unrealized[0]->behaviorId, "s");
  EXPECT_NE(unrealized[0]->warning.message.find("character 'robot': speech cannot be said: no speech backend"),
            std::string::npos) << unrealized[0]->warning.message;
  EXPECT_FALSE(unrealized[0]->warning.fatal);
}

// A gesture whose lexeme names a clip lasts as long as the clip (per repetition),
// matched ignoring case; without a clip the built-in 2 s stays.
TEST_F(RealizerWithRobot, DefaultDurationsComeFromTheCharactersClips) {
  const double wave = scene.findCharacter("robot")->rig().findClip("wave")->clip.duration;
  Schedule s = r.perform("<bml id='b'><gesture id='g1' lexeme='WAVE'/><gesture id='g2' lexeme='wave' repetition='3'/>"
                         "<gesture id='g3' lexeme='BEAT'/></bml>");
  ASSERT_FALSE(s.failed);
  EXPECT_NEAR(*s.time("g1", "end"), wave, 1e-6);
  EXPECT_NEAR(*s.time("g2", "end"), 3 * wave, 1e-6);
  EXPECT_NEAR(*s.time("g3", "end"), 2.0, 1e-9);
}

// `otherBlock:behavior:sync` refers to a queued block, of any character, on the
// scene clock; repetition indices reach into repeated strokes.
TEST_F(RealizerWithRobot, ReferencesToOtherQueuedBlocks) {
  scene.addCharacter("bob", test::makeSyntheticRig());
  step(scene, r, 0.5);
  ASSERT_FALSE(r.perform("<bml id='a'><head id='nod' lexeme='NOD' start='1' repetition='2'/></bml>", "robot").failed);
  const double aStart = *r.blockStart("a");
  step(scene, r, 0.5);  // the next block starts 0.5 s later: its block times are shifted
  Schedule b = r.perform("<bml id='b'><gaze id='look' target='robot' start='a:nod:stroke:2'/>"
                         "<head id='n2' lexeme='NOD' start='a:nod:end+0.25'/></bml>",
                         "bob");
  ASSERT_FALSE(b.failed);
  const double bStart = *r.blockStart("b");
  EXPECT_NEAR(bStart - aStart, 0.5, 1e-9);
  Schedule probe = scheduleText("<bml id='a'><head id='nod' lexeme='NOD' start='1' repetition='2'/></bml>");
  EXPECT_NEAR(aStart + *probe.time("nod", "stroke:2"), bStart + *b.time("look", "start"), 1e-9);
  EXPECT_NEAR(aStart + *probe.time("nod", "end") + 0.25, bStart + *b.time("n2", "start"), 1e-9);
  // Unknown blocks, behaviors and sync points are NO_SUCH_TARGET, naming what is missing.
  Schedule c = r.perform("<bml id='c'><head id='x' lexeme='NOD' start='zz:nod:end'/>"
                         "<head id='y' lexeme='NOD' start='a:shake:end'/><head id='z' lexeme='NOD' start='a:nod:stroke:3'/></bml>",
                         "bob");
  const auto missing = rec.warnings(WarningType::NoSuchTarget);
  ASSERT_EQ(missing.size(), 3u);
  EXPECT_NE(missing[0]->warning.message.find("no block 'zz' is queued"), std::string::npos) << missing[0]->warning.message;
  EXPECT_NE(missing[1]->warning.message.find("has no behavior 'shake'"), std::string::npos) << missing[1]->warning.message;
  EXPECT_NE(missing[2]->warning.message.find("stroke:3"), std::string::npos) << missing[2]->warning.message;
  EXPECT_TRUE(c.behaviors.empty());
}

TEST_F(RealizerWithRobot, BlockIdsMustBeUniqueWhileQueued) {
  ASSERT_FALSE(r.perform("<bml id='a'><head id='h' lexeme='NOD'/></bml>").failed);
  Schedule again = r.perform("<bml id='a'><head id='h' lexeme='NOD'/></bml>");
  EXPECT_TRUE(again.failed);
  EXPECT_NE(again.warnings.back().message.find("'a' is still queued"), std::string::npos);
  EXPECT_EQ(r.activeBlocks(), 1u);
  // REPLACE ends the earlier block first, so the same id may come back that way.
  EXPECT_FALSE(r.perform("<bml id='a' composition='REPLACE'><head id='h' lexeme='NOD'/></bml>").failed);
  EXPECT_EQ(r.activeBlocks(), 1u);
}

// REPLACE ends the running blocks and their motion blends back smoothly to what
// lies below (here the rest pose) over replaceBlendSeconds.
TEST_F(RealizerWithRobot, ReplaceBlendsBackToNeutralSmoothly) {
  Character& robot = *scene.findCharacter("robot");
  const glm::quat rest = robot.skeleton().restPose[3].rotation;
  ASSERT_FALSE(r.perform("<bml id='a'><gesture id='g' lexeme='wave' start='0' end='5'/></bml>").failed);
  const double dt = 1.0 / 60.0;
  for (int f = 0; f < 45; ++f) {
    scene.update(dt);
    r.update();
  }
  const float moved = test::angleBetween(rest, robot.localPose()[3].rotation);
  EXPECT_GT(moved, 0.3f);  // the wave is on
  r.setReplaceBlendSeconds(0.5);
  ASSERT_FALSE(r.perform("<bml id='b' composition='REPLACE'><wait id='w' start='0' end='1'/></bml>").failed);
  glm::quat previous = robot.localPose()[3].rotation;
  float maxStep = 0.0f;
  for (int f = 0; f < 33; ++f) {  // 0.55 s
    scene.update(dt);
    r.update();
    maxStep = std::max(maxStep, test::angleBetween(previous, robot.localPose()[3].rotation));
    previous = robot.localPose()[3].rotation;
  }
  EXPECT_EQ(robot.localPose()[3].rotation, rest);
  // Smooth: no frame moves more than the wave clip itself does (1.2 rad per 0.25 s).
  EXPECT_LT(maxStep, 0.1f);
  EXPECT_EQ(robot.behaviors().find("a:g"), nullptr);
}

// A standing posture by its BML stance name plays the profile's idle clip.
TEST(Realizer, StandingPostureIsTheProfilesIdleClip) {
  auto rig = std::make_shared<Rig>(*test::makeSyntheticRig());
  CharacterProfile p = rig->profile();
  p.idle = "walk";
  rig->setProfile(p);
  Scene scene;
  scene.addCharacter("robot", rig);
  Realizer r(scene);
  ASSERT_FALSE(r.perform("<bml id='b'><posture id='p' lexeme='STAND' start='0' end='3'/>"
                         "<posture id='q' stance='standing' start='3' end='4'/></bml>").failed);
  EXPECT_EQ(scene.findCharacter("robot")->behaviors().find("b:p")->request.clip, "walk");
  EXPECT_EQ(scene.findCharacter("robot")->behaviors().find("b:q")->request.clip, "walk");
  EXPECT_TRUE(scene.findCharacter("robot")->behaviors().find("b:p")->request.loop);
}

// A locomotion's sync points are scheduled on the walk's estimated length from
// where the character stands; its end feedback fires when the character arrives.
TEST_F(RealizerWithRobot, LocomotionEndFiresOnArrival) {
  Character* c = scene.findCharacter("robot");
  const Schedule s = r.perform(
      "<bml id='b'><locomotion id='w' target='0 3' facing='90'/><head id='n' lexeme='NOD' start='w:end'/></bml>");
  ASSERT_FALSE(s.failed);
  const auto end = s.time("w", "end");
  ASSERT_TRUE(end);
  // 3 m at the synthetic walk's 1 m/s, plus accelerating, braking and turning 90 degrees.
  EXPECT_GT(*end, 3.0);
  EXPECT_LT(*end, 5.0);
  EXPECT_NEAR(*s.time("n", "start"), *end, 1e-9);
  step(scene, r, 8.0, 1.0 / 60.0);
  const Feedback* arrival = nullptr;
  for (const Feedback* f : rec.of(Feedback::Kind::SyncPointProgress))
    if (f->behaviorId == "w" && f->syncPoint == "end") arrival = f;
  ASSERT_TRUE(arrival);
  const LocomotionStatus st = c->locomotionStatus("b:w");
  ASSERT_EQ(st.state, LocomotionStatus::State::Done);
  EXPECT_DOUBLE_EQ(arrival->sceneTime, st.doneTime);
  EXPECT_NEAR(arrival->sceneTime, *end, 0.1);  // the estimate is close
  EXPECT_LT(glm::length(glm::vec2(c->position().x, c->position().z) - glm::vec2(0, 3)), 0.05f);
  EXPECT_NEAR(c->heading(), glm::radians(90.0f), glm::radians(1.0f));
  EXPECT_EQ(r.activeBlocks(), 0u);
}

// Bad targets are warnings that name the target; nothing moves, nothing crashes.
TEST_F(RealizerWithRobot, LocomotionBadTargetsAreWarnings) {
  Character* c = scene.findCharacter("robot");
  r.perform("<bml id='b1'><locomotion id='w' target='nan 2'/></bml>");
  r.perform("<bml id='b2'><locomotion id='w' target='Nobody'/></bml>");
  r.perform("<bml id='b3'><locomotion id='w' target='0 0'/></bml>");
  r.perform("<bml id='b4' composition='APPEND'><locomotion id='w' target='10000 0' manner='RUN'/></bml>");
  const auto w = rec.warnings(WarningType::CannotCreateBehavior);
  ASSERT_GE(w.size(), 2u);
  EXPECT_NE(w[0]->warning.message.find("'nan 2'"), std::string::npos) << w[0]->warning.message;
  EXPECT_NE(w[1]->warning.message.find("'Nobody'"), std::string::npos) << w[1]->warning.message;
  bool inside = false, far = false;
  for (const Feedback* f : rec.warnings(WarningType::ParsingFailure)) {
    inside |= f->warning.message.find("inside the character") != std::string::npos;
    far |= f->warning.message.find("10.0 km away") != std::string::npos;
  }
  EXPECT_TRUE(inside);
  EXPECT_TRUE(far);
  step(scene, r, 2.0, 0.5);
  EXPECT_TRUE(std::isfinite(c->position().x) && std::isfinite(c->position().z));
}

// Scripts walk to named scene objects (pawns, props) as to characters, onto them unless a
// proximity is given (issue 24, 6; gaze: Gaze.SceneObjectsAreTargetsLikePoints).
TEST_F(RealizerWithRobot, LocomotionReachesASceneObject) {
  Character* c = scene.findCharacter("robot");
  ASSERT_TRUE(scene.setObject("door", {2.0f, 0.0f, 1.0f}));
  ASSERT_TRUE(scene.setObject("camera", {0.0f, 1.6f, 3.0f}));
  ASSERT_FALSE(r.perform("<bml id='w'><locomotion id='l' target='door'/></bml>", "robot").failed);
  EXPECT_TRUE(rec.warnings(WarningType::CannotCreateBehavior).empty())
      << rec.warnings(WarningType::CannotCreateBehavior).front()->warning.message;
  step(scene, r, 12.0);
  EXPECT_LT(glm::length(glm::vec2(c->position().x - 2.0f, c->position().z - 1.0f)), 0.5f)
      << c->position().x << " " << c->position().z;
}

// <pointing> with a target aims the arm (no "no controller" warning); a bad
// target is a CANNOT_CREATE_BEHAVIOR warning naming it.
TEST(Realizer, PointingAimsTheArmAndBadTargetsAreWarnings) {
  Scene scene;
  Realizer r(scene);
  Recorder rec;
  r.addFeedbackListener([&](const Feedback& f) { rec.all.push_back(f); });
  Character* c = scene.addCharacter("ann", test::makeUpperBodyRig());
  r.perform("<bml id='b1' characterId='ann'><pointing id='p' target='3 4 6' mode='LEFT_HAND' start='0' ready='0.3' end='2'/></bml>");
  ASSERT_TRUE(rec.of(Feedback::Kind::Warning).empty()) << rec.all.front().xml();
  const int lower = c->skeleton().findJoint("LeftForeArm"), hand = c->skeleton().findJoint("LeftHand");
  step(scene, r, 1.0, 1.0 / 30.0);
  EXPECT_TRUE(c->stats().used(Controller::Pointing));
  auto world = [&](int j) {
    return glm::vec3(c->transformBuffer().worldMatrix() * c->transformBuffer().modelMatrices()[static_cast<std::size_t>(j)][3]);
  };
  const glm::vec3 elbow = world(lower), forearm = glm::normalize(world(hand) - elbow);
  EXPECT_GT(glm::dot(forearm, glm::normalize(glm::vec3(3, 4, 6) - elbow)), std::cos(glm::radians(0.5f)));
  r.perform("<bml id='b2' characterId='ann' composition='APPEND'><pointing id='q' target='inf 0 0'/></bml>");
  r.perform("<bml id='b3' characterId='ann' composition='APPEND'><pointing id='q' target='Nobody'/></bml>");
  const auto w = rec.warnings(WarningType::CannotCreateBehavior);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0]->warning.message.find("pointing target 'inf 0 0' is not finite"), std::string::npos) << w[0]->warning.message;
  EXPECT_NE(w[1]->warning.message.find("'Nobody'"), std::string::npos) << w[1]->warning.message;
}

// A preparation shortened to nothing (stroke="0", ready="0" relax="0") reaches the body without
// a NaN (issue 24, 2): head, pointing and gaze on an upper body. The nod, which a head cannot make
// in no time, is slowed (issue 45, 10): its peak comes as soon as a head can turn that far, said.
TEST(Realizer, ShortenedPreparationsMoveTheBodyWithoutNaN) {
  Scene scene;
  Realizer r(scene);
  Recorder rec;
  r.addFeedbackListener([&](const Feedback& f) { rec.all.push_back(f); });
  Character* c = scene.addCharacter("ann", test::makeUpperBodyRig());
  r.perform("<bml id='b' characterId='ann'><head id='h' lexeme='NOD' stroke='0'/>"
            "<pointing id='p' target='3 4 6' stroke='0' relax='1'/>"
            "<gaze id='g' target='1 1 2' ready='0' relax='0'/></bml>");
  const auto warned = rec.of(Feedback::Kind::Warning);
  ASSERT_EQ(warned.size(), 1u) << rec.all.front().xml();
  EXPECT_NE(warned[0]->warning.message.find("slowed to what a head can do"), std::string::npos) << warned[0]->xml();
  EXPECT_EQ(warned[0]->warning.behaviorId, "h");
  for (int frame = 0; frame < 60; ++frame) {
    scene.update(1.0 / 60.0);
    r.update();
    for (const Transform& t : c->localPose()) ASSERT_TRUE(test::finite(t)) << "frame " << frame;
  }
  EXPECT_TRUE(c->stats().used(Controller::Pointing));
}

// SmartBody's <animation name speed> plays the rig's clip over duration / speed; <sbm:event>
// sends its message at its stroke, as feedback and to the scene's listeners (issue 24, 5).
TEST_F(RealizerWithRobot, SmartBodyAnimationsPlayClipsAndEventsSendMessages) {
  struct Messages : SceneListener {
    std::vector<std::pair<std::string, double>> got;
    void onMessage(const Character& c, std::string_view m, double t) override {
      got.emplace_back(c.name() + ": " + std::string(m), t);
    }
  } messages;
  scene.addListener(&messages);
  const double wave = scene.findCharacter("robot")->rig().findClip("wave")->clip.duration;
  const Schedule s = r.perform("<bml xmlns:sbm=\"http://ict.usc.edu\"><animation name=\"wave\" speed=\"2\"/>"
                               "<sbm:event message=\"cue lights\" stroke=\"animation_1:end\"/></bml>",
                               "robot");
  ASSERT_FALSE(s.failed);
  EXPECT_NEAR(*s.time("animation_1", "end"), wave / 2, 1e-6);
  const auto* entry = scene.findCharacter("robot")->behaviors().find(s.blockId + ":animation_1");
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry->request.clip, "wave");
  EXPECT_TRUE(rec.of(Feedback::Kind::Warning).empty() || rec.of(Feedback::Kind::Warning).size() == 1u)
      << "only the generated ids are named";
  step(scene, r, wave);
  ASSERT_EQ(messages.got.size(), 1u);
  EXPECT_EQ(messages.got[0].first, "robot: cue lights");
  EXPECT_NEAR(messages.got[0].second, wave / 2, 1e-9);
  const auto events = rec.of(Feedback::Kind::Event);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]->message, "cue lights");
  EXPECT_NE(events[0]->xml().find("message=\"cue lights\""), std::string::npos) << events[0]->xml();
  // A clip the rig does not have is named, with what it has.
  r.perform("<bml><animation name=\"Moonwalk\"/></bml>", "robot");
  const auto cannot = rec.warnings(WarningType::CannotCreateBehavior);
  ASSERT_EQ(cannot.size(), 1u);
  EXPECT_NE(cannot[0]->warning.message.find("no clip named 'Moonwalk' (it has"), std::string::npos)
      << cannot[0]->warning.message;
  scene.removeListener(&messages);
}

// AsapRealizer's BMLA (issue 24, 5): start after named blocks end or relax, interrupt them,
// plan now and start later; what is not supported is named.
TEST_F(RealizerWithRobot, BmlaAppendChunkInterruptPreplanAndActivate) {
  const std::string ns = " xmlns:bmla=\"http://www.asap-project.org/bmla\"";
  auto ends = [&](const std::string& block) {
    int n = 0;
    for (const Feedback* f : rec.of(Feedback::Kind::BlockProgress)) n += f->blockId == block && f->syncPoint == "end";
    return n;
  };
  ASSERT_FALSE(r.perform("<bml id=\"a\"><gaze id=\"g\" target=\"1 1 1\" start=\"0\" ready=\"0.2\" relax=\"1\" end=\"2\"/></bml>",
                         "robot").failed);
  const Schedule appended = r.perform("<bml id=\"b\"" + ns + " bmla:appendAfter=\"a\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot");
  ASSERT_FALSE(appended.failed);
  EXPECT_DOUBLE_EQ(*r.blockStart("b"), 2.0) << "after a ends";
  ASSERT_FALSE(r.perform("<bml id=\"c\"" + ns + " bmla:chunkAfter=\"a\"><head id=\"h\" lexeme=\"SHAKE\"/></bml>", "robot").failed);
  EXPECT_DOUBLE_EQ(*r.blockStart("c"), 1.0) << "once a relaxes";
  // Preplanned: checked now (warnings), started by another block's onStart.
  const Schedule planned = r.perform("<bml id=\"p\"" + ns + " bmla:preplan=\"true\"><head id=\"h\" lexeme=\"TILT\"/></bml>", "robot");
  EXPECT_TRUE(planned.preplanned);
  EXPECT_EQ(r.preplannedBlocks(), 1u);
  EXPECT_FALSE(r.blockStart("p"));
  step(scene, r, 0.5);
  // A block that interrupts a and starts p.
  ASSERT_FALSE(r.perform("<bml id=\"i\"" + ns + " bmla:interrupt=\"a, c\" bmla:onStart=\"p\">"
                         "<head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  EXPECT_EQ(ends("a"), 1) << "interrupted when i started";
  EXPECT_EQ(ends("c"), 1);
  EXPECT_EQ(r.preplannedBlocks(), 0u);
  ASSERT_TRUE(r.blockStart("p"));
  EXPECT_NEAR(*r.blockStart("p"), scene.time(), 1e-9);
  // <bmla:activate> at a sync point, and Realizer::activate.
  ASSERT_FALSE(r.perform("<bml id=\"q\"" + ns + " bmla:preplan=\"true\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  ASSERT_FALSE(r.perform("<bml id=\"x\"" + ns + "><head id=\"h\" lexeme=\"NOD\"/>"
                         "<bmla:activate id=\"act\" target=\"q\" start=\"h:end\"/></bml>", "robot").failed);
  EXPECT_FALSE(r.blockStart("q"));
  step(scene, r, 1.1);
  ASSERT_TRUE(r.blockStart("q")) << "activated when x's nod ended";
  ASSERT_FALSE(r.perform("<bml id=\"z\"" + ns + " bmla:preplan=\"true\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  EXPECT_TRUE(r.activate("z"));
  EXPECT_FALSE(r.activate("z"));
  EXPECT_TRUE(r.blockStart("z"));
  // Named: BMLA attributes this realizer does not read, a block to wait for that never ran.
  const Schedule odd = r.perform("<bml id=\"o\"" + ns + " bmla:prependBefore=\"z\" bmla:appendAfter=\"ghost\" color=\"red\">"
                                 "<head id=\"h\" lexeme=\"NOD\"/></bml>", "robot");
  EXPECT_FALSE(odd.failed);
  std::string said;
  for (const Warning& w : odd.warnings) said += w.message + "\n";
  EXPECT_NE(said.find("BMLA's bmla:prependBefore is not supported"), std::string::npos) << said;
  EXPECT_NE(said.find("block 'ghost' (appendAfter/chunkAfter) is neither queued nor finished"), std::string::npos) << said;
  EXPECT_NE(said.find("attribute 'color' of <bml> is not one of id, characterId, composition"), std::string::npos) << said;
  // A preplanned id is taken until it starts; interrupt drops a preplanned block.
  ASSERT_FALSE(r.perform("<bml id=\"w\"" + ns + " bmla:preplan=\"true\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  EXPECT_TRUE(r.perform("<bml id=\"w\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  EXPECT_TRUE(r.interrupt("w"));
  EXPECT_EQ(r.preplannedBlocks(), 0u);
}

// SmartBody mode on the realizer: blocks without ids get "sbm_block_N", N counting perform()
// calls, so that two identical SmartBody blocks run one after the other (issue 24, 1).
TEST_F(RealizerWithRobot, SmartBodyModeNumbersTheBlocksItGivesIds) {
  const std::string block = "<bml><head lexeme=\"NOD\" start=\"0\" end=\"0.5\"/></bml>";
  EXPECT_EQ(r.dialect(), Dialect::Auto);
  EXPECT_TRUE(r.perform(block, "robot").failed) << "BML 1.0: a block needs an id";
  r.setDialect(Dialect::SmartBody);
  const Schedule first = r.perform(block, "robot");
  const Schedule second = r.perform(block, "robot");
  ASSERT_FALSE(first.failed);
  ASSERT_FALSE(second.failed) << "the generated ids differ, so the second is not a duplicate";
  EXPECT_EQ(first.blockId, "sbm_block_2");
  EXPECT_EQ(second.blockId, "sbm_block_3");
  ASSERT_EQ(first.behaviors.size(), 1u);
  EXPECT_EQ(first.behaviors[0].id, "head_1");
  // The warning reaches the feedback once per block, naming what was generated.
  int generated = 0;
  for (const Feedback* f : rec.warnings(WarningType::ParsingFailure))
    generated += f->warning.message.find("SmartBody mode: ids generated") != std::string::npos;
  EXPECT_EQ(generated, 2);
  step(scene, r, 1.0);
  EXPECT_EQ(r.activeBlocks(), 0u);
}

// A character's own dialect (a scene file's "bmlDialect") comes first, whether the block is
// sent to it by name or names it as characterId; the others keep the realizer's (issue 24, 1).
TEST_F(RealizerWithRobot, ACharactersOwnDialectComesFirst) {
  scene.addCharacter("sbm", test::makeSyntheticRig());
  r.setDialect(Dialect::Bml);
  r.setDialect("sbm", Dialect::SmartBody);
  EXPECT_EQ(r.dialectFor("sbm"), Dialect::SmartBody);
  EXPECT_EQ(r.dialectFor("robot"), Dialect::Bml);
  const std::string noIds = "<bml><head lexeme=\"NOD\" start=\"0\" end=\"0.5\"/></bml>";
  const Schedule toSbm = r.perform(noIds, "sbm");
  EXPECT_FALSE(toSbm.failed);
  EXPECT_EQ(toSbm.dialect, Dialect::SmartBody);
  EXPECT_TRUE(r.perform(noIds, "robot").failed) << "strict BML for the robot";
  // Named inside the block: found even though the block has no id to parse strictly.
  const Schedule named = r.perform("<bml characterId=\"sbm\"><head lexeme=\"SHAKE\" start=\"0\" end=\"0.4\"/></bml>");
  EXPECT_FALSE(named.failed);
  EXPECT_EQ(named.dialect, Dialect::SmartBody);
  const Schedule namedRobot = r.perform("<bml characterId=\"robot\"><head lexeme=\"SHAKE\"/></bml>");
  EXPECT_TRUE(namedRobot.failed);
  // A block with ids, for the robot, is read as BML; a later setDialect replaces the first.
  EXPECT_EQ(r.perform("<bml id=\"b\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").dialect, Dialect::Bml);
  r.setDialect("robot", Dialect::SmartBody);
  r.setDialect("robot", Dialect::Auto);
  EXPECT_EQ(r.dialectFor("robot"), Dialect::Auto);
  // Unparseable text stays an error in every dialect (the lenient read only finds the character).
  EXPECT_TRUE(r.perform("<bml characterId=\"sbm\"><head", "").failed);
  // A scene file's list, as loadSceneFile gives it, sets the same thing; every name it accepts is one.
  SceneLoadResult loaded;
  loaded.bmlDialects = {{"robot", "smartbody"}, {"sbm", "bml"}};
  useSceneDialects(r, loaded);
  EXPECT_EQ(r.dialectFor("robot"), Dialect::SmartBody);
  EXPECT_EQ(r.dialectFor("sbm"), Dialect::Bml);
  for (const char* name : {"auto", "bml", "smartbody"}) EXPECT_TRUE(dialectFromName(name)) << name;
}

// Timing no body can follow, from BML (issue 45, 10): a thousand nods in 10 ms are thinned, said
// with the behavior's id; at 1000 frames a second no frame turns the head by more than a head can.
TEST(Realizer, AThousandNodsInTenMillisecondsAreThinnedAndSaid) {
  Scene scene;
  Realizer r(scene);
  Recorder rec;
  r.addFeedbackListener([&](const Feedback& f) { rec.all.push_back(f); });
  Character* c = scene.addCharacter("ann", test::makeUpperBodyRig());
  scene.update(0.0);
  r.perform("<bml id='b' characterId='ann'><head id='h' lexeme='NOD' repeats='1000' start='0' end='0.01'/></bml>");
  const auto warned = rec.of(Feedback::Kind::Warning);
  ASSERT_FALSE(warned.empty());
  bool thinned = false;
  for (const Feedback* f : warned) thinned |= f->warning.behaviorId == "h" && f->warning.message.find("thinned") != std::string::npos;
  EXPECT_TRUE(thinned) << warned[0]->xml();
  const int head = c->rig().joints().head;
  ASSERT_GE(head, 0);
  glm::quat before = c->transformBuffer().modelMatrices().empty() ? glm::quat(1, 0, 0, 0)
                                                                  : glm::quat_cast(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(head)]);
  float worst = 0.0f;
  for (int frame = 0; frame < 40; ++frame) {
    scene.update(0.001);
    r.update();
    const glm::quat now = glm::quat_cast(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(head)]);
    worst = std::max(worst, glm::angle(glm::normalize(now * glm::inverse(before))));
    before = now;
  }
  EXPECT_LT(glm::degrees(worst), 0.5f);  // 2.4 degrees in one frame before
}
