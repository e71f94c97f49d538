// AsapRealizer's <bmlt:audiofile> (issue 45, 6): parsed in its namespace, its WAV read when
// the block is realized, lasting as long as the WAV, handed to the scene's listeners once at
// its start and stopped by an earlier end, an interrupt or REPLACE; a file that cannot be
// played removes the behavior, and those that refer to it, with warnings naming it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "marionette/bml/realizer.hpp"
#include "marionette/bml/timed_files.hpp"
#include "synthetic_rig.hpp"
#include "wav_bytes.hpp"

using namespace marionette;
using namespace marionette::bml;
namespace fs = std::filesystem;

namespace {

const std::string kNs = " xmlns:bmlt=\"http://hmi.ewi.utwente.nl/bmlt\"";

// 0.5 s of 8 kHz 16-bit stereo: left a ramp, right silent.
std::string halfSecondStereo() {
  std::string data;
  for (int i = 0; i < 4000; ++i) {
    test::wav::put(data, static_cast<std::uint32_t>(i * 8), 2);
    test::wav::put(data, 0, 2);
  }
  return test::wav::makeWav(test::wav::fmtBody(1, 2, 8000, 16), data);
}

struct Sounds : SceneListener {
  struct Played {
    std::string character, id, file;
    double start = 0.0;
    int channels = 0, rate = 0;
    std::size_t frames = 0;
    float sample1 = 0.0f;
  };
  std::vector<Played> played;
  std::vector<std::pair<std::string, double>> stopped;
  void onAudio(const Character& c, std::string_view id, const speech::AudioClip& clip, std::string_view file,
               double start) override {
    played.push_back({c.name(), std::string(id), std::string(file), start, clip.channels, clip.sampleRate, clip.frames(),
                      clip.samples.size() > 2 ? clip.samples[2] : 0.0f});
  }
  void onAudioStopped(const Character&, std::string_view id, double time) override {
    stopped.emplace_back(std::string(id), time);
  }
};

struct AudioFileTest : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("marionette_audiofile_" + std::to_string(::getpid()));
  Scene scene;
  Realizer r{scene};
  std::vector<Feedback> feedback;
  Sounds sounds;

  AudioFileTest() {
    fs::create_directories(dir / "sub");
    write(dir / "beep.wav", halfSecondStereo());
    scene.addCharacter("robot", test::makeSyntheticRig());
    scene.addListener(&sounds);
    r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
    r.setForwardWarningsToScene(false);
    r.setFiles({}, dir.string());
    r.addFeedbackListener([this](const Feedback& f) { feedback.push_back(f); });
  }
  ~AudioFileTest() override {
    scene.removeListener(&sounds);
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  static void write(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  std::vector<Warning> warnings(WarningType type) const {
    std::vector<Warning> out;
    for (const Feedback& f : feedback)
      if (f.kind == Feedback::Kind::Warning && f.warning.type == type) out.push_back(f.warning);
    return out;
  }
  void step(double seconds, double dt = 0.05) {
    for (double t = 0; t < seconds - 1e-9; t += dt) {
      scene.update(dt);
      r.update();
    }
  }
};

TEST(AudioFileParsing, ReadInAsapRealizersNamespaceOnly) {
  const ParseResult p = parseBlock("<bml id=\"b\"" + kNs + " xmlns:x=\"urn:other\">"
                                   "<bmlt:audiofile id=\"a1\" start=\"1\" fileName=\"hello.wav\" volume=\"2\"/>"
                                   "<x:audiofile id=\"a2\" fileName=\"hello.wav\"/></bml>");
  ASSERT_TRUE(p.block);
  ASSERT_EQ(p.block->behaviors.size(), 1u);
  const Behavior& b = p.block->behaviors[0];
  EXPECT_EQ(b.type, "audiofile");
  ASSERT_NE(b.attribute("fileName"), nullptr);
  EXPECT_EQ(b.attribute("fileName")->value, "hello.wav");
  int custom = 0, unknownAttribute = 0;
  for (const Warning& w : p.warnings) {
    custom += w.type == WarningType::CustomBehaviorNotSupported && w.behaviorId == "a2";
    unknownAttribute += w.type == WarningType::CustomAttributeNotSupported && w.message.find("'volume'") != std::string::npos;
  }
  EXPECT_EQ(custom, 1) << "another namespace's audiofile is not AsapRealizer's";
  EXPECT_EQ(unknownAttribute, 1);
  EXPECT_EQ(resolveAudioFile("a/../b.wav", "/x/y"), "/x/y/b.wav");
  EXPECT_EQ(resolveAudioFile("/abs/c.wav", "/x"), "/abs/c.wav");
}

TEST_F(AudioFileTest, TheBlockSchedulesTheSoundsEndAtItsDuration) {
  const Schedule s = r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" start=\"0.25\" fileName=\"beep.wav\"/>"
                               "<wait id=\"h\" start=\"a1:end\" end=\"a1:end+1\"/></bml>", "robot");
  ASSERT_FALSE(s.failed);
  EXPECT_DOUBLE_EQ(*s.time("a1", "start"), 0.25);
  EXPECT_DOUBLE_EQ(*s.time("a1", "end"), 0.75) << "0.25 s + 4000 frames at 8 kHz";
  EXPECT_DOUBLE_EQ(*s.time("h", "start"), 0.75);
  EXPECT_TRUE(warnings(WarningType::CannotCreateBehavior).empty());
  const BehaviorTimeline::Entry* e = scene.findCharacter("robot")->behaviors().find("b1:a1");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->request.kind, BehaviorKind::Audio);
  EXPECT_EQ(e->request.channelBits(), BodyChannel::None) << "a sound takes no body channel";
  const AudioParameters* p = e->request.as<AudioParameters>();
  ASSERT_TRUE(p && p->clip);
  EXPECT_EQ(p->clip->frames(), 4000u);
  // Without a realizer (a scheduler alone), the behavior has the built-in default.
  EXPECT_DOUBLE_EQ(*scheduleText("<bml id=\"b\"" + kNs + "><bmlt:audiofile id=\"a\" fileName=\"x.wav\"/></bml>")
                        .time("a", "end"),
                   1.0);
}

TEST_F(AudioFileTest, TheListenerGetsTheSoundOnceAtItsStartAndItPlaysOut) {
  step(1.0);
  const double now = scene.time();
  ASSERT_FALSE(r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" start=\"0.25\" fileName=\"beep.wav\"/></bml>",
                         "robot").failed);
  ASSERT_EQ(sounds.played.size(), 1u) << "told when realized, before its start";
  const Sounds::Played& p = sounds.played[0];
  EXPECT_EQ(p.character, "robot");
  EXPECT_EQ(p.id, "b1:a1");
  EXPECT_EQ(p.file, (dir / "beep.wav").lexically_normal().generic_string());
  EXPECT_NEAR(p.start, now + 0.25, 1e-9);
  EXPECT_EQ(p.channels, 2);
  EXPECT_EQ(p.rate, 8000);
  EXPECT_EQ(p.frames, 4000u);
  EXPECT_FLOAT_EQ(p.sample1, 8.0f / 32768.0f) << "frame 1, left: decoded, channels kept";
  step(2.0);
  EXPECT_EQ(sounds.played.size(), 1u);
  EXPECT_TRUE(sounds.stopped.empty()) << "it played to its end: nothing to stop";
  r.interrupt("b1");  // long over: no stop either
  EXPECT_TRUE(sounds.stopped.empty());
}

TEST_F(AudioFileTest, AnEndBeforeTheSoundsCutsItThere) {
  const Schedule s = r.perform(
      "<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" start=\"0.1\" end=\"0.3\" fileName=\"beep.wav\"/></bml>", "robot");
  ASSERT_FALSE(s.failed);
  EXPECT_DOUBLE_EQ(*s.time("a1", "end"), 0.3);
  step(0.25);
  EXPECT_TRUE(sounds.stopped.empty());
  step(0.5);
  ASSERT_EQ(sounds.stopped.size(), 1u);
  EXPECT_EQ(sounds.stopped[0].first, "b1:a1");
  EXPECT_NEAR(sounds.stopped[0].second, 0.3, 1e-9) << "at the end, not at the frame that passed it";
  // An end after the sound's: it plays out, then silence; nothing is cut.
  ASSERT_FALSE(r.perform("<bml id=\"b2\"" + kNs + "><bmlt:audiofile id=\"a1\" end=\"2\" fileName=\"beep.wav\"/></bml>",
                         "robot").failed);
  step(2.5);
  EXPECT_EQ(sounds.stopped.size(), 1u);
}

TEST_F(AudioFileTest, InterruptAndReplaceStopTheSound) {
  ASSERT_FALSE(r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"beep.wav\"/></bml>", "robot").failed);
  step(0.2);
  ASSERT_TRUE(r.interrupt("b1"));
  ASSERT_EQ(sounds.stopped.size(), 1u);
  EXPECT_EQ(sounds.stopped[0].first, "b1:a1");
  EXPECT_NEAR(sounds.stopped[0].second, scene.time(), 1e-9);
  step(1.0);
  EXPECT_EQ(sounds.stopped.size(), 1u) << "once";

  ASSERT_FALSE(r.perform("<bml id=\"b2\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"beep.wav\"/></bml>", "robot").failed);
  step(0.1);
  ASSERT_FALSE(r.perform("<bml id=\"b3\" composition=\"REPLACE\"><head id=\"h\" lexeme=\"NOD\"/></bml>", "robot").failed);
  ASSERT_EQ(sounds.stopped.size(), 2u);
  EXPECT_EQ(sounds.stopped[1].first, "b2:a1");
  EXPECT_EQ(sounds.played.size(), 2u);
}

TEST_F(AudioFileTest, AMissingFileRemovesTheBehaviorAndThoseThatReferToIt) {
  const Schedule s = r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"nope.wav\"/>"
                               "<wait id=\"h\" start=\"a1:end\" end=\"a1:end+1\"/><wait id=\"h2\" start=\"0\" end=\"1\"/></bml>",
                               "robot");
  ASSERT_FALSE(s.failed) << "h2 still runs";
  EXPECT_EQ(s.find("a1"), nullptr);
  EXPECT_EQ(s.find("h"), nullptr);
  EXPECT_NE(s.find("h2"), nullptr);
  const auto cannot = warnings(WarningType::CannotCreateBehavior);
  ASSERT_EQ(cannot.size(), 1u);
  EXPECT_EQ(cannot[0].behaviorId, "a1");
  const std::string& m = cannot[0].message;
  EXPECT_NE(m.find("'a1' of block 'b1'"), std::string::npos) << m;
  EXPECT_NE(m.find((dir / "nope.wav").generic_string() + ": cannot read the WAV file"), std::string::npos) << m;
  EXPECT_NE(m.find("the behavior was removed"), std::string::npos) << m;
  const auto noTarget = warnings(WarningType::NoSuchTarget);
  ASSERT_EQ(noTarget.size(), 1u);
  EXPECT_EQ(noTarget[0].behaviorId, "h");
  EXPECT_NE(noTarget[0].message.find("'a1'"), std::string::npos) << noTarget[0].message;
  step(1.0);
  EXPECT_TRUE(sounds.played.empty());

  // Required: the block fails. No fileName at all: named too.
  const Schedule required = r.perform("<bml id=\"b2\"" + kNs + "><required><bmlt:audiofile id=\"a1\" fileName=\"nope.wav\"/>"
                                      "</required></bml>", "robot");
  EXPECT_TRUE(required.failed);
  (void)r.perform("<bml id=\"b3\"" + kNs + "><bmlt:audiofile id=\"a1\"/></bml>", "robot");
  EXPECT_NE(warnings(WarningType::CannotCreateBehavior).back().message.find("it has no fileName"), std::string::npos);
}

TEST_F(AudioFileTest, AMalformedFileIsNamedWithItsProblem) {
  const std::string wav = halfSecondStereo();
  write(dir / "cut.wav", wav.substr(0, 100));
  write(dir / "zero.wav", test::wav::makeWav(test::wav::fmtBody(1, 1, 0, 16), "abcd"));
  (void)r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"cut.wav\"/>"
                  "<bmlt:audiofile id=\"a2\" fileName=\"zero.wav\"/></bml>", "robot");
  const auto cannot = warnings(WarningType::CannotCreateBehavior);
  ASSERT_EQ(cannot.size(), 2u);
  EXPECT_NE(cannot[0].message.find("cut.wav: truncated: the data chunk declares 16000 bytes"), std::string::npos)
      << cannot[0].message;
  EXPECT_NE(cannot[1].message.find("zero.wav: sample rate 0 Hz"), std::string::npos) << cannot[1].message;
  EXPECT_TRUE(sounds.played.empty());
}

TEST_F(AudioFileTest, AnEnginesReaderAndTheBmlFilesFolderFindTheFile) {
  std::vector<std::string> asked;
  const std::string wav = halfSecondStereo();
  r.setFiles([&](const std::string& path, std::string& bytes, std::string&) {
    asked.push_back(path);
    bytes = wav;
    return true;
  }, "pak/sounds");
  ASSERT_FALSE(r.perform("<bml id=\"b1\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"../voice/hi.wav\"/></bml>",
                         "robot").failed);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(asked[0], "pak/voice/hi.wav");
  ASSERT_EQ(sounds.played.size(), 1u);

  // A scene file's BML file: its names are beside it.
  r.setFiles({}, "/nonexistent");
  write(dir / "sub" / "near.wav", wav);
  write(dir / "sub" / "say.xml", "<bml id=\"b2\"" + kNs + "><bmlt:audiofile id=\"a1\" fileName=\"near.wav\"/></bml>");
  TimedFiles files(r, {TimedFile{(dir / "sub" / "say.xml").string(), 0.0, "robot"}});
  std::vector<Diagnostic> reported;
  files.sendDue(scene.time(), [&](const Diagnostic& d) { reported.push_back(d); });
  EXPECT_TRUE(reported.empty()) << reported.front().message;
  ASSERT_EQ(sounds.played.size(), 2u);
  EXPECT_EQ(sounds.played[1].file, (dir / "sub" / "near.wav").lexically_normal().generic_string());
}

}  // namespace
