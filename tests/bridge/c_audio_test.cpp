// Sounds through the C API (<bmlt:audiofile>): the decoded WAV reaches the audio callback
// once, with its start on the scene clock; an interrupt stops it; the engine's reader and
// folder find the file; a missing file is a warning naming it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "marionette/marionette.h"
#include "test_data.hpp"

#ifdef MARIONETTE_TEST_HAS_BML
namespace {

const std::string kRobot = marionette::test::sharedAsset("characters/RobotExpressive.glb");
const std::string kRobotProfile = marionette::test::sourceFile("assets/profiles/RobotExpressive.json");
const std::string kNs = " xmlns:bmlt='http://hmi.ewi.utwente.nl/bmlt'";

struct Heard {
  struct Sound {
    mn_audio_event_kind kind;
    std::string character, behavior, file;
    std::size_t frames = 0;
    int channels = 0, rate = 0;
    double time = 0.0, duration = 0.0;
    float peak = 0.0f;
  };
  std::vector<Sound> sounds;
  std::vector<std::string> warnings;
};

void hear(void* user, const mn_audio* a) {
  Heard::Sound s{a->kind, a->character, a->behavior, a->file, a->frame_count, a->channels, a->sample_rate,
                 a->scene_time, a->duration, 0.0f};
  for (std::size_t i = 0; a->samples && i < a->frame_count * static_cast<std::size_t>(a->channels); ++i)
    s.peak = std::max(s.peak, a->samples[i] < 0 ? -a->samples[i] : a->samples[i]);
  static_cast<Heard*>(user)->sounds.push_back(std::move(s));
}

struct SceneWithRobot {
  mn_scene* scene = nullptr;
  Heard heard;
  SceneWithRobot() {
    EXPECT_EQ(mn_scene_create(&scene), MN_OK);
    EXPECT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), kRobotProfile.c_str(), nullptr), MN_OK)
        << mn_scene_last_error(scene);
    EXPECT_EQ(mn_scene_set_audio_callback(scene, hear, &heard), MN_OK);
    EXPECT_EQ(mn_scene_set_feedback_callback(scene, [](void* user, const mn_feedback* f) {
      if (f->kind == MN_FEEDBACK_WARNING) static_cast<Heard*>(user)->warnings.push_back(f->message);
    }, &heard), MN_OK);
  }
  ~SceneWithRobot() { mn_scene_destroy(scene); }
  void run(int frames) {
    for (int f = 0; f < frames; ++f) ASSERT_EQ(mn_scene_update(scene, 0.1), MN_OK);
  }
};

TEST(CAudio, TheCallbackGetsTheSoundOnceAndAnInterruptStopsIt) {
  MARIONETTE_REQUIRE_FILE(marionette::test::sharedAsset("speech/arctic_a0009.wav"));
  SceneWithRobot s;
  const std::string folder = marionette::test::sharedAsset("speech");
  ASSERT_EQ(mn_scene_set_audio_files(s.scene, folder.c_str(), nullptr, nullptr), MN_OK);
  s.run(5);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", ("<bml id='b'" + kNs + "><bmlt:audiofile id='a' start='0.5' "
                                                 "fileName='arctic_a0009.wav'/></bml>").c_str()),
            MN_OK)
      << mn_scene_last_error(s.scene);
  ASSERT_EQ(s.heard.sounds.size(), 1u);
  const Heard::Sound& play = s.heard.sounds[0];
  EXPECT_EQ(play.kind, MN_AUDIO_PLAY);
  EXPECT_EQ(play.character, "robot");
  EXPECT_EQ(play.behavior, "b:a");
  EXPECT_NE(play.file.find("speech/arctic_a0009.wav"), std::string::npos) << play.file;
  EXPECT_EQ(play.frames, 49520u);
  EXPECT_EQ(play.channels, 1);
  EXPECT_EQ(play.rate, 16000);
  EXPECT_DOUBLE_EQ(play.duration, 3.095);
  EXPECT_NEAR(play.time, 1.0, 1e-9) << "0.5 s after the block, sent at 0.5 s";
  EXPECT_NEAR(play.peak * 32768.0f, 21297.0f, 0.01f) << "ASSETS.md's peak";
  s.run(10);
  EXPECT_EQ(s.heard.sounds.size(), 1u);
  ASSERT_EQ(mn_scene_interrupt_block(s.scene, "b"), MN_OK);
  ASSERT_EQ(s.heard.sounds.size(), 2u);
  EXPECT_EQ(s.heard.sounds[1].kind, MN_AUDIO_STOP);
  EXPECT_EQ(s.heard.sounds[1].behavior, "b:a");
  EXPECT_NEAR(s.heard.sounds[1].time, 1.5, 1e-9);
  EXPECT_EQ(s.heard.sounds[1].frames, 0u);
  s.run(40);
  EXPECT_EQ(s.heard.sounds.size(), 2u) << "once";
  EXPECT_TRUE(s.heard.warnings.empty()) << s.heard.warnings.front();
}

TEST(CAudio, TheEnginesReaderGivesTheFileAndAMissingOneIsNamed) {
  SceneWithRobot s;
  const std::string wav = marionette::test::readFile(marionette::test::sharedAsset("speech/arctic_a0009.wav"));
  ASSERT_FALSE(wav.empty());
  struct Pak {
    std::string wav;
    std::vector<std::string> asked;
  } pak{wav, {}};
  ASSERT_EQ(mn_scene_set_audio_files(s.scene, "pak", [](void* user, const char* path, mn_file_sink* sink) {
    auto* p = static_cast<Pak*>(user);
    p->asked.push_back(path);
    if (std::string(path) != "pak/voice.wav") return 0;
    return mn_file_sink_write(sink, p->wav.data(), p->wav.size()) == MN_OK ? 1 : 0;
  }, &pak), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", ("<bml id='b'" + kNs + "><bmlt:audiofile id='a' fileName='voice.wav'/>"
                                                 "<bmlt:audiofile id='m' fileName='gone.wav'/></bml>").c_str()),
            MN_OK);
  EXPECT_EQ(pak.asked, (std::vector<std::string>{"pak/voice.wav", "pak/gone.wav"}));
  ASSERT_EQ(s.heard.sounds.size(), 1u);
  EXPECT_EQ(s.heard.sounds[0].frames, 49520u);
  ASSERT_EQ(s.heard.warnings.size(), 1u);
  EXPECT_NE(s.heard.warnings[0].find("CANNOT_CREATE_BEHAVIOR"), std::string::npos) << s.heard.warnings[0];
  EXPECT_NE(s.heard.warnings[0].find("pak/gone.wav: cannot read the WAV file"), std::string::npos) << s.heard.warnings[0];
  EXPECT_EQ(mn_scene_set_audio_files(nullptr, "x", nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_audio_callback(nullptr, hear, nullptr), MN_ERROR_INVALID_ARGUMENT);
}

}  // namespace
#endif
