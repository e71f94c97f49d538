// Blend spaces through the C API (marionette.h alone): the robot's profile space by
// name, bad handles and arguments named in the message, and a blend that moves the
// pose differently from either clip alone.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "marionette/marionette.h"
#include "test_data.hpp"

namespace {

const std::string kRobot = marionette::test::sharedAsset("characters/RobotExpressive.glb");
const std::string kRobotProfile = marionette::test::sourceFile("assets/profiles/RobotExpressive.json");

struct Robot {
  mn_scene* scene = nullptr;
  mn_character* robot = nullptr;
  Robot() {
    EXPECT_EQ(mn_scene_create(&scene), MN_OK);
    EXPECT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), kRobotProfile.c_str(), &robot), MN_OK)
        << mn_scene_last_error(scene);
  }
  ~Robot() { mn_scene_destroy(scene); }
  std::vector<float> palette() const {
    std::vector<float> out(mn_character_joint_count(robot) * 16);
    EXPECT_EQ(mn_character_palette(robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 0, out.data(), out.size()), MN_OK);
    return out;
  }
};

bool says(const mn_scene* scene, const char* text) {
  return std::string(mn_scene_last_error(scene)).find(text) != std::string::npos;
}

float largestDifference(const std::vector<float>& a, const std::vector<float>& b) {
  float d = 0.0f;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::fabs(a[i] - b[i]));
  return d;
}

}  // namespace

TEST(CApiBlendSpaces, BadHandlesAndArgumentsAreNamedErrors) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  EXPECT_EQ(mn_character_blend_space_count(nullptr), 0u);
  EXPECT_EQ(mn_character_blend_space_name(nullptr, 0), nullptr);
  EXPECT_EQ(mn_character_play_blend(nullptr, 0, "locomotion", nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(nullptr, "mn_character_play_blend: character"));
  EXPECT_EQ(mn_character_set_blend_parameter(nullptr, 0, 0.0f, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(nullptr, "mn_character_set_blend_parameter: character"));

  Robot r;
  ASSERT_TRUE(r.robot);
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(r.scene, "blend_space is NULL"));
  EXPECT_EQ(mn_character_play_blend(r.robot, 8, "locomotion", nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(r.scene, "layer 8 is not in 0..7"));
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, "sprint", nullptr), MN_ERROR_NOT_FOUND);
  EXPECT_TRUE(says(r.scene, "has no blend space 'sprint' (it has 'locomotion')")) << mn_scene_last_error(r.scene);
  mn_play_options o = mn_play_options_default();
  o.additive = 1;
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, "locomotion", &o), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(r.scene, "additive"));
  o = mn_play_options_default();
  o.speed = NAN;
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, "locomotion", &o), MN_ERROR_INVALID_ARGUMENT);
  o = mn_play_options_default();
  o.struct_size = 8;
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, "locomotion", &o), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_blend_parameter(r.robot, 0, 0.5f, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(says(r.scene, "layer 0 plays no blend space"));
  ASSERT_EQ(mn_character_play_blend(r.robot, 0, "locomotion", nullptr), MN_OK) << mn_scene_last_error(r.scene);
  EXPECT_EQ(mn_character_set_blend_parameter(r.robot, 0, INFINITY, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_blend_parameter(r.robot, -1, 0.0f, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_blend_parameter(r.robot, 0, 0.5f, 0.0f), MN_OK);
  // A removed character is refused, not a crash.
  ASSERT_EQ(mn_scene_remove_character(r.scene, r.robot), MN_OK);
  EXPECT_EQ(mn_character_play_blend(r.robot, 0, "locomotion", nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_character_set_blend_parameter(r.robot, 0, 0.5f, 0.0f), MN_ERROR_INVALID_ARGUMENT);
  r.robot = nullptr;
}

TEST(CApiBlendSpaces, TheProfileSpacePlaysAndItsParameterMovesThePose) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  ASSERT_EQ(mn_character_blend_space_count(nullptr), 0u);
  std::vector<float> pose[3];
  for (int k = 0; k < 3; ++k) {  // walk alone, run alone, halfway: at the same scene time
    Robot r;
    ASSERT_TRUE(r.robot);
    ASSERT_EQ(mn_character_blend_space_count(r.robot), 1u);
    EXPECT_STREQ(mn_character_blend_space_name(r.robot, 0), "locomotion");
    EXPECT_EQ(mn_character_blend_space_name(r.robot, 1), nullptr);
    ASSERT_EQ(mn_character_play_blend(r.robot, 2, "locomotion", nullptr), MN_OK) << mn_scene_last_error(r.scene);
    const float x = k == 0 ? 0.0f : k == 1 ? 100.0f : 3.93f;  // clamped to the walk, to the run; between
    for (int f = 0; f < 20; ++f) {
      ASSERT_EQ(mn_character_set_blend_parameter(r.robot, 2, x, 0.0f), MN_OK);
      ASSERT_EQ(mn_scene_update(r.scene, 1.0 / 60.0), MN_OK);
    }
    pose[k] = r.palette();
    for (float v : pose[k]) ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_GT(largestDifference(pose[0], pose[1]), 0.01f);
  EXPECT_GT(largestDifference(pose[2], pose[0]), 0.01f);
  EXPECT_GT(largestDifference(pose[2], pose[1]), 0.01f);
}
