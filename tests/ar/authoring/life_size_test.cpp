// Life size (marionette_ar/authoring/life_size.hpp): the profile's "lifeHeight", else the file's
// own height when a person could be that tall (0.5 to 2.5 m, ends included), else 1.7 m with a
// note; and a session placing a character at that height.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "marionette_ar/authoring/authoring_session.hpp"
#include "marionette_ar/authoring/life_size.hpp"

namespace marionette::ar {
namespace {

using From = LifeSize::From;

TEST(LifeSize, TheProfileSaysFirstWhateverTheFileIs) {
  for (float file : {4.46f, 1.81f, 0.3f}) {
    const LifeSize s = lifeSizeHeight("robot", "/assets/RobotExpressive.glb", file, 1.2f);
    EXPECT_EQ(s.from, From::Profile) << file;
    EXPECT_EQ(s.metres, 1.2f) << file;
    EXPECT_TRUE(s.note.empty()) << s.note;
  }
  // A profile value that is no height (the loader keeps it in [0.05, 20]) is not one.
  for (float bad : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    const LifeSize s = lifeSizeHeight("bcn", "bcn.x", 1.81f, bad);
    EXPECT_EQ(s.from, From::File) << bad;
    EXPECT_EQ(s.metres, 1.81f) << bad;
  }
}

TEST(LifeSize, AFileAPersonCouldBeTallStandsAtItsOwnHeightEndsIncluded) {
  for (float file : {kPersonHeightMinMetres, 0.5f, 1.7f, 1.81f, 2.5f, kPersonHeightMaxMetres}) {
    const LifeSize s = lifeSizeHeight("bcn", "/usr/share/assimp/models/X/BCN_Epileptic.X", file, std::nullopt);
    EXPECT_EQ(s.from, From::File) << file;
    EXPECT_EQ(s.metres, file) << file;  // exactly: the session's scale is then metres / file = 1
    EXPECT_EQ(s.metres / file, 1.0f) << file;
    EXPECT_TRUE(s.note.empty()) << s.note;
  }
}

TEST(LifeSize, AnyOtherFileStandsAtTheDefaultHeightWithANoteSayingWhyAndTheFix) {
  for (float file : {std::nextafter(0.5f, 0.0f), std::nextafter(2.5f, 3.0f), 0.3f, 4.46f, 170.0f}) {
    const LifeSize s = lifeSizeHeight("robot", "/assets/RobotExpressive.glb", file, std::nullopt);
    EXPECT_EQ(s.from, From::Default) << file;
    EXPECT_EQ(s.metres, kDefaultLifeHeightMetres) << file;
    EXPECT_EQ(s.metres, 1.7f);
    EXPECT_NE(s.note.find("set \"lifeHeight\" in its profile"), std::string::npos) << s.note;
  }
  EXPECT_EQ(lifeSizeHeight("RobotExpressive", "/assets/RobotExpressive.glb", 4.4637f, std::nullopt).note,
            "RobotExpressive: its file RobotExpressive.glb is 4.46 m tall, not a person's height (0.5 to 2.5 m); "
            "placed at 1.7 m (set \"lifeHeight\" in its profile)");
  EXPECT_NE(lifeSizeHeight("ant", "", 0.004f, std::nullopt).note.find("ant: its file is 0.004 m tall"), std::string::npos);
  EXPECT_NE(lifeSizeHeight("giant", "g.glb", 170.0f, std::nullopt).note.find("is 170 m tall"), std::string::npos);
  for (float none : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    const LifeSize s = lifeSizeHeight("blob", "blob.glb", none, std::nullopt);
    EXPECT_EQ(s.from, From::Default);
    EXPECT_EQ(s.metres, 1.7f);
    EXPECT_NE(s.note.find("blob: its file blob.glb has no height to measure; placed at 1.7 m"), std::string::npos)
        << s.note;
  }
}

// The camera of authoring_session_test.cpp: 3 m back and 2 m up, looking at the origin.
AuthoringView view() {
  AuthoringView v;
  v.width = 640;
  v.height = 480;
  v.tracked = true;
  v.view = glm::lookAt(glm::vec3(0, 2, 3), glm::vec3(0), glm::vec3(0, 1, 0));
  v.projection = glm::perspective(glm::radians(60.0f), 640.0f / 480.0f, 0.05f, 100.0f);
  return v;
}

// The height a click places the entry at, and the session's scale for it.
float placedHeight(const CatalogueEntry& e, float* scale = nullptr) {
  AuthoringSession s({}, {e});
  Diagnostics d;
  EXPECT_TRUE(s.apply({.kind = ActionKind::PickCharacter, .name = e.name}, view(), d)) << d.format();
  EXPECT_TRUE(s.apply({.kind = ActionKind::Place, .pixel = {320, 300}}, view(), d)) << d.format();
  if (s.augmentation().characters.empty()) return 0.0f;
  const float k = s.augmentation().characters[0].placement.scale;
  if (scale) *scale = k;
  return e.heightMetres * k;
}

TEST(LifeSize, APlacedCharacterStandsAtItsLifeSizeAndTheSliderStillSetsMetres) {
  float scale = 0;
  // A person-sized file keeps scale 1, exactly (saved augmentations and the demo rely on it).
  EXPECT_FLOAT_EQ(placedHeight({"bcn", "/assets/bcn.x", 1.81f, {}}, &scale), 1.81f);
  EXPECT_EQ(scale, 1.0f);
  // A 4.46 m file without a profile height: 1.7 m, and the entry says why.
  const CatalogueEntry robot{"robot", "/assets/RobotExpressive.glb", 4.46f, {}};
  EXPECT_NEAR(placedHeight(robot, &scale), 1.7f, 1e-6f);
  EXPECT_NEAR(scale, 1.7f / 4.46f, 1e-7f);
  EXPECT_NE(robot.lifeSize().note.find("robot: its file RobotExpressive.glb is 4.46 m tall"), std::string::npos);
  // Its profile's height wins; no note.
  CatalogueEntry told = robot;
  told.profileLifeHeight = 1.2f;
  EXPECT_NEAR(placedHeight(told), 1.2f, 1e-6f);
  EXPECT_TRUE(told.lifeSize().note.empty());
  // The height slider sets metres from the file's own height, whatever life size was.
  AuthoringSession s({}, {robot});
  Diagnostics d;
  ASSERT_TRUE(s.apply({.kind = ActionKind::PickCharacter, .name = "robot"}, view(), d));
  ASSERT_TRUE(s.apply({.kind = ActionKind::Place, .pixel = {320, 300}}, view(), d));
  ASSERT_TRUE(s.apply({.kind = ActionKind::Height, .value = 0.4f}, view(), d));
  EXPECT_NEAR(4.46f * s.augmentation().characters[0].placement.scale, 0.4f, 1e-6f);
}

}  // namespace
}  // namespace marionette::ar
