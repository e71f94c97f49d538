// Speech in the runtime: recorded voice lines, the scene's speech service, and a
// speech behavior on a real character (Godette, VRM mouth shapes A I U E O).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "marionette/scene/scene.hpp"
#include "marionette/speech/recorded_speech.hpp"
#include "marionette/speech/speech_service.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

namespace marionette {
namespace {

using test::sharedAsset;

constexpr const char* kArcticText = "He turned sharply, and faced Gregson across the table.";

std::shared_ptr<speech::RecordedSpeech> arcticLine() {
  auto recorded = std::make_shared<speech::RecordedSpeech>();
  const std::string error = recorded->addLine(kArcticText, sharedAsset("speech/arctic_a0009.wav"),
                                              sharedAsset("speech/arctic_a0009.phones.txt"));
  EXPECT_EQ(error, "");
  return recorded;
}

// A backend that counts how often it is asked, to see the cache work.
struct CountingBackend : speech::SpeechBackend {
  int calls = 0;
  speech::SpeechRequest last;  // what it was asked, voice names mapped
  std::string_view name() const noexcept override { return "counting"; }
  speech::SpeechResult synthesize(const speech::SpeechRequest& r) override {
    ++calls;
    last = r;
    auto u = std::make_shared<speech::Utterance>();
    u->text = r.text;
    speech::Phoneme p;
    p.start = 0.1, p.end = 0.3, p.name = "aa";
    p.cls = speech::classifyPhoneme("aa", speech::PhonemeAlphabet::Arpabet).cls;
    u->phonemes.push_back(p);
    u->duration = 0.5;
    return {u, {}};
  }
};

TEST(RecordedSpeech, MatchesTextIgnoringCasePunctuationAndSpacing) {
  EXPECT_EQ(speech::RecordedSpeech::matchKey("  He turned   SHARPLY, and... faced!"), "he turned sharply and faced");
  EXPECT_EQ(speech::RecordedSpeech::matchKey("don't"), "dont");
  EXPECT_EQ(speech::RecordedSpeech::matchKey("?!"), "");
}

TEST(RecordedSpeech, ArcticLineKeepsItsAudioAndAlignment) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("speech/arctic_a0009.wav"));
  auto recorded = arcticLine();
  speech::SpeechRequest r;
  r.text = "he turned sharply and faced gregson across the table";
  const speech::SpeechResult said = recorded->synthesize(r);
  ASSERT_TRUE(said.utterance) << said.error;
  const speech::Utterance& u = *said.utterance;
  EXPECT_EQ(u.sampleRate, 16000);
  EXPECT_EQ(u.audio.size(), 49520u);                  // ASSETS.md: 49,520 frames
  EXPECT_NEAR(u.duration, 49520.0 / 16000.0, 1e-9);  // the audio's length
  ASSERT_EQ(u.phonemes.size(), 40u);                  // ASSETS.md: 40 segments
  EXPECT_NEAR(u.phonemes[1].start, 0.130, 1e-9);     // "hh" after 130 ms of silence
  EXPECT_EQ(u.phonemes[1].name, "hh");
  EXPECT_TRUE(u.phonemes.front().cls.pause);
}

TEST(RecordedSpeech, MarkTimesFollowTheLettersBeforeThem) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("speech/arctic_a0009.wav"));
  auto recorded = arcticLine();
  speech::SpeechRequest r;
  r.text = kArcticText;
  r.marks = {{"w0", 0}, {"w3", std::string(kArcticText).find("and")}, {"end", r.text.size()}};
  const speech::SpeechResult said = recorded->synthesize(r);
  ASSERT_TRUE(said.utterance) << said.error;
  const auto& m = said.utterance->marks;
  ASSERT_EQ(m.size(), 3u);
  // The voiced part: from "hh" (0.130 s) to the last phone before the final silence.
  EXPECT_NEAR(m[0].time, 0.130, 1e-6);
  EXPECT_GT(m[1].time, m[0].time);
  EXPECT_LT(m[1].time, m[2].time);
  // "and" follows "He turned sharply," (15 of 44 letters): the alignment puts its "ae" at 1.140 s.
  EXPECT_NEAR(m[1].time, 1.140, 0.15);
}

TEST(RecordedSpeech, UnknownTextAndBadFilesAreClearErrors) {
  speech::RecordedSpeech recorded;
  speech::SpeechRequest r;
  r.text = "nothing recorded";
  const speech::SpeechResult none = recorded.synthesize(r);
  EXPECT_FALSE(none.utterance);
  EXPECT_NE(none.error.find("nothing recorded"), std::string::npos);
  const std::string missing = recorded.addLine("hello", "/nonexistent/a.wav", sharedAsset("speech/arctic_a0009.phones.txt"));
  EXPECT_NE(missing.find("/nonexistent/a.wav"), std::string::npos) << missing;
  const std::string noWords = recorded.addLine("?!", "", sharedAsset("speech/arctic_a0009.phones.txt"));
  EXPECT_NE(noWords.find("no words"), std::string::npos) << noWords;
  EXPECT_EQ(recorded.lineCount(), 0u);
}

TEST(SpeechService, SaysEachRequestOnceAndAsksBackendsInOrder) {
  speech::SpeechService service;
  auto counting = std::make_shared<CountingBackend>();
  service.addBackend(arcticLine());
  service.addBackend(counting);
  speech::SpeechRequest a;
  a.text = "something new";
  const auto first = service.speak(a);
  const auto again = service.speak(a);
  ASSERT_TRUE(first.line) << first.error;
  EXPECT_EQ(first.line, again.line);  // cached: one synthesis for scheduling and realizing
  EXPECT_EQ(counting->calls, 1);
  EXPECT_EQ(first.line->backend, "counting");
  speech::SpeechRequest b;
  b.text = kArcticText;
  const auto recorded = service.speak(b);
  ASSERT_TRUE(recorded.line) << recorded.error;
  EXPECT_EQ(recorded.line->backend, "recorded");  // the recording wins over the later backend
  EXPECT_EQ(counting->calls, 1);
  EXPECT_GT(recorded.line->curves.frames, 0);
}

// Voice names of other engines: the scene's map (case-insensitive) turns them into the
// backend's; "default" fills a request without a voice and its fallback. A character's profile
// map applies first (withVoiceNames, as Character does), then the scene's.
TEST(SpeechService, VoiceNamesMapOtherEnginesVoices) {
  speech::SpeechService service;
  service.useDefaultSynthesizer(false);
  auto counting = std::make_shared<CountingBackend>();
  service.addBackend(counting);
  service.setVoiceNames({{"OpenMARY", "en-gb"}, {"default", "en-us"}});
  speech::SpeechRequest r;
  r.text = "one";
  r.voice = "openmary";
  ASSERT_TRUE(service.speak(r).line);
  EXPECT_EQ(counting->last.voice, "en-gb");
  EXPECT_EQ(counting->last.fallbackVoice, "en-us");
  r.text = "two";
  r.voice = "marytts";  // not mapped: asked as it is, the default as its fallback
  ASSERT_TRUE(service.speak(r).line);
  EXPECT_EQ(counting->last.voice, "marytts");
  EXPECT_EQ(counting->last.fallbackVoice, "en-us");
  r.text = "three";
  r.voice.clear();
  ASSERT_TRUE(service.speak(r).line);
  EXPECT_EQ(counting->last.voice, "en-us");
  // A character's own map first: its "openmary" wins over the scene's.
  r.text = "four";
  r.voice = "OpenMary";
  const std::map<std::string, std::string> profile = speech::voiceNameMap({{"OPENMARY", "de"}});
  ASSERT_TRUE(service.speak(speech::withVoiceNames(r, profile)).line);
  EXPECT_EQ(counting->last.voice, "de");
  // Mapped the same, said once: the cache keys on the mapped request.
  const int calls = counting->calls;
  r.text = "one";
  r.voice = "OPENMARY";
  ASSERT_TRUE(service.speak(r).line);
  EXPECT_EQ(counting->calls, calls);
}

TEST(SpeechService, WithoutBackendsSaysWhy) {
  speech::SpeechService service;
  service.useDefaultSynthesizer(false);
  speech::SpeechRequest r;
  r.text = "hello";
  const auto said = service.speak(r);
  EXPECT_FALSE(said.line);
  EXPECT_NE(said.error.find("no speech backend"), std::string::npos) << said.error;
}

TEST(SpeechService, WritesEachUtterancesAudioOnce) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "marionette_speech_service_test";
  std::filesystem::remove_all(dir);
  speech::SpeechService service;
  service.addBackend(arcticLine());
  service.setAudioDirectory(dir);
  speech::SpeechRequest r;
  r.text = kArcticText;
  const auto said = service.speak(r);
  ASSERT_TRUE(said.line) << said.error;
  ASSERT_FALSE(said.line->audioFile.empty());
  speech::WavAudio back;
  ASSERT_EQ(speech::readWav(said.line->audioFile, back), "");
  EXPECT_EQ(back.sampleRate, 16000);
  EXPECT_EQ(back.samples, said.line->utterance->audio);
  std::filesystem::remove_all(dir);
}

// Listens for what an engine needs to play speech in sync.
struct SpeechListener : SceneListener {
  int speeches = 0;
  double start = -1.0, duration = 0.0;
  std::size_t samples = 0;
  std::vector<std::pair<std::string, double>> visemes;
  void onSpeech(const Character&, std::string_view, const speech::Utterance& u, std::string_view, double at) override {
    ++speeches;
    start = at;
    duration = u.duration;
    samples = u.audio.size();
  }
  void onViseme(const Character&, std::string_view v, float, double t) override { visemes.emplace_back(std::string(v), t); }
};

BehaviorRequest speechRequest(const std::string& id, double start, double duration, const std::string& text) {
  BehaviorRequest r;
  r.id = id;
  r.kind = BehaviorKind::Speech;
  r.syncs = {{"start", start}, {"end", start + duration}};
  r.parameters = SpeechParameters{.text = text};
  return r;
}

struct GodetteSpeaks : ::testing::Test {
  Scene scene;
  SpeechListener listener;
  Character* godette = nullptr;
  std::shared_ptr<Rig> rig;
  std::vector<int> mouth;  // Godette's VRM mouth morphs: ah ih uu ee oh
  void SetUp() override {
    const std::string vrm = sharedAsset("characters/Godette_vrm_v4.vrm");
    MARIONETTE_REQUIRE_FILE(vrm);
    rig = test::loadRigWithProfile(vrm, "Godette_vrm_v4.json");
    ASSERT_TRUE(rig);
    godette = scene.addCharacter("godette", rig);
    scene.addListener(&listener);
    scene.speech().addBackend(arcticLine());
    const auto& names = rig->morphTargets();
    for (const char* m : {"ah", "ih", "uu", "ee", "oh"}) {
      auto it = std::find(names.begin(), names.end(), m);
      ASSERT_NE(it, names.end()) << m;
      mouth.push_back(static_cast<int>(it - names.begin()));
    }
  }
  float mouthOpen() const {
    float sum = 0.0f;
    for (int m : mouth) sum += godette->transformBuffer().morphWeights()[static_cast<std::size_t>(m)];
    return sum;
  }
};

TEST_F(GodetteSpeaks, VisemesMoveHerMouthInTimeWithTheRecording) {
  ASSERT_FALSE(godette->rig().joints().visemes.empty()) << "the VRM mouth shapes should map to lip-sync channels";
  const double start = 0.5;
  const BehaviorResult added = godette->addBehavior(speechRequest("s1", start, 3.095, kArcticText));
  ASSERT_TRUE(added.added && added.realized) << added.message;
  EXPECT_EQ(listener.speeches, 1);
  EXPECT_DOUBLE_EQ(listener.start, start);  // the engine plays the WAV from here
  EXPECT_EQ(listener.samples, 49520u);
  const speech::Utterance& u = *godette->behaviors().find("s1")->as<SpeechState>()->line->utterance;
  const double dt = 1.0 / 60.0;
  float widest = 0.0f;
  int closedInBilabials = 0, bilabials = 0;
  for (int f = 0; f < 300; ++f) {
    scene.update(f == 0 ? 0.0 : dt);
    const double local = scene.time() - start;
    widest = std::max(widest, mouthOpen());
    for (const speech::Phoneme& p : u.phonemes)
      if (p.cls.bilabial && local >= p.start && local < p.end) {
        ++bilabials;
        closedInBilabials += mouthOpen() < 0.15f ? 1 : 0;
      }
    for (float w : godette->transformBuffer().morphWeights()) ASSERT_TRUE(std::isfinite(w) && w >= 0.0f && w <= 1.0f);
    if (local < 0.0) {
      EXPECT_EQ(mouthOpen(), 0.0f) << "before the speech starts";
    }
  }
  EXPECT_GT(widest, 0.5f) << "vowels should open the mouth visibly";
  ASSERT_GT(bilabials, 0);  // "sharply", "table": p, b
  EXPECT_GE(closedInBilabials, 1) << "the lips close in P and B";
  EXPECT_LT(mouthOpen(), 0.05f) << "the mouth is at rest after the speech";
  // One viseme event per phoneme, at the phoneme's start on the scene clock.
  ASSERT_EQ(listener.visemes.size(), u.phonemes.size());
  for (std::size_t i = 0; i < u.phonemes.size(); ++i) {
    EXPECT_EQ(listener.visemes[i].first, speech::visemeName(u.phonemes[i].cls.viseme));
    EXPECT_NEAR(listener.visemes[i].second, start + u.phonemes[i].start, 1e-9);
  }
  EXPECT_TRUE(godette->stats().used(Controller::Speech));
}

TEST_F(GodetteSpeaks, TheLaterOfTwoOverlappingUtterancesMovesTheLips) {
  ASSERT_TRUE(godette->addBehavior(speechRequest("s1", 0.0, 3.095, kArcticText)).realized);
  auto counting = std::make_shared<CountingBackend>();  // one "aa" from 0.1 to 0.3 s
  scene.speech().addBackend(counting);
  ASSERT_TRUE(godette->addBehavior(speechRequest("s2", 1.0, 0.5, "aa")).realized);
  EXPECT_EQ(godette->behaviors().owner(BodyChannel::Voice, 1.2), &godette->behaviors().find("s2")->request);
  for (int f = 0; f < 72; ++f) scene.update(f == 0 ? 0.0 : 1.0 / 60.0);  // to t = 1.183 s: inside s2's "aa"
  const float duringS2 = mouthOpen();
  EXPECT_GT(duringS2, 0.3f);
}

TEST(SpeechWithoutBackend, FailsClearlyAndTheRestKeepsWorking) {
  const std::string vrm = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(vrm);
  Scene scene;
  scene.speech().useDefaultSynthesizer(false);  // as a build without TTS
  Character* c = scene.addCharacter("godette", test::loadRigWithProfile(vrm, "Godette_vrm_v4.json"));
  ASSERT_TRUE(c);
  const BehaviorResult said = c->addBehavior(speechRequest("s1", 0.0, 1.0, "Hello there."));
  EXPECT_TRUE(said.added);
  EXPECT_FALSE(said.realized);
  EXPECT_NE(said.message.find("no speech backend"), std::string::npos) << said.message;
  BehaviorRequest smile;
  smile.id = "smile";
  smile.kind = BehaviorKind::FaceLexeme;
  smile.syncs = {{"start", 0.0}, {"end", 2.0}};
  smile.parameters = FaceParameters{"SMILE"};
  ASSERT_TRUE(c->addBehavior(smile).realized);
  for (int f = 0; f < 60; ++f) scene.update(f == 0 ? 0.0 : 1.0 / 60.0);
  float any = 0.0f;
  for (float w : c->transformBuffer().morphWeights()) any = std::max(any, w);
  EXPECT_GT(any, 0.2f) << "the smile still shows";
}

// The middleware links no synthesizer (espeak-ng is marionette::tts_espeak, GPL): a scene
// that was given none says how to get one, in every build.
TEST(SpeechWithoutBackend, ASceneWithoutASynthesizerSaysHowToGetOne) {
  Scene scene;
  Character* c = scene.addCharacter("c", std::make_shared<Rig>(Asset{}));
  const BehaviorResult said = c->addBehavior(speechRequest("s1", 0.0, 1.0, "Hello there."));
  EXPECT_FALSE(said.realized);
  EXPECT_NE(said.message.find("no synthesizer was set (link marionette::tts_espeak"), std::string::npos) << said.message;
}

// Stiff and extreme frame steps: a line said at scene time 1e7 s, stepped by 0, 1/240,
// 0.5 and 10 s. Every phoneme's viseme is reported once, weights stay in [0, 1], and
// the mouth is at rest once the line is over, whatever the step.
TEST_F(GodetteSpeaks, AnyFrameStepAtAnySceneTime) {
  for (double dt : {1.0 / 240.0, 0.5, 10.0}) {
    Scene far;
    SpeechListener heard;
    far.addListener(&heard);
    far.speech().addBackend(arcticLine());
    Character* g = far.addCharacter("g", rig);
    far.update(1e7);
    const double start = far.time() + 0.25;
    ASSERT_TRUE(g->addBehavior(speechRequest("s", start, 3.095, kArcticText)).realized);
    for (int f = 0; far.time() < start + 4.0; ++f) {
      far.update(f % 5 == 0 ? 0.0 : dt);
      for (float w : g->transformBuffer().morphWeights()) ASSERT_TRUE(std::isfinite(w) && w >= 0.0f && w <= 1.0f);
    }
    EXPECT_EQ(heard.visemes.size(), 40u) << "dt " << dt;
    for (std::size_t i = 1; i < heard.visemes.size(); ++i) EXPECT_GE(heard.visemes[i].second, heard.visemes[i - 1].second);
    float open = 0.0f;
    for (float w : g->transformBuffer().morphWeights()) open = std::max(open, w);
    EXPECT_EQ(open, 0.0f) << "dt " << dt;
  }
}

#ifdef MARIONETTE_HAS_ASSIMP
TEST(SpeechJaw, TheJawOfACharacterWithOneOpensOnVowels) {
  const std::string x = test::assimpModel("X/BCN_Epileptic.X");
  MARIONETTE_REQUIRE_FILE(x);
  Scene scene;
  auto rig = test::loadRigWithProfile(x, "BCN_Epileptic.json");
  ASSERT_TRUE(rig);
  ASSERT_GE(rig->joints().jaw, 0);
  Character* c = scene.addCharacter("bcn", rig);
  scene.speech().addBackend(arcticLine());
  c->stop(0);
  scene.update(0.0);
  const auto jaw = static_cast<std::size_t>(rig->joints().jaw);
  const glm::quat rest = c->localPose()[jaw].rotation;
  ASSERT_TRUE(c->addBehavior(speechRequest("s1", 0.0, 3.095, kArcticText)).realized);
  // The lower lip hangs from the jaw: opening the mouth moves it down.
  const int lip = rig->skeleton().findJoint("B_LowerLip");
  ASSERT_GE(lip, 0);
  const float lipRest = c->transformBuffer().modelMatrices()[static_cast<std::size_t>(lip)][3].y;
  float largest = 0.0f, lipAtLargest = lipRest;
  for (int f = 0; f < 180; ++f) {
    scene.update(1.0 / 60.0);
    const float angle = 2.0f * std::acos(std::min(1.0f, std::abs(glm::dot(rest, c->localPose()[jaw].rotation))));
    if (angle > largest)
      largest = angle, lipAtLargest = c->transformBuffer().modelMatrices()[static_cast<std::size_t>(lip)][3].y;
  }
  EXPECT_GT(largest, 0.3f * kMaxJawOpenRadians) << "the jaw should open on the open vowels";
  EXPECT_LE(largest, kMaxJawOpenRadians + 1e-3f);
  EXPECT_LT(lipAtLargest, lipRest) << "the jaw opens downward, not up into the skull";
}
#endif

// A listener that changes the timeline from inside onViseme: it cancels a speech that has not
// started (which erases it, so the entries after it move down) and adds another. The speech
// pass finds each entry again by its order, so the two lines speaking now each send every one
// of their visemes once, and neither advances the other's.
TEST_F(GodetteSpeaks, AListenerThatCancelsAndAddsDuringVisemesMovesNoOtherSpeech) {
  struct Meddler : SceneListener {
    Character* who = nullptr;
    bool done = false;
    std::vector<double> times;  // scene time of each viseme
    void onViseme(const Character&, std::string_view, float, double t) override {
      times.push_back(t);
      if (done || !who) return;
      done = true;
      who->cancelBehavior("future", 0.2);  // not started: erased, "now" and "other" move down
      who->addBehavior(speechRequest("added", 20.0, 3.095, kArcticText));
    }
  } meddler;
  meddler.who = godette;
  scene.addListener(&meddler);
  constexpr double kOther = 0.5;  // "other" starts half a second after "now" (the same line)
  ASSERT_TRUE(godette->addBehavior(speechRequest("future", 10.0, 3.095, kArcticText)).realized);
  ASSERT_TRUE(godette->addBehavior(speechRequest("now", 0.0, 3.095, kArcticText)).realized);
  ASSERT_TRUE(godette->addBehavior(speechRequest("other", kOther, 3.095, kArcticText)).realized);
  const BehaviorTimeline::Entry* now = godette->behaviors().find("now");
  ASSERT_NE(now, nullptr);
  ASSERT_NE(now->as<SpeechState>(), nullptr);
  const std::vector<speech::Phoneme> phonemes = now->as<SpeechState>()->line->utterance->phonemes;
  ASSERT_GT(phonemes.size(), 10u);
  float widest = 0.0f;
  for (int f = 0; f < 240; ++f) {  // 0 .. 4 s: both lines end
    scene.update(1.0 / 60.0);
    widest = std::max(widest, mouthOpen());
  }
  EXPECT_TRUE(meddler.done);
  EXPECT_EQ(godette->behaviors().find("future"), nullptr);
  EXPECT_NE(godette->behaviors().find("added"), nullptr);
  // Every phoneme of both lines, once, each at its own line's time: the visemes before
  // "other" starts are exactly those of "now" (none of "other"'s sent early, none skipped).
  std::vector<double> expected;
  for (const speech::Phoneme& p : phonemes) expected.push_back(p.start), expected.push_back(kOther + p.start);
  std::sort(expected.begin(), expected.end());
  std::vector<double> got = meddler.times;
  std::sort(got.begin(), got.end());
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-9) << i;
  EXPECT_GT(widest, 0.2f);  // the lips moved
}

}  // namespace
}  // namespace marionette
