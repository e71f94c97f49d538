// Recorded voice lines through the C API (mn_scene_add_speech_line): a <speech> of the line's
// text is said with the recording (the speech callback gets its samples) and its phones drive
// the visemes; the engine's reader serves the files; bad files and arguments are refused
// with messages that name them.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "marionette/marionette.h"
#include "test_data.hpp"

#ifdef MARIONETTE_TEST_HAS_BML
namespace {

const std::string kGodette = marionette::test::sharedAsset("characters/Godette_vrm_v4.vrm");
const std::string kWav = marionette::test::sharedAsset("speech/arctic_a0009.wav");
const std::string kLab = marionette::test::sharedAsset("speech/arctic_a0009_phone.lab");
const char* kText = "He turned sharply, and faced Gregson across the table.";

struct Said {
  std::size_t samples = 0;
  int rate = 0;
  double duration = 0.0;
  int lines = 0;
  std::vector<std::string> visemes;
};

mn_scene* sceneWithGodette(Said& said) {
  mn_scene* scene = nullptr;
  EXPECT_EQ(mn_scene_create(&scene), MN_OK);
  EXPECT_EQ(mn_scene_set_speech_synthesis(scene, MN_SPEECH_INLINE), MN_OK);
  EXPECT_EQ(mn_scene_add_character(scene, "godette", kGodette.c_str(), nullptr, nullptr), MN_OK) << mn_scene_last_error(scene);
  EXPECT_EQ(mn_scene_set_speech_callback(scene, [](void* user, const mn_speech* s) {
    auto& out = *static_cast<Said*>(user);
    out.samples = s->sample_count, out.rate = s->sample_rate, out.duration = s->duration, ++out.lines;
  }, &said), MN_OK);
  EXPECT_EQ(mn_scene_set_viseme_callback(scene, [](void* user, const mn_viseme* v) {
    static_cast<Said*>(user)->visemes.emplace_back(v->viseme);
  }, &said), MN_OK);
  return scene;
}

void sayTheLine(mn_scene* scene) {
  const std::string bml = std::string("<bml id='b1'><speech id='s'><text>") + kText + "</text></speech></bml>";
  ASSERT_EQ(mn_scene_send_bml(scene, nullptr, bml.c_str()), MN_OK) << mn_scene_last_error(scene);
  for (int f = 0; f < 30; ++f) ASSERT_EQ(mn_scene_update(scene, 0.1), MN_OK);
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(CSpeechLines, ALineIsSaidWithItsRecordingAndItsPhonesDriveTheVisemes) {
  MARIONETTE_REQUIRE_FILE(kWav);
  Said said;
  mn_scene* scene = sceneWithGodette(said);
  ASSERT_EQ(mn_scene_add_speech_line(scene, kText, kWav.c_str(), kLab.c_str(), nullptr, nullptr), MN_OK)
      << mn_scene_last_error(scene);
  sayTheLine(scene);
  EXPECT_EQ(said.lines, 1);
  EXPECT_EQ(said.rate, 16000);
  EXPECT_EQ(said.samples, (bytesOf(kWav).size() - 44) / 2) << "the recording's own samples (16-bit mono, 44-byte header)";
  EXPECT_NEAR(said.duration, 3.095, 0.01);
  EXPECT_GT(said.visemes.size(), 10u);
  EXPECT_NE(std::find(said.visemes.begin(), said.visemes.end(), "aa"), said.visemes.end());
  mn_scene_destroy(scene);
}

TEST(CSpeechLines, TheEnginesReaderServesTheFiles) {
  MARIONETTE_REQUIRE_FILE(kWav);
  std::map<std::string, std::string> files{{"lines/a.wav", bytesOf(kWav)}, {"lines/a.lab", bytesOf(kLab)}};
  std::vector<std::string> asked;
  struct Reader {
    std::map<std::string, std::string>* files;
    std::vector<std::string>* asked;
  } reader{&files, &asked};
  Said said;
  mn_scene* scene = sceneWithGodette(said);
  const auto read = [](void* user, const char* path, mn_file_sink* sink) -> int {
    auto& r = *static_cast<Reader*>(user);
    r.asked->emplace_back(path);
    const auto it = r.files->find(path);
    if (it == r.files->end()) return 0;
    return mn_file_sink_write(sink, it->second.data(), it->second.size()) == MN_OK;
  };
  ASSERT_EQ(mn_scene_add_speech_line(scene, kText, "lines/a.wav", "lines/a.lab", read, &reader), MN_OK)
      << mn_scene_last_error(scene);
  EXPECT_EQ(asked.size(), 2u);
  sayTheLine(scene);
  EXPECT_EQ(said.lines, 1);
  EXPECT_GT(said.samples, 40000u);
  mn_scene_destroy(scene);
}

TEST(CSpeechLines, ALineAddedForATextSaidBeforeIsSaidFromThen) {
  MARIONETTE_REQUIRE_FILE(kWav);
  Said said;
  mn_scene* scene = sceneWithGodette(said);
  ASSERT_EQ(mn_scene_add_speech_line(scene, kText, kWav.c_str(), kLab.c_str(), nullptr, nullptr), MN_OK);
  sayTheLine(scene);
  ASSERT_NEAR(said.duration, 3.095, 0.01);
  // The same text again, now a 0.6 s line without audio (start,end,phoneme CSV).
  std::string csv = "0,0.3,HH\n0.3,0.6,AY\n";
  const auto read = [](void* user, const char*, mn_file_sink* sink) -> int {
    const auto* text = static_cast<const std::string*>(user);
    return mn_file_sink_write(sink, text->data(), text->size()) == MN_OK;
  };
  ASSERT_EQ(mn_scene_add_speech_line(scene, kText, nullptr, "short.csv", read, &csv), MN_OK) << mn_scene_last_error(scene);
  said = Said{};
  const std::string bml = std::string("<bml id='b2'><speech id='s'><text>") + kText + "</text></speech></bml>";
  ASSERT_EQ(mn_scene_send_bml(scene, nullptr, bml.c_str()), MN_OK) << mn_scene_last_error(scene);
  for (int f = 0; f < 20; ++f) ASSERT_EQ(mn_scene_update(scene, 0.1), MN_OK);
  EXPECT_NEAR(said.duration, 0.6, 0.01) << "the cached 3.1 s line must not be said again";
  EXPECT_EQ(said.samples, 0u);
  mn_scene_destroy(scene);
}

TEST(CSpeechLines, AReaderThatDestroysTheSceneDoesNotFreeItUnderTheCall) {
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  const auto read = [](void* user, const char*, mn_file_sink*) -> int {
    mn_scene_destroy(static_cast<mn_scene*>(user));  // waits for the call's end
    return 0;
  };
  EXPECT_EQ(mn_scene_add_speech_line(scene, kText, nullptr, "a.lab", read, scene), MN_ERROR_LOAD);
  EXPECT_EQ(mn_scene_update(scene, 0.1), MN_ERROR_INVALID_ARGUMENT) << "destroyed when the call returned";
}

TEST(CSpeechLines, BadFilesAndArgumentsAreRefusedByName) {
  Said said;
  mn_scene* scene = sceneWithGodette(said);
  EXPECT_EQ(mn_scene_add_speech_line(scene, kText, kWav.c_str(), "no/such/line.lab", nullptr, nullptr), MN_ERROR_LOAD);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("no/such/line.lab"), std::string::npos) << mn_scene_last_error(scene);
  EXPECT_EQ(mn_scene_add_speech_line(scene, kText, kLab.c_str(), kLab.c_str(), nullptr, nullptr), MN_ERROR_LOAD)
      << "a .lab is not a WAV";
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("arctic_a0009_phone.lab"), std::string::npos) << mn_scene_last_error(scene);
  EXPECT_EQ(mn_scene_add_speech_line(scene, "", kWav.c_str(), kLab.c_str(), nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_add_speech_line(scene, kText, kWav.c_str(), nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_add_speech_line(nullptr, kText, kWav.c_str(), kLab.c_str(), nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  // The refusals left the scene usable: a good line is added after them.
  EXPECT_EQ(mn_scene_add_speech_line(scene, kText, kWav.c_str(), kLab.c_str(), nullptr, nullptr), MN_OK)
      << mn_scene_last_error(scene);
  mn_scene_destroy(scene);
}

}  // namespace
#endif
