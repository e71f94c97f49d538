// BML <speech> end to end: the realizer schedules a speech with the timing its
// backend says (word marks as sync points other behaviors refer to), and
// composition decides what happens to two utterances on one character.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "marionette/bml/realizer.hpp"
#ifdef MARIONETTE_HAS_TTS
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif
#include "marionette/speech/recorded_speech.hpp"
#include "gated_speech_backend.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {

constexpr const char* kArcticText = "He turned sharply, and faced Gregson across the table.";

std::string speechBlock(const std::string& id, const std::string& composition = "MERGE") {
  return "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' id='" + id + "' composition='" + composition +
         "'><speech id='s1'><text>He turned sharply, and <sync id='w4'/> faced Gregson across the table.</text>"
         "</speech><head id='h1' lexeme='NOD' start='s1:w4'/></bml>";
}

struct GodetteRealizer : ::testing::Test {
  Scene scene;
  Realizer realizer{scene};
  std::vector<Feedback> feedback;
  std::shared_ptr<speech::RecordedSpeech> recorded = std::make_shared<speech::RecordedSpeech>();
  void SetUp() override {
    realizer.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
    const std::string vrm = test::sharedAsset("characters/Godette_vrm_v4.vrm");
    MARIONETTE_REQUIRE_FILE(vrm);
    ASSERT_TRUE(scene.addCharacter("godette", test::loadRigWithProfile(vrm, "Godette_vrm_v4.json")));
    ASSERT_EQ(recorded->addLine(kArcticText, test::sharedAsset("speech/arctic_a0009.wav"),
                                test::sharedAsset("speech/arctic_a0009.phones.txt")),
              "");
    scene.speech().addBackend(recorded);
    realizer.addFeedbackListener([this](const Feedback& f) { feedback.push_back(f); });
  }
  void step(double seconds) {
    for (int i = 0, n = static_cast<int>(std::lround(seconds * 60.0)); i < n; ++i) {
      scene.update(1.0 / 60.0);
      realizer.update();
    }
  }
};

TEST_F(GodetteRealizer, WordMarksAreSyncPointsAtTheTimesTheVoiceSaysThem) {
  const Schedule s = realizer.perform(speechBlock("b1"), "godette");
  ASSERT_FALSE(s.failed);
  for (const Warning& w : s.warnings) ADD_FAILURE() << w.message;
  // The recording's length, not the characters-per-second estimate (54 chars x 0.065 s = 3.51 s).
  ASSERT_TRUE(s.time("s1", "end"));
  EXPECT_NEAR(*s.time("s1", "end"), 49520.0 / 16000.0, 1e-6);
  // The same mark time the backend gives for the same words.
  speech::SpeechRequest direct;
  direct.text = kArcticText;
  direct.marks = {{"w4", std::string(kArcticText).find(" faced") + 1}};
  const speech::SpeechResult said = recorded->synthesize(direct);
  ASSERT_TRUE(said.utterance);
  ASSERT_TRUE(s.time("s1", "w4"));
  EXPECT_NEAR(*s.time("s1", "w4"), said.utterance->marks.at(0).time, 0.02);
  EXPECT_NEAR(*s.time("h1", "start"), *s.time("s1", "w4"), 1e-9);  // the nod starts on the word
  // Feedback: the mark passes as a syncPointProgress at its time.
  step(3.5);
  bool seen = false;
  for (const Feedback& f : feedback)
    if (f.kind == Feedback::Kind::SyncPointProgress && f.behaviorId == "s1" && f.syncPoint == "w4") {
      seen = true;
      EXPECT_NEAR(f.blockTime, *s.time("s1", "w4"), 1.0 / 60.0 + 1e-9);
    }
  EXPECT_TRUE(seen);
}

// Speech off the frame path (the default, SpeechSynthesis::Background): a block whose
// line is not said yet is held, frames go on, blocks sent after it wait behind it (an
// APPEND still starts after it), and it starts at the update after its line is said.
// A line said before starts at once; a held block can be interrupted; a block that
// does not parse fails at once.
TEST_F(GodetteRealizer, InTheBackgroundABlockWaitsForItsSpeechAndNoFrameDoes) {
  Scene s2;
  ASSERT_TRUE(s2.addCharacter("godette", std::make_shared<const Rig>(scene.findCharacter("godette")->rig())));
  s2.speech().useDefaultSynthesizer(false);
  auto gate = std::make_shared<test::GatedSpeechBackend>(recorded);
  s2.speech().addBackend(gate);
  const test::GateOpener opener{*gate};
  Realizer r(s2);
  ASSERT_EQ(r.speechSynthesis(), Realizer::SpeechSynthesis::Background);
  std::vector<Feedback> heard;
  r.addFeedbackListener([&](const Feedback& f) { heard.push_back(f); });

  const Schedule held = r.perform(speechBlock("b1"), "godette");
  EXPECT_FALSE(held.failed);
  EXPECT_TRUE(held.heldForSpeech);
  EXPECT_EQ(held.blockId, "b1");
  const Schedule behind = r.perform("<bml id='b2' composition='APPEND'><head id='n' lexeme='NOD'/></bml>", "godette");
  EXPECT_TRUE(behind.heldForSpeech) << "a block sent after a held one waits behind it";
  EXPECT_EQ(r.heldBlocks(), 2u);
  EXPECT_TRUE(r.perform("<bml id='broken'><speech", "godette").failed) << "a block that does not parse fails at once";
  for (int i = 0; i < 30; ++i) {  // half a second of frames while the synthesizer works
    s2.update(1.0 / 60.0);
    r.update();
  }
  EXPECT_EQ(r.heldBlocks(), 2u);
  EXPECT_EQ(s2.findCharacter("godette")->behaviors().find("b1:s1"), nullptr);
  for (const Feedback& f : heard) EXPECT_NE(f.kind, Feedback::Kind::Prediction) << f.xml();

  gate->setOpen(true);
  r.waitForSpeech();
  EXPECT_EQ(r.heldBlocks(), 0u);
  const double first = 49520.0 / 16000.0;
  ASSERT_TRUE(r.blockStart("b1") && r.blockStart("b2"));
  EXPECT_NEAR(*r.blockStart("b1"), 0.5, 1e-9) << "starts when its line is ready";
  EXPECT_NEAR(*r.blockStart("b2"), 0.5 + first, 1e-6) << "APPEND after the held block, as sent";
  EXPECT_TRUE(std::any_of(heard.begin(), heard.end(), [](const Feedback& f) {
    return f.kind == Feedback::Kind::Prediction && f.blockId == "b1";
  }));

  // Said before: at once, the synthesizer not asked again.
  const int calls = gate->calls;
  const Schedule again = r.perform(speechBlock("b3", "REPLACE"), "godette");
  EXPECT_FALSE(again.heldForSpeech);
  EXPECT_FALSE(again.behaviors.empty());
  EXPECT_EQ(gate->calls, calls);

  // A block sent for a later time waits for that time, not only for its line; a setting
  // changed while the line is said does not make the realizer say it again on the frame.
  gate->setOpen(false);
  const int before = gate->calls;
  const double sentFor = s2.time() + 5.0;
  EXPECT_TRUE(r.perform("<bml id='later'><speech id='s'><text>" + std::string(kArcticText) + " Again.</text></speech></bml>",
                        "godette", {}, sentFor)
                  .heldForSpeech);
  s2.speech().setLipSyncSettings({});  // the cache forgets; the held block keeps its line
  gate->setOpen(true);
  r.waitForSpeech();
  ASSERT_TRUE(r.blockStart("later"));
  EXPECT_NEAR(*r.blockStart("later"), sentFor, 1e-9);
  EXPECT_EQ(gate->calls, before + 1) << "the line was said once, in the background";
  r.interrupt("later");

  // Held, then interrupted: dropped, never performed.
  gate->setOpen(false);
  const Schedule dropped = r.perform(
      "<bml id='b4'><speech id='s'><text>A line nobody recorded.</text></speech></bml>", "godette");
  EXPECT_TRUE(dropped.heldForSpeech);
  EXPECT_TRUE(r.interrupt("b4"));
  EXPECT_EQ(r.heldBlocks(), 0u);
  gate->setOpen(true);
  s2.speech().waitUntilPrepared();
  s2.update(1.0 / 60.0);
  r.update();
  EXPECT_EQ(s2.findCharacter("godette")->behaviors().find("b4:s"), nullptr);

  // Switched to Inline with a block held: the held one is realized first, in order.
  gate->setOpen(false);
  EXPECT_TRUE(r.perform("<bml id='b5'><speech id='s'><text>Held, then inline.</text></speech></bml>", "godette")
                  .heldForSpeech);
  r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
  gate->setOpen(true);
  EXPECT_FALSE(r.perform("<bml id='b6'><head id='n' lexeme='NOD'/></bml>", "godette").heldForSpeech);
  EXPECT_EQ(r.heldBlocks(), 0u);
  ASSERT_TRUE(r.blockStart("b5")) << "the held block was realized before the inline one";
  ASSERT_TRUE(r.blockStart("b6"));
}

TEST_F(GodetteRealizer, AppendQueuesTheSecondUtteranceAndReplaceInterruptsTheFirst) {
  ASSERT_FALSE(realizer.perform(speechBlock("b1"), "godette").failed);
  ASSERT_FALSE(realizer.perform(speechBlock("b2", "APPEND"), "godette").failed);
  const double first = 49520.0 / 16000.0;
  ASSERT_TRUE(realizer.blockStart("b2"));
  EXPECT_NEAR(*realizer.blockStart("b2"), first, 1e-6);  // queued after the first ends
  step(1.0);
  ASSERT_FALSE(realizer.perform(speechBlock("b3", "REPLACE"), "godette").failed);
  const Character& g = *scene.findCharacter("godette");
  // b1 is cut off now (blending out over the replace blend), b2 never starts, b3 speaks.
  ASSERT_NE(g.behaviors().find("b1:s1"), nullptr);
  EXPECT_TRUE(g.behaviors().find("b1:s1")->cancelled());
  EXPECT_EQ(g.behaviors().find("b2:s1"), nullptr);
  EXPECT_EQ(g.behaviors().owner(BodyChannel::Voice, scene.time() + 0.5), &g.behaviors().find("b3:s1")->request);
}

#ifdef MARIONETTE_HAS_TTS
// With espeak-ng, the schedule holds the synthesized utterance's own length and mark.
TEST(SpeechBml, EspeakTimingDrivesTheSchedule) {
  Scene scene;
  speech::useEspeak(scene.speech());
  Realizer realizer(scene);
  realizer.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
  const std::string vrm = test::sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(vrm);
  ASSERT_TRUE(scene.addCharacter("godette", test::loadRigWithProfile(vrm, "Godette_vrm_v4.json")));
  const Schedule s = realizer.perform(
      "<bml id='b1'><speech id='s1'><text>Hello there, <sync id='w3'/> how are you?</text></speech>"
      "<gesture id='g1' lexeme='BEAT' stroke='s1:w3'/></bml>",
      "godette");
  ASSERT_FALSE(s.failed);
  std::string why;
  auto tts = speech::makeEspeakBackend(&why);
  ASSERT_TRUE(tts) << why;
  speech::SpeechRequest r;
  r.text = "Hello there, how are you?";
  r.marks = {{"w3", std::string("Hello there, ").size()}};
  const speech::SpeechResult said = tts->synthesize(r);
  ASSERT_TRUE(said.utterance) << said.error;
  EXPECT_NEAR(*s.time("s1", "end"), said.utterance->duration, 1e-6);
  ASSERT_EQ(said.utterance->marks.size(), 1u);
  EXPECT_NEAR(*s.time("s1", "w3"), said.utterance->marks[0].time, 1e-6);
  EXPECT_GT(*s.time("s1", "w3"), 0.3);  // after "Hello there,"
  EXPECT_LT(*s.time("s1", "w3"), *s.time("s1", "end"));
  const auto* entry = scene.findCharacter("godette")->behaviors().find("b1:s1");
  ASSERT_NE(entry, nullptr);
  EXPECT_TRUE(entry->as<SpeechState>() != nullptr);
}
#endif

}  // namespace

// ../shared/repro/bml_speech_mark_after_trailing_space_dropped.xml: a <sync> after the last
// word, a space after it. The mark was dropped with the nod that starts on it; it is the
// end of the speech.
TEST(SpeechBml, AMarkAfterTheLastWordIsTheEndOfTheSpeech) {
  const std::string file = ::marionette::test::sharedDir() + "/repro/bml_speech_mark_after_trailing_space_dropped.xml";
  MARIONETTE_REQUIRE_FILE(file);
  const std::string vrm = test::sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(vrm);
  Scene scene;
#ifdef MARIONETTE_HAS_TTS
  speech::useEspeak(scene.speech());  // the repro was found with espeak-ng's timing
#endif
  ASSERT_TRUE(scene.addCharacter("godette", test::loadRigWithProfile(vrm, "Godette_vrm_v4.json")));
  Realizer realizer(scene);
  realizer.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
  const Schedule s = realizer.perform(test::readFile(file), "godette");
  ASSERT_FALSE(s.failed);
  for (const Warning& w : s.warnings) ADD_FAILURE() << toString(w.type) << ": " << w.message;
  ASSERT_TRUE(s.time("s", "m")) << "the mark was dropped";
  ASSERT_TRUE(s.time("s", "end"));
  EXPECT_LE(*s.time("s", "m"), *s.time("s", "end") + 1e-9);
  EXPECT_GT(*s.time("s", "m"), *s.time("s", "start")) << "the mark is after the words, not at the start";
  ASSERT_TRUE(s.time("n", "start")) << "the nod that starts on the mark was dropped";
  EXPECT_NEAR(*s.time("n", "start"), *s.time("s", "m"), 1e-9);
}

// ../shared/repro/README.md: 1 MB of speech text blocked a frame for about 400 s (100 KB:
// 48 s) and 5000 <sync> marks took 65 s, with exit 0 and no warning. A line is at most
// limits::kMaxSpeechCharacters characters with limits::kMaxSpeechMarks marks: past that
// the speech is refused with a warning naming the behavior and the limit, at once.
TEST(SpeechBml, TextAndMarksOverTheLimitsAreRefusedAtOnce) {
  const std::string vrm = test::sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(vrm);
  Scene scene;
  ASSERT_TRUE(scene.addCharacter("godette", test::loadRigWithProfile(vrm, "Godette_vrm_v4.json")));
  Realizer realizer(scene);
  realizer.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
  std::string words;
  while (words.size() < 100000) words += "lorem ipsum ";
  std::string marks;
  for (int i = 0; i < 300; ++i) marks += "w <sync id='m" + std::to_string(i) + "'/> ";  // 600 characters, 300 marks
  std::string manyMarks;  // the reproducer's 5000 marks: over both limits
  for (int i = 0; i < 5000; ++i) manyMarks += "w <sync id='m" + std::to_string(i) + "'/> ";
  struct Case {
    std::string text, expected;
  };
  int block = 0;
  for (const Case& c : {Case{words, "more than the 2000 one line may have (limits::kMaxSpeechCharacters)"},
                        Case{marks, "300 word marks, more than the 256 one line may have (limits::kMaxSpeechMarks)"},
                        Case{manyMarks, "(limits::kMaxSpeechCharacters)"}, Case{"   ", "the text is empty"}}) {
    const auto started = std::chrono::steady_clock::now();
    const Schedule s = realizer.perform(
        "<bml id='long" + std::to_string(block++) + "'><speech id='s'><text>" + c.text + "</text></speech></bml>", "godette");
    for (int i = 0; i < 5; ++i) {
      scene.update(1.0 / 60.0);
      realizer.update();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::string warnings;
    for (const Warning& w : s.warnings) warnings += "'" + w.behaviorId + "': " + w.message + "\n";
    SCOPED_TRACE(c.expected);
    EXPECT_NE(warnings.find(c.expected), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("'s': "), std::string::npos) << "the warning does not name the behavior: " << warnings;
    // Refusing is checking a length: far under the 48 s that 100 KB of text took (a
    // bound for a machine under ASan and load, not a speed goal).
    EXPECT_LT(seconds, 20.0);
  }
}
