// The C API as an FFI sees it: only marionette.h and the shared library. Null
// handles, bad arguments, missing files, bad BML, buffer sizes, layouts, callbacks,
// scene files, and scenes on two threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "marionette/marionette.h"
#include "marionette/version.h"
#include "test_data.hpp"

namespace {

const std::string kRobot = marionette::test::sharedAsset("characters/RobotExpressive.glb");
const std::string kRobotProfile = marionette::test::sourceFile("assets/profiles/RobotExpressive.json");

// A scene with the robot, freed at the end of the test.
struct SceneWithRobot {
  mn_scene* scene = nullptr;
  mn_character* robot = nullptr;
  SceneWithRobot() {
    EXPECT_EQ(mn_scene_create(&scene), MN_OK);
    EXPECT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), kRobotProfile.c_str(), &robot), MN_OK)
        << mn_scene_last_error(scene);
  }
  ~SceneWithRobot() { mn_scene_destroy(scene); }
};

std::string tempFile(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("mn_c_api_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace

// The loaded library says its version (the one this program was compiled against) and
// whether it is the variant with espeak-ng (these tests link it where the build has it).
TEST(CApi, VersionAndSpeechSynthesisOfTheLoadedLibrary) {
  EXPECT_STREQ(mn_version(), MARIONETTE_VERSION_STRING);
  EXPECT_EQ(std::string(mn_version()), std::to_string(MARIONETTE_VERSION_MAJOR) + "." +
                                           std::to_string(MARIONETTE_VERSION_MINOR) + "." +
                                           std::to_string(MARIONETTE_VERSION_PATCH));
#ifdef MARIONETTE_HAS_TTS
  EXPECT_EQ(mn_has_speech_synthesis(), 1);
#else
  EXPECT_EQ(mn_has_speech_synthesis(), 0);
#endif
}

TEST(CApi, NullHandlesAndArgumentsAreErrorsNotCrashes) {
  EXPECT_EQ(mn_scene_create(nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_scene_create"), std::string::npos);
  mn_scene_destroy(nullptr);
  EXPECT_EQ(mn_scene_update(nullptr, 0.1), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_scene_update: scene is NULL"), std::string::npos);
  EXPECT_EQ(mn_scene_load_file(nullptr, "x.json"), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_send_bml(nullptr, nullptr, "<bml/>"), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_add_character(nullptr, "a", "b", nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_feedback_callback(nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_viseme_callback(nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_log_callback(nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_time(nullptr), 0.0);
  EXPECT_EQ(mn_scene_character_count(nullptr), 0u);
  EXPECT_EQ(mn_scene_character_at(nullptr, 0), nullptr);
  float out[16];
  EXPECT_EQ(mn_character_palette(nullptr, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, out, 16), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_morph_weights(nullptr, out, 16), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_world_matrix(nullptr, out), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_position(nullptr, 0, 0, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_heading(nullptr, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_joint_count(nullptr), 0u);
  EXPECT_EQ(mn_character_joint_name(nullptr, 0), nullptr);
  EXPECT_EQ(mn_character_morph_name(nullptr, 0), nullptr);
  EXPECT_EQ(mn_character_find_joint(nullptr, "Head"), -1);
  EXPECT_STREQ(mn_character_name(nullptr), "");
  EXPECT_STREQ(mn_status_name(MN_ERROR_BML), "MN_ERROR_BML");

  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  EXPECT_STREQ(mn_scene_last_error(scene), "");
  EXPECT_EQ(mn_scene_load_file(scene, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_add_character(scene, nullptr, kRobot.c_str(), nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_add_character(scene, "", kRobot.c_str(), nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_send_bml(scene, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_update(scene, -1.0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_update(scene, NAN), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("dt must be finite"), std::string::npos);
  EXPECT_EQ(mn_scene_time(scene), 0.0);
  mn_character* c = reinterpret_cast<mn_character*>(1);
  EXPECT_EQ(mn_scene_find_character(scene, "nobody", &c), MN_ERROR_NOT_FOUND);
  EXPECT_EQ(c, nullptr);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("'nobody'"), std::string::npos);
  mn_scene_destroy(scene);
}

TEST(CApi, MissingAndBadFilesNameTheFile) {
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  mn_character* c = nullptr;
  EXPECT_EQ(mn_scene_add_character(scene, "x", "/no/such/robot.glb", nullptr, &c), MN_ERROR_IO);
  EXPECT_EQ(c, nullptr);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("/no/such/robot.glb"), std::string::npos);
  EXPECT_EQ(mn_scene_add_character(scene, "x", kRobot.c_str(), "/no/such/profile.json", &c), MN_ERROR_IO);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("/no/such/profile.json"), std::string::npos);
  EXPECT_EQ(mn_scene_load_file(scene, "/no/such/scene.json"), MN_ERROR_IO);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("/no/such/scene.json"), std::string::npos);
  // A file that exists but is not a character.
  const std::string notGlb = tempFile("bad.glb", "not a glTF file");
  EXPECT_EQ(mn_scene_add_character(scene, "x", notGlb.c_str(), nullptr, &c), MN_ERROR_LOAD);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find(notGlb), std::string::npos) << mn_scene_last_error(scene);
  // A scene file with a syntax error on line 3: the message names the file and the line.
  const std::string badScene = tempFile("bad_scene.json", "{\n  \"characters\": [\n    {\"name\": \"a\",, }\n  ]\n}\n");
  EXPECT_EQ(mn_scene_load_file(scene, badScene.c_str()), MN_ERROR_LOAD);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find(badScene + ":3:"), std::string::npos) << mn_scene_last_error(scene);
  EXPECT_EQ(mn_scene_character_count(scene), 0u);
  std::filesystem::remove(notGlb);
  std::filesystem::remove(badScene);
  mn_scene_destroy(scene);
}

TEST(CApi, CharactersJointsMorphsAndDuplicateNames) {
  SceneWithRobot s;
  ASSERT_NE(s.robot, nullptr);
  EXPECT_STREQ(mn_character_name(s.robot), "robot");
  EXPECT_EQ(mn_character_joint_count(s.robot), 43u);
  EXPECT_EQ(mn_character_find_joint(s.robot, "Head"), mn_character_find_joint(s.robot, mn_character_joint_name(s.robot, static_cast<size_t>(mn_character_find_joint(s.robot, "Head")))));
  EXPECT_GE(mn_character_find_joint(s.robot, "Head"), 0);
  EXPECT_EQ(mn_character_joint_name(s.robot, 43), nullptr);
  ASSERT_EQ(mn_character_morph_count(s.robot), 3u);
  EXPECT_STREQ(mn_character_morph_name(s.robot, 0), "Angry");
  EXPECT_EQ(mn_character_morph_name(s.robot, 3), nullptr);
  mn_character* again = nullptr;
  EXPECT_EQ(mn_scene_add_character(s.scene, "robot", kRobot.c_str(), nullptr, &again), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("'robot' exists already"), std::string::npos);
  mn_character* found = nullptr;
  EXPECT_EQ(mn_scene_find_character(s.scene, "robot", &found), MN_OK);
  EXPECT_EQ(found, s.robot);
  EXPECT_EQ(mn_scene_character_count(s.scene), 1u);
  EXPECT_EQ(mn_scene_character_at(s.scene, 0), s.robot);
  EXPECT_EQ(mn_scene_character_at(s.scene, 1), nullptr);
}

TEST(CApi, WrongBufferSizesWriteNothing) {
  SceneWithRobot s;
  ASSERT_EQ(mn_scene_update(s.scene, 0.1), MN_OK);
  const size_t joints = mn_character_joint_count(s.robot);
  for (mn_palette_layout layout : {MN_PALETTE_MAT4_COLUMN_MAJOR, MN_PALETTE_MAT4_ROW_MAJOR, MN_PALETTE_MAT3X4_ROW_MAJOR}) {
    const size_t need = joints * mn_palette_floats_per_joint(layout);
    std::vector<float> small(need - 1, 7.0f);
    EXPECT_EQ(mn_character_palette(s.robot, layout, 1, small.data(), small.size()), MN_ERROR_INVALID_ARGUMENT);
    for (float v : small) ASSERT_EQ(v, 7.0f);
    EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("needs " + std::to_string(need) + " floats"),
              std::string::npos) << mn_scene_last_error(s.scene);
    std::vector<float> exact(need, 7.0f);
    EXPECT_EQ(mn_character_palette(s.robot, layout, 1, exact.data(), exact.size()), MN_OK);
  }
  std::vector<float> out(joints * 16);
  EXPECT_EQ(mn_character_palette(s.robot, static_cast<mn_palette_layout>(3), 1, out.data(), out.size()),
            MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_palette_floats_per_joint(static_cast<mn_palette_layout>(3)), 0u);
  EXPECT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, nullptr, 1000), MN_ERROR_INVALID_ARGUMENT);
  float morphs[3] = {7, 7, 7};
  EXPECT_EQ(mn_character_morph_weights(s.robot, morphs, 2), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(morphs[0], 7.0f);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("has 3 morphs"), std::string::npos);
  EXPECT_EQ(mn_character_morph_weights(s.robot, morphs, 3), MN_OK);
}

TEST(CApi, LayoutsAndInverseBindAgree) {
  SceneWithRobot s;
  ASSERT_EQ(mn_character_set_position(s.robot, 1.0f, 2.0f, 3.0f), MN_OK);
  ASSERT_EQ(mn_character_set_heading(s.robot, 0.5f), MN_OK);
  EXPECT_EQ(mn_character_set_position(s.robot, NAN, 0, 0), MN_ERROR_INVALID_ARGUMENT);
  ASSERT_EQ(mn_scene_update(s.scene, 0.1), MN_OK);
  const size_t n = mn_character_joint_count(s.robot);
  std::vector<float> col(n * 16), row(n * 16), packed(n * 12), model(n * 16);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, col.data(), col.size()), MN_OK);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_ROW_MAJOR, 1, row.data(), row.size()), MN_OK);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT3X4_ROW_MAJOR, 1, packed.data(), packed.size()), MN_OK);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 0, model.data(), model.size()), MN_OK);
  float differs = 0.0f;
  for (size_t j = 0; j < n; ++j)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(row[j * 16 + r * 4 + c], col[j * 16 + c * 4 + r]);
        if (r < 3) {
          ASSERT_EQ(packed[j * 12 + r * 4 + c], col[j * 16 + c * 4 + r]);
        }
        differs = std::max(differs, std::fabs(model[j * 16 + c * 4 + r] - col[j * 16 + c * 4 + r]));
      }
  EXPECT_GT(differs, 1e-3f) << "model-space and skinning matrices must differ for a skinned character";
  float world[16];
  ASSERT_EQ(mn_character_world_matrix(s.robot, world), MN_OK);
  EXPECT_FLOAT_EQ(world[12], 1.0f);
  EXPECT_FLOAT_EQ(world[13], 2.0f);
  EXPECT_FLOAT_EQ(world[14], 3.0f);
  EXPECT_NEAR(world[0], std::cos(0.5f), 1e-6f);
}

#ifdef MARIONETTE_TEST_HAS_BML
namespace {
struct Heard {
  int feedback = 0, blockEnds = 0, warnings = 0, visemes = 0, logs = 0;
  std::string lastWarning, character;
  double lastVisemeTime = -1.0;
};
}  // namespace

TEST(CApi, BadBmlNamesTheBlockAndTheLine) {
  SceneWithRobot s;
  // The <head> element is not closed: malformed XML on line 2.
  const char* bad = "<bml id='broken' characterId='robot'>\n<head id='h' lexeme='NOD'>\n</bml>";
  EXPECT_EQ(mn_scene_send_bml(s.scene, "robot", bad), MN_ERROR_BML);
  const std::string message = mn_scene_last_error(s.scene);
  EXPECT_NE(message.find("bml block 'broken':3:"), std::string::npos) << message;  // where the parser stopped
  EXPECT_NE(message.find("PARSING_FAILURE"), std::string::npos) << message;
  // A block without an id fails as a whole too.
  EXPECT_EQ(mn_scene_send_bml(s.scene, nullptr, "<bml characterId='robot'><head lexeme='NOD'/></bml>"), MN_ERROR_BML);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("bml block (no id):1:1: error: PARSING_FAILURE"), std::string::npos)
      << mn_scene_last_error(s.scene);
  EXPECT_EQ(mn_scene_send_bml(s.scene, "nobody", "<bml id='b'><head id='h' lexeme='NOD'/></bml>"), MN_ERROR_NOT_FOUND);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("'nobody'"), std::string::npos);
}

TEST(CApi, CallbacksReportFeedbackVisemesAndWarnings) {
  SceneWithRobot s;
  Heard heard;
  ASSERT_EQ(mn_scene_set_feedback_callback(s.scene, [](void* user, const mn_feedback* f) {
    auto* h = static_cast<Heard*>(user);
    ++h->feedback;
    h->character = f->character;
    if (f->kind == MN_FEEDBACK_BLOCK_PROGRESS && std::string(f->sync_point) == "end" && std::string(f->block) == "b1") ++h->blockEnds;
    if (f->kind == MN_FEEDBACK_WARNING) {
      ++h->warnings;
      h->lastWarning = f->message;
    }
  }, &heard), MN_OK);
  ASSERT_EQ(mn_scene_set_viseme_callback(s.scene, [](void* user, const mn_viseme* v) {
    auto* h = static_cast<Heard*>(user);
    ++h->visemes;
    h->lastVisemeTime = v->time;
    EXPECT_STREQ(v->character, "robot");
    EXPECT_GT(std::string(v->viseme).size(), 0u);
  }, &heard), MN_OK);
  ASSERT_EQ(mn_scene_set_log_callback(s.scene, [](void* user, mn_log_level, const char*) { ++static_cast<Heard*>(user)->logs; },
                                      &heard), MN_OK);
  // A nod, a line, and an unknown behavior type (a non-fatal warning naming it).
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot",
                              "<bml id='b1'>\n<head id='nod' lexeme='NOD'/>\n<speech id='say'><text>Hello there.</text></speech>\n"
                              "<dance id='d' start='0' end='1'/>\n</bml>"),
            MN_OK) << mn_scene_last_error(s.scene);
  // The line is said in the background: the block, and its warning, come when it is said
  // (these frames run faster than real time: wait for it).
  EXPECT_EQ(heard.warnings, 0);
  ASSERT_EQ(mn_scene_wait_for_speech(s.scene), MN_OK);
  for (int f = 0; f < 240; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_GE(heard.warnings, 1);
  EXPECT_NE(heard.lastWarning.find("bml block 'b1':4:"), std::string::npos) << heard.lastWarning;
  EXPECT_EQ(heard.blockEnds, 1);
  EXPECT_EQ(heard.character, "robot");
#ifdef MARIONETTE_HAS_TTS
  EXPECT_GT(heard.visemes, 3);
  EXPECT_GT(heard.lastVisemeTime, 0.0);
#endif
  // Removed callbacks hear nothing more.
  const int before = heard.feedback;
  mn_scene_set_feedback_callback(s.scene, nullptr, nullptr);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='b2'><head id='n' lexeme='NOD'/></bml>"), MN_OK);
  for (int f = 0; f < 90; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(heard.feedback, before);
}

// Speech off the frame path: in the background a block with a line not said yet
// waits (send returns at once, no feedback), and starts with the update after it is
// said; inline, or after mn_scene_wait_for_speech, it is there at once. A mode that is
// not one is refused, naming the value.
TEST(CApi, SpeechIsSaidInTheBackgroundOrInlineAsAsked) {
  SceneWithRobot s;
  int predictions = 0;
  ASSERT_EQ(mn_scene_set_feedback_callback(s.scene, [](void* user, const mn_feedback* f) {
    if (f->kind == MN_FEEDBACK_PREDICTION) ++*static_cast<int*>(user);
  }, &predictions), MN_OK);
  EXPECT_EQ(mn_scene_set_speech_synthesis(s.scene, static_cast<mn_speech_synthesis>(7)), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("mode 7"), std::string::npos) << mn_scene_last_error(s.scene);
  EXPECT_EQ(mn_scene_set_speech_synthesis(nullptr, MN_SPEECH_INLINE), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_wait_for_speech(nullptr), MN_ERROR_INVALID_ARGUMENT);
#ifdef MARIONETTE_TEST_HAS_BML
  // Background (the default): held until said.
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='bg'><speech id='s'><text>Said in the background.</text></speech></bml>"),
            MN_OK) << mn_scene_last_error(s.scene);
  EXPECT_EQ(predictions, 0) << "a block waiting for its speech predicts nothing yet";
  for (int f = 0; f < 600 && predictions == 0; ++f) {
    ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
    if (predictions == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_GT(predictions, 0) << "the block never started";
  // Inline: at once.
  predictions = 0;
  ASSERT_EQ(mn_scene_set_speech_synthesis(s.scene, MN_SPEECH_INLINE), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='in'><speech id='s'><text>Said inline.</text></speech></bml>"), MN_OK);
  EXPECT_GT(predictions, 0);
  // Background again, then waited for: at once too.
  predictions = 0;
  ASSERT_EQ(mn_scene_set_speech_synthesis(s.scene, MN_SPEECH_BACKGROUND), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='w'><speech id='s'><text>Waited for.</text></speech></bml>"), MN_OK);
  ASSERT_EQ(mn_scene_wait_for_speech(s.scene), MN_OK);
  EXPECT_GT(predictions, 0);
#endif
}

TEST(CApi, SceneFileCharactersAndTheirBmlAtItsTime) {
  const std::string bml = tempFile("nod.xml", "<bml id='filed'><head id='n' lexeme='NOD'/></bml>");
  const std::string sceneFile = tempFile("scene.json", "{\"characters\": [{\"name\": \"r1\", \"asset\": \"" + kRobot +
                                                           "\"}, {\"name\": \"r2\", \"asset\": \"" + kRobot +
                                                           "\", \"position\": [2, 0, 0]}],\n"
                                                           " \"bml\": [{\"file\": \"" + bml + "\", \"time\": 0.5, \"character\": \"r2\"}]}");
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  ASSERT_EQ(mn_scene_load_file(scene, sceneFile.c_str()), MN_OK) << mn_scene_last_error(scene);
  ASSERT_EQ(mn_scene_character_count(scene), 2u);
  mn_character* r2 = nullptr;
  ASSERT_EQ(mn_scene_find_character(scene, "r2", &r2), MN_OK);
  EXPECT_EQ(mn_scene_character_at(scene, 1), r2);
  struct Seen {
    double start = -1.0;
    std::string character;
  } seen;
  mn_scene_set_feedback_callback(scene, [](void* user, const mn_feedback* f) {
    auto* s = static_cast<Seen*>(user);
    if (f->kind == MN_FEEDBACK_BLOCK_PROGRESS && std::string(f->sync_point) == "start") {
      s->start = f->scene_time;
      s->character = f->character;
    }
  }, &seen);
  for (int f = 0; f < 60; ++f) ASSERT_EQ(mn_scene_update(scene, 1.0 / 60.0), MN_OK);
  EXPECT_NEAR(seen.start, 0.5, 1e-9);
  EXPECT_EQ(seen.character, "r2");
  mn_scene_destroy(scene);
  std::filesystem::remove(bml);
  std::filesystem::remove(sceneFile);
}
#else
TEST(CApi, BmlIsUnsupportedWithoutTheRealizer) {
  SceneWithRobot s;
  EXPECT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='b'/>"), MN_ERROR_UNSUPPORTED);
  EXPECT_EQ(mn_scene_set_bml_dialect(s.scene, nullptr, "smartbody"), MN_ERROR_UNSUPPORTED);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("without BML"), std::string::npos);
}
#endif

TEST(CApi, ScenesOnTwoThreadsAreIndependent) {
  // Each thread its own scene; errors without a scene stay on their thread.
  std::vector<float> first[2];
  std::string threadError[2];
  auto run = [&](int k) {
    mn_scene* scene = nullptr;
    ASSERT_EQ(mn_scene_create(&scene), MN_OK);
    mn_character* c = nullptr;
    ASSERT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), nullptr, &c), MN_OK);
    if (k == 1) mn_scene_update(nullptr, 0.0);  // a failure without a scene, on thread 1 only
    for (int f = 0; f < 100; ++f) ASSERT_EQ(mn_scene_update(scene, 1.0 / 60.0), MN_OK);
    first[k].resize(mn_character_joint_count(c) * 16);
    ASSERT_EQ(mn_character_palette(c, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, first[k].data(), first[k].size()), MN_OK);
    threadError[k] = mn_scene_last_error(nullptr);
    mn_scene_destroy(scene);
  };
  std::thread a(run, 0), b(run, 1);
  a.join();
  b.join();
  EXPECT_EQ(first[0], first[1]);
  EXPECT_EQ(threadError[0], "");
  EXPECT_NE(threadError[1].find("mn_scene_update"), std::string::npos);
}

// ../shared/repro/README.md: a dt finite as a double but not as a float (1e39) became an
// infinite character clock, a NaN locomotion phase and a read past the key times.
TEST(CApi, DtTooLargeForTheClockIsRejectedAndTheWalkGoesOn) {
  SceneWithRobot s;
  ASSERT_NE(s.robot, nullptr);
#ifdef MARIONETTE_TEST_HAS_BML
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", R"(<bml id="walk"><locomotion id="l" target="2 2"/></bml>)"), MN_OK)
      << mn_scene_last_error(s.scene);
#endif
  for (int i = 0; i < 10; ++i) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  const double before = mn_scene_time(s.scene);
  for (const double dt : {1e39, 3600.5, 1e300, static_cast<double>(INFINITY)}) {
    EXPECT_EQ(mn_scene_update(s.scene, dt), MN_ERROR_INVALID_ARGUMENT) << dt;
    EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("at most 3600"), std::string::npos)
        << mn_scene_last_error(s.scene);
    EXPECT_EQ(mn_scene_time(s.scene), before) << "a rejected dt moved the clock";
  }
  EXPECT_EQ(mn_scene_update(s.scene, 3600.0), MN_OK) << "the limit itself is allowed";  // long pause, then on
  const std::size_t joints = mn_character_joint_count(s.robot);
  std::vector<float> palette(joints * 16);
  for (int i = 0; i < 30; ++i) {
    ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
    ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette.data(), palette.size()), MN_OK);
    for (float v : palette) ASSERT_TRUE(std::isfinite(v)) << "frame " << i;
  }
}

// ../shared/repro/scene_number_overflow_uncaught_out_of_range.json through the C API: an
// error naming the file and the number, not an internal error.
TEST(CApi, SceneFileWithANumberTooLargeNamesTheFile) {
  const std::string path = ::marionette::test::sharedDir() + "/repro/scene_number_overflow_uncaught_out_of_range.json";
  MARIONETTE_REQUIRE_FILE(path);
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  const mn_status status = mn_scene_load_file(scene, path.c_str());
  EXPECT_EQ(status, MN_ERROR_LOAD) << mn_status_name(status) << ": " << mn_scene_last_error(scene);
  const std::string error = mn_scene_last_error(scene);
  EXPECT_NE(error.find("scene_number_overflow_uncaught_out_of_range.json:1:"), std::string::npos) << error;
  EXPECT_NE(error.find("1e999"), std::string::npos) << error;
  mn_scene_destroy(scene);
}

// ../shared/repro/README.md: double destroy, use after destroy and a callback that
// destroys its own scene were uses after free; out-of-range enum values were undefined
// behaviour before the "unknown" branch (UBSan: invalid enum load). All are errors now.
TEST(CApi, DestroyedHandlesAreRefusedNotUsed) {
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  mn_character* robot = nullptr;
  ASSERT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), nullptr, &robot), MN_OK) << mn_scene_last_error(scene);
  mn_scene_destroy(scene);
  // The scene and its character are stale: every call says so (AddressSanitizer would
  // report a use after free if one of them read the freed scene).
  EXPECT_EQ(mn_scene_update(scene, 0.1), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_scene_update: scene is not a live handle"), std::string::npos)
      << mn_scene_last_error(nullptr);
  EXPECT_NE(std::string(mn_scene_last_error(scene)).find("not a live handle"), std::string::npos);
  EXPECT_EQ(mn_scene_time(scene), 0.0);
  EXPECT_EQ(mn_scene_character_count(scene), 0u);
  EXPECT_EQ(mn_scene_character_at(scene, 0), nullptr);
  mn_character* found = nullptr;
  EXPECT_EQ(mn_scene_find_character(scene, "robot", &found), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_send_bml(scene, nullptr, "<bml id='b'/>"), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_load_file(scene, "x.json"), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_log_callback(scene, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  float out[16 * 64];
  EXPECT_EQ(mn_character_palette(robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, out, 16 * 64), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_character_palette: character is not a live handle"),
            std::string::npos);
  EXPECT_EQ(mn_character_world_matrix(robot, out), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_position(robot, 0, 0, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_morph_weights(robot, out, 64), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_joint_count(robot), 0u);
  EXPECT_EQ(mn_character_joint_name(robot, 0), nullptr);
  EXPECT_EQ(mn_character_find_joint(robot, "Head"), -1);
  EXPECT_STREQ(mn_character_name(robot), "");
  // A second destroy is a no-op with an error, not a double free.
  mn_scene_destroy(scene);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("mn_scene_destroy: scene is not a live handle"), std::string::npos);
  // And a pointer that never was a scene.
  int notAScene = 0;
  EXPECT_EQ(mn_scene_update(reinterpret_cast<mn_scene*>(&notAScene), 0.1), MN_ERROR_INVALID_ARGUMENT);
  // A new scene does not take the stale one's address while it is held back.
  std::vector<mn_scene*> fresh(8, nullptr);
  for (mn_scene*& s : fresh) {
    ASSERT_EQ(mn_scene_create(&s), MN_OK);
    EXPECT_NE(s, scene);
  }
  for (mn_scene* s : fresh) mn_scene_destroy(s);
}

#ifdef MARIONETTE_TEST_HAS_BML  // the callback is BML feedback
namespace {
struct DestroyInCallback {
  mn_scene* scene = nullptr;
  int calls = 0;
  mn_status nestedUpdate = MN_OK;
};
void destroyOwnScene(void* user, const mn_feedback* /*feedback*/) {
  auto* d = static_cast<DestroyInCallback*>(user);
  if (d->calls++ == 0) {
    d->nestedUpdate = mn_scene_update(d->scene, 0.1);  // refused: the scene is mid-call
    mn_scene_destroy(d->scene);                        // deferred to the end of that call
  }
}
}  // namespace

TEST(CApi, ACallbackMayDestroyItsOwnScene) {
  DestroyInCallback d;
  ASSERT_EQ(mn_scene_create(&d.scene), MN_OK);
  ASSERT_EQ(mn_scene_add_character(d.scene, "robot", kRobot.c_str(), kRobotProfile.c_str(), nullptr), MN_OK);
  ASSERT_EQ(mn_scene_set_feedback_callback(d.scene, destroyOwnScene, &d), MN_OK);
  // Feedback comes during send_bml (predictions) and update (progress): the first destroys.
  (void)mn_scene_send_bml(d.scene, "robot", "<bml id='b1'><head id='h' lexeme='NOD'/></bml>");
  for (int i = 0; i < 10 && d.calls == 0; ++i) (void)mn_scene_update(d.scene, 1.0 / 30.0);
  ASSERT_GT(d.calls, 0) << "no feedback came: the test did not run its callback";
  EXPECT_EQ(d.nestedUpdate, MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_update(d.scene, 0.1), MN_ERROR_INVALID_ARGUMENT) << "the scene outlived the call that destroyed it";
}
#endif

TEST(CApi, OutOfRangeEnumValuesAreErrors) {
  for (int value : {9, 999, -1, -2147483647 - 1, 2147483647})
    EXPECT_STREQ(mn_status_name(static_cast<mn_status>(value)), "MN_ERROR_UNKNOWN_STATUS") << value;
  SceneWithRobot s;
  ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  std::vector<float> out(16 * mn_character_joint_count(s.robot));
  for (int value : {3, 7, -1, 2147483647}) {
    const auto layout = static_cast<mn_palette_layout>(value);
    EXPECT_EQ(mn_palette_floats_per_joint(layout), 0u) << value;
    EXPECT_EQ(mn_character_palette(s.robot, layout, 1, out.data(), out.size()), MN_ERROR_INVALID_ARGUMENT) << value;
    EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("unknown layout " + std::to_string(value)), std::string::npos)
        << mn_scene_last_error(s.scene);
  }
}

// The rig's clips by index; playing one moves the palette and the clip callback hears it
// start and stop; bad layers, names and options are errors naming what is wrong.
TEST(CApi, ClipsListPlayStopAndTheirEvents) {
  SceneWithRobot s;
  const size_t clips = mn_character_clip_count(s.robot);
  ASSERT_GE(clips, 10u);  // RobotExpressive: Idle, Walking, Running, Dance, ...
  bool idle = false;
  for (size_t i = 0; i < clips; ++i) {
    ASSERT_NE(mn_character_clip_name(s.robot, i), nullptr);
    EXPECT_GT(mn_character_clip_duration(s.robot, i), 0.0) << mn_character_clip_name(s.robot, i);
    idle = idle || std::string(mn_character_clip_name(s.robot, i)) == "Idle";
  }
  EXPECT_TRUE(idle);
  EXPECT_EQ(mn_character_clip_name(s.robot, clips), nullptr);
  EXPECT_EQ(mn_character_clip_duration(s.robot, clips), 0.0);
  EXPECT_EQ(mn_character_clip_count(nullptr), 0u);

  struct Events {
    std::vector<std::string> seen;
  } events;
  ASSERT_EQ(mn_scene_set_clip_callback(s.scene, [](void* user, const mn_clip_event* e) {
    static_cast<Events*>(user)->seen.push_back(std::string(e->kind == MN_CLIP_STARTED ? "started " : "stopped ") + e->clip +
                                               " by " + e->character);
  }, &events), MN_OK);
  const size_t floats = mn_character_joint_count(s.robot) * 16;
  std::vector<float> rest(floats), moving(floats);
  ASSERT_EQ(mn_scene_update(s.scene, 0.0), MN_OK);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, rest.data(), floats), MN_OK);
  mn_play_options o = mn_play_options_default();
  EXPECT_EQ(o.weight, 1.0f);
  EXPECT_EQ(o.loop, 1);
  o.fade_in = 0.2f;
  ASSERT_EQ(mn_character_play(s.robot, 0, "Dance", &o), MN_OK) << mn_scene_last_error(s.scene);
  for (int f = 0; f < 30; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, moving.data(), floats), MN_OK);
  float change = 0.0f;
  for (size_t k = 0; k < floats; ++k) change = std::max(change, std::fabs(moving[k] - rest[k]));
  EXPECT_GT(change, 0.01f) << "the dance must move the palette";
  ASSERT_EQ(mn_character_stop(s.robot, 0, 0.0f), MN_OK);
  EXPECT_EQ(mn_character_stop(s.robot, 3, 0.5f), MN_OK);  // nothing plays there: not an error
  ASSERT_EQ(events.seen.size(), 2u);
  EXPECT_EQ(events.seen[0], "started Dance by robot");
  EXPECT_EQ(events.seen[1], "stopped Dance by robot");

  EXPECT_EQ(mn_character_play(s.robot, 0, "Moonwalk", nullptr), MN_ERROR_NOT_FOUND);
  const std::string missing = mn_scene_last_error(s.scene);
  EXPECT_NE(missing.find("has no clip 'Moonwalk' (it has '"), std::string::npos) << missing;
  EXPECT_EQ(mn_character_play(s.robot, 8, "Idle", nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("layer 8 is not in 0..7"), std::string::npos);
  o.speed = std::nanf("");
  EXPECT_EQ(mn_character_play(s.robot, 0, "Idle", &o), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_play(s.robot, 0, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  // An options struct of another size (another header version, or not from the default) is
  // refused before it is read.
  mn_play_options sized = mn_play_options_default();
  EXPECT_EQ(sized.struct_size, sizeof(mn_play_options));
  sized.struct_size = sizeof(mn_play_options) - 8;
  EXPECT_EQ(mn_character_play(s.robot, 0, "Idle", &sized), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene))
                .find("mn_character_play: options->struct_size is " + std::to_string(sizeof(mn_play_options) - 8) +
                      ", but this library's mn_play_options is " + std::to_string(sizeof(mn_play_options)) + " bytes"),
            std::string::npos)
      << mn_scene_last_error(s.scene);
  EXPECT_EQ(mn_character_stop(s.robot, -1, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_play(nullptr, 0, "Idle", nullptr), MN_ERROR_INVALID_ARGUMENT);
}

// A removed character's handle is refused afterwards, never a crash; the others stay.
TEST(CApi, RemovedCharactersHandlesAreRefused) {
  SceneWithRobot s;
  mn_character* other = nullptr;
  ASSERT_EQ(mn_scene_add_character(s.scene, "other", kRobot.c_str(), kRobotProfile.c_str(), &other), MN_OK);
  ASSERT_EQ(mn_scene_character_count(s.scene), 2u);
  ASSERT_EQ(mn_scene_remove_character(s.scene, s.robot), MN_OK) << mn_scene_last_error(s.scene);
  EXPECT_EQ(mn_scene_character_count(s.scene), 1u);
  EXPECT_EQ(mn_scene_character_at(s.scene, 0), other);
  mn_character* found = nullptr;
  EXPECT_EQ(mn_scene_find_character(s.scene, "robot", &found), MN_ERROR_NOT_FOUND);
  EXPECT_EQ(mn_character_joint_count(s.robot), 0u);
  EXPECT_EQ(mn_character_play(s.robot, 0, "Idle", nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_remove_character(s.scene, s.robot), MN_ERROR_INVALID_ARGUMENT);
  for (int f = 0; f < 10; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_GT(mn_character_joint_count(other), 0u);
  s.robot = nullptr;
}

#ifdef MARIONETTE_TEST_HAS_BML
// BML interrupt from C: the block ends now (blockProgress end), an unknown id is named.
TEST(CApi, InterruptEndsABlock) {
  SceneWithRobot s;
  Heard heard;
  ASSERT_EQ(mn_scene_set_feedback_callback(s.scene, [](void* user, const mn_feedback* f) {
    auto* h = static_cast<Heard*>(user);
    if (f->kind == MN_FEEDBACK_BLOCK_PROGRESS && std::string(f->sync_point) == "end" && std::string(f->block) == "long") ++h->blockEnds;
  }, &heard), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='long'><head id='n' lexeme='NOD' start='0' end='30'/></bml>"), MN_OK);
  for (int f = 0; f < 30; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(heard.blockEnds, 0);
  ASSERT_EQ(mn_scene_interrupt_block(s.scene, "long"), MN_OK) << mn_scene_last_error(s.scene);
  for (int f = 0; f < 5; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(heard.blockEnds, 1);
  EXPECT_EQ(mn_scene_interrupt_block(s.scene, "long"), MN_ERROR_NOT_FOUND);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("no block 'long'"), std::string::npos);
  EXPECT_EQ(mn_scene_interrupt_block(s.scene, nullptr), MN_ERROR_INVALID_ARGUMENT);
}

// Scene objects from C (issue 24, 6): the engine's camera as a target.
TEST(CApi, SceneObjectsAreTargets) {
  SceneWithRobot s;
  std::vector<std::string> warnings;
  ASSERT_EQ(mn_scene_set_feedback_callback(s.scene, [](void* user, const mn_feedback* f) {
    if (f->kind == MN_FEEDBACK_WARNING) static_cast<std::vector<std::string>*>(user)->push_back(f->message);
  }, &warnings), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='n'><gaze id='g' target='camera' start='0' end='1'/></bml>"), MN_OK);
  ASSERT_FALSE(warnings.empty()) << "no camera yet";
  EXPECT_NE(warnings[0].find("no character or object 'camera'"), std::string::npos) << warnings[0];
  ASSERT_EQ(mn_scene_interrupt_block(s.scene, "n"), MN_OK);
  ASSERT_EQ(mn_scene_set_object(s.scene, "camera", 0.0f, 1.6f, 3.0f), MN_OK) << mn_scene_last_error(s.scene);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='g'><gaze id='g' target='camera' start='0' end='1'/></bml>"), MN_OK)
      << mn_scene_last_error(s.scene);
  for (int f = 0; f < 30; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(warnings.size(), 1u) << warnings.back();
  EXPECT_EQ(mn_scene_set_object(s.scene, "", 0, 0, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_object(s.scene, nullptr, 0, 0, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_object(s.scene, "x", std::nanf(""), 0, 0), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("'x' is not finite"), std::string::npos);
  EXPECT_EQ(mn_scene_remove_object(s.scene, "camera"), MN_OK);
  EXPECT_EQ(mn_scene_remove_object(s.scene, "camera"), MN_ERROR_NOT_FOUND);
  EXPECT_EQ(mn_scene_remove_object(nullptr, "camera"), MN_ERROR_INVALID_ARGUMENT);
}

// The dialect from the C API (issue 24): SmartBody's blocks without ids, for one character or
// the scene; a script's <event> message arrives as MN_FEEDBACK_EVENT.
TEST(CApi, BmlDialectAndEventMessages) {
  SceneWithRobot s;
  struct Got {
    std::vector<std::string> messages;
    int warnings = 0;
  } got;
  ASSERT_EQ(mn_scene_set_feedback_callback(s.scene, [](void* user, const mn_feedback* f) {
    auto* g = static_cast<Got*>(user);
    if (f->kind == MN_FEEDBACK_EVENT) g->messages.push_back(std::string(f->character) + ": " + f->message);
    if (f->kind == MN_FEEDBACK_WARNING) ++g->warnings;
  }, &got), MN_OK);
  const char* noIds = "<bml><head lexeme='NOD' start='0' end='0.2'/><event message='nodded' start='0.1'/></bml>";
  ASSERT_EQ(mn_scene_set_bml_dialect(s.scene, nullptr, "bml"), MN_OK);
  EXPECT_NE(mn_scene_send_bml(s.scene, "robot", noIds), MN_OK) << "strict: a block needs an id";
  ASSERT_EQ(mn_scene_set_bml_dialect(s.scene, "robot", "smartbody"), MN_OK) << mn_scene_last_error(s.scene);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", noIds), MN_OK) << mn_scene_last_error(s.scene);
  for (int f = 0; f < 20; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  ASSERT_EQ(got.messages.size(), 1u);
  EXPECT_EQ(got.messages[0], "robot: nodded");
  EXPECT_EQ(mn_scene_set_bml_dialect(s.scene, nullptr, "greta"), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(s.scene)).find("\"greta\" is not a BML dialect (auto, bml or smartbody)"),
            std::string::npos);
  EXPECT_EQ(mn_scene_set_bml_dialect(s.scene, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_scene_set_bml_dialect(nullptr, nullptr, "bml"), MN_ERROR_INVALID_ARGUMENT);
}
#endif

#if defined(MARIONETTE_TEST_HAS_BML) && defined(MARIONETTE_HAS_TTS)
// The engine gets each line's audio with its start on the scene clock.
TEST(CApi, SpeechCallbackHandsOverTheAudio) {
  SceneWithRobot s;
  struct Said {
    int lines = 0;
    size_t samples = 0;
    int rate = 0;
    double start = -1.0, duration = 0.0;
    std::string behavior;
  } said;
  ASSERT_EQ(mn_scene_set_speech_callback(s.scene, [](void* user, const mn_speech* sp) {
    auto* h = static_cast<Said*>(user);
    ++h->lines;
    h->samples = sp->samples ? sp->sample_count : 0;
    h->rate = sp->sample_rate;
    h->start = sp->start_time;
    h->duration = sp->duration;
    h->behavior = sp->behavior;
  }, &said), MN_OK);
  ASSERT_EQ(mn_scene_set_speech_synthesis(s.scene, MN_SPEECH_INLINE), MN_OK);
  ASSERT_EQ(mn_scene_send_bml(s.scene, "robot", "<bml id='b'><speech id='s'><text>Hello there.</text></speech></bml>"), MN_OK);
  for (int f = 0; f < 10; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  ASSERT_EQ(said.lines, 1);
  EXPECT_EQ(said.behavior, "b:s");
  EXPECT_GT(said.rate, 8000);
  EXPECT_NEAR(static_cast<double>(said.samples) / said.rate, said.duration, 0.05);
  EXPECT_GE(said.start, 0.0);
}
#endif

// The joint hierarchy and rest pose from C rebuild the model-space rest matrices the palette
// gives (no inverse bind, nothing playing), and the root-motion delta is the move of the
// world matrix over one update (and nothing when no clip moves the character).
TEST(CApi, JointParentsRestPoseAndRootMotionDelta) {
  SceneWithRobot s;
  ASSERT_NE(s.robot, nullptr);
  const size_t n = mn_character_joint_count(s.robot);
  EXPECT_EQ(mn_character_joint_parent(s.robot, 0), -1);
  EXPECT_EQ(mn_character_joint_parent(s.robot, n), -2);
  EXPECT_EQ(mn_character_joint_parent(nullptr, 0), -2);
  std::vector<float> rest(10 * n);
  EXPECT_EQ(mn_character_rest_pose(s.robot, rest.data(), rest.size() - 1), MN_ERROR_INVALID_ARGUMENT);
  ASSERT_EQ(mn_character_rest_pose(s.robot, rest.data(), rest.size()), MN_OK);
  ASSERT_EQ(mn_scene_update(s.scene, 0.0), MN_OK);
  std::vector<float> palette(16 * n);
  ASSERT_EQ(mn_character_palette(s.robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 0, palette.data(), palette.size()), MN_OK);
  glm::mat4 root(1.0f);
  ASSERT_EQ(mn_character_root_transform(s.robot, glm::value_ptr(root)), MN_OK);
  std::vector<glm::mat4> model(n);
  float worst = 0.0f;
  for (size_t j = 0; j < n; ++j) {
    const int parent = mn_character_joint_parent(s.robot, j);
    ASSERT_LT(parent, static_cast<int>(j));
    const float* r = &rest[10 * j];
    const glm::mat4 local = glm::translate(glm::mat4(1.0f), glm::vec3(r[0], r[1], r[2])) *
                            glm::mat4_cast(glm::quat(r[6], r[3], r[4], r[5])) * glm::scale(glm::mat4(1.0f), glm::vec3(r[7], r[8], r[9]));
    model[j] = (parent < 0 ? root : model[static_cast<size_t>(parent)]) * local;
    for (int k = 0; k < 16; ++k) worst = std::max(worst, std::fabs(glm::value_ptr(model[j])[k] - palette[16 * j + static_cast<size_t>(k)]));
  }
  EXPECT_LT(worst, 1e-4f);

  float delta[4] = {1, 1, 1, 1};
  ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 30.0), MN_OK);
  ASSERT_EQ(mn_character_root_motion_delta(s.robot, delta), MN_OK);
  EXPECT_EQ(delta[0], 0.0f);  // nothing moves it
  EXPECT_EQ(delta[2], 0.0f);
  // The demo scene's jumper plays CMU's 01_01 with root motion: it travels.
  const std::string demo = marionette::test::sourceFile("assets/scenes/demo.json");
  mn_scene* scene = nullptr;
  ASSERT_EQ(mn_scene_create(&scene), MN_OK);
  ASSERT_EQ(mn_scene_load_file(scene, demo.c_str()), MN_OK) << mn_scene_last_error(scene);
  mn_character* jumper = nullptr;
  ASSERT_EQ(mn_scene_find_character(scene, "jumper", &jumper), MN_OK);
  float before[16], after[16];
  float travelled = 0.0f;
  ASSERT_EQ(mn_scene_update(scene, 0.0), MN_OK);
  for (int f = 0; f < 60; ++f) {
    ASSERT_EQ(mn_character_world_matrix(jumper, before), MN_OK);
    ASSERT_EQ(mn_scene_update(scene, 1.0 / 30.0), MN_OK);
    ASSERT_EQ(mn_character_world_matrix(jumper, after), MN_OK);
    ASSERT_EQ(mn_character_root_motion_delta(jumper, delta), MN_OK);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(delta[k], after[12 + k] - before[12 + k], 1e-5f) << "frame " << f;
    EXPECT_NEAR(std::remainder(std::atan2(after[8], after[10]) - std::atan2(before[8], before[10]), 6.2831853f), delta[3], 1e-4f) << "frame " << f;
    travelled += std::hypot(delta[0], delta[2]);
  }
  EXPECT_GT(travelled, 0.1f) << "the clip's root motion moved it";
  mn_scene_destroy(scene);
  EXPECT_EQ(mn_character_root_motion_delta(s.robot, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_rest_pose(nullptr, rest.data(), rest.size()), MN_ERROR_INVALID_ARGUMENT);
}

// Animation events through mn_scene_set_event_callback: the robot's Walking sends each foot's
// touchdown and lift-off once per loop, with the clip, layer, weight and both times.
TEST(CApi, AnimationEventsThroughTheCallback) {
  SceneWithRobot s;
  EXPECT_EQ(mn_scene_set_event_callback(nullptr, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  double duration = 0.0;
  for (size_t i = 0; i < mn_character_clip_count(s.robot); ++i)
    if (std::string(mn_character_clip_name(s.robot, i)) == "Walking") duration = mn_character_clip_duration(s.robot, i);
  ASSERT_GT(duration, 0.0);
  struct Heard {
    std::vector<mn_animation_event> events;
    std::vector<std::string> names;
    std::string problems;
  } heard;
  ASSERT_EQ(mn_scene_set_event_callback(s.scene, [](void* user, const mn_animation_event* e) {
    auto& h = *static_cast<Heard*>(user);
    h.events.push_back(*e);
    h.names.emplace_back(e->name);
    const bool left = e->foot == MN_FOOT_LEFT, down = e->kind == MN_ANIMATION_EVENT_FOOT_DOWN;
    const std::string expected = std::string(left ? "left" : "right") + (down ? "_foot_down" : "_foot_up");
    if (e->kind != MN_ANIMATION_EVENT_MARKER && expected != e->name) h.problems += std::string("name ") + e->name + "; ";
    if (std::string(e->character) != "robot" || std::string(e->clip) != "Walking" || e->layer != 2)
      h.problems += "character, clip or layer; ";
  }, &heard), MN_OK);
  mn_play_options o = mn_play_options_default();
  o.weight = 0.75f;
  ASSERT_EQ(mn_character_play(s.robot, 2, "Walking", &o), MN_OK) << mn_scene_last_error(s.scene);
  const int frames = static_cast<int>(2.0 * duration * 60.0) - 1;  // two loops, short of the third's start
  for (int f = 0; f < frames; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(heard.problems, "");
  int count[2][2] = {};
  for (const mn_animation_event& e : heard.events) {
    ASSERT_NE(e.kind, MN_ANIMATION_EVENT_MARKER);  // the robot's clips have no markers
    ++count[e.foot == MN_FOOT_LEFT ? 0 : 1][e.kind == MN_ANIMATION_EVENT_FOOT_DOWN ? 0 : 1];
    EXPECT_FLOAT_EQ(e.weight, 0.75f);
    EXPECT_GE(e.clip_time, 0.0);
    EXPECT_LE(e.clip_time, duration);
    EXPECT_GE(e.scene_time, 0.0);
    EXPECT_LE(e.scene_time, frames / 60.0 + 1e-9);
  }
  // One down and one up of each foot in the first loop; each again one loop later.
  int firstLoop[2][2] = {};
  for (const mn_animation_event& e : heard.events) {
    if (e.scene_time >= duration) continue;
    ++firstLoop[e.foot == MN_FOOT_LEFT ? 0 : 1][e.kind == MN_ANIMATION_EVENT_FOOT_DOWN ? 0 : 1];
    if (e.scene_time + duration > frames / 60.0) continue;
    const bool again = std::any_of(heard.events.begin(), heard.events.end(), [&](const mn_animation_event& x) {
      return x.kind == e.kind && x.foot == e.foot && x.clip_time == e.clip_time &&
             std::fabs(x.scene_time - e.scene_time - duration) < 1e-6;
    });
    EXPECT_TRUE(again) << e.name << " at " << e.clip_time;
  }
  for (int foot = 0; foot < 2; ++foot)
    for (int kind = 0; kind < 2; ++kind) {
      EXPECT_EQ(firstLoop[foot][kind], 1) << foot << kind;
      EXPECT_GE(count[foot][kind], 1);
      EXPECT_LE(count[foot][kind], 2);
    }
  for (std::size_t i = 1; i < heard.events.size(); ++i) EXPECT_GE(heard.events[i].scene_time, heard.events[i - 1].scene_time);
  // A NULL function removes the callback.
  ASSERT_EQ(mn_scene_set_event_callback(s.scene, nullptr, nullptr), MN_OK);
  const std::size_t before = heard.events.size();
  for (int f = 0; f < 120; ++f) ASSERT_EQ(mn_scene_update(s.scene, 1.0 / 60.0), MN_OK);
  EXPECT_EQ(heard.events.size(), before);
}
