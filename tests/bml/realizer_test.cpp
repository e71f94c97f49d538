#include <gtest/gtest.h>

#include "marionette/bml/realizer.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {
struct Recorder {
  std::vector<Feedback> all;
  std::vector<const Feedback*> of(Feedback::Kind kind) const {
    std::vector<const Feedback*> out;
    for (const Feedback& f : all)
      if (f.kind == kind) out.push_back(&f);
    return out;
  }
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
  EXPECT_TRUE(rec.of(Feedback::Kind::Warning).empty());
  r.perform("<bml id='b'><head id='shake' lexeme='SHAKE' start='1' end='3'/>"
            "<faceLexeme id='smile' lexeme='SMILE' start='1'/></bml>");
  const auto warnings = rec.of(Feedback::Kind::Warning);
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
  EXPECT_TRUE(rec.of(Feedback::Kind::Warning).empty());
  r.perform("<bml id='b'><gesture id='both' lexeme='WAVE' start='1'/></bml>");
  EXPECT_EQ(rec.of(Feedback::Kind::Warning).size(), 2u);  // overlaps each hand's gesture
  EXPECT_EQ(r.channelOwner("robot", "leftHand", 1.5)->second, "both");
  EXPECT_EQ(r.channelOwner("robot", "leftHand", 0.5)->second, "l");
  // Within one block, the later behavior in the text wins.
  r.perform("<bml id='c' composition='REPLACE'><head id='h1' lexeme='NOD' start='0'/><head id='h2' lexeme='TILT' start='0.5'/></bml>");
  EXPECT_EQ(r.channelOwner("robot", "head", scene.time() + 0.75)->second, "h2");
}
