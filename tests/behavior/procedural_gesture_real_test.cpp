// Procedural gestures on real characters through their shipped profiles (issue 24, 7):
// every lexeme of the set on RobotExpressive (playing Idle) and Godette (the T-pose). At
// the stroke each hand is where the lexeme puts it (in the character's own frame, scaled by
// its arm); after the end the arms are back where the posture holds them; nothing is NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "marionette/behavior/procedural_gesture.hpp"
#include "marionette/core/text_file.hpp"
#include "marionette/rig/gesture_vocabulary.hpp"
#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

BehaviorRequest gesture(const std::string& lexeme, PointingArms hands = PointingArms::Nearest) {
  BehaviorRequest r;
  r.id = "g:" + lexeme;
  r.kind = BehaviorKind::Gesture;
  r.parameters = GestureParameters{lexeme, hands, {}};
  r.channels = BodyChannel::Hands;
  r.syncs = {{"start", 0.0}, {"ready", 0.3}, {"strokeStart", 0.5}, {"stroke", 0.7},
             {"strokeEnd", 0.9}, {"relax", 1.4}, {"end", 1.7}};
  return r;
}

glm::vec3 modelOf(const Character& c, int joint) {
  return glm::vec3(c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)][3]);
}

void checkEveryLexeme(const char* asset, const char* profile) {
  MARIONETTE_REQUIRE_FILE(sharedAsset(asset));
  auto rig = loadRigWithProfile(sharedAsset(asset), profile);
  ASSERT_TRUE(rig);
  for (std::string_view name : proceduralGestureLexemes()) {
    const std::string lexeme(name);
    SCOPED_TRACE(std::string(asset) + " " + lexeme);
    Scene scene, still;
    Character* c = scene.addCharacter("c", rig);
    Character* s = still.addCharacter("c", rig);
    if (!rig->clips().empty()) {
      c->play(0, rig->clips().front());
      s->play(0, rig->clips().front());
    }
    const BehaviorResult added = c->addBehavior(gesture(lexeme));
    ASSERT_TRUE(added.realized) << added.message;
    const GestureState* st = c->behaviors().find("g:" + lexeme)->as<GestureState>();
    ASSERT_NE(st, nullptr);
    for (int f = 0; f < 42; ++f) {  // to 0.7 s: the stroke
      scene.update(1.0 / 60.0);
      still.update(1.0 / 60.0);
    }
    for (int side = 0; side < 2; ++side) {
      if (!st->arm[side]) continue;
      const LimbIk& limb = st->limb[side];
      const glm::vec3 want = proceduralGestureHand(*st, side, scene.time(), modelOf(*c, limb.upper));
      const glm::vec3 hand = limbEndModel(rig->skeleton(), c->localPose(), limb);
      EXPECT_LT(glm::length(hand - want), 0.03f * st->armLength[side]) << "side " << side;
      EXPECT_GT(glm::length(hand - limbEndModel(rig->skeleton(), s->localPose(), limb)), 0.05f * st->armLength[side])
          << "side " << side << ": the hand moved";
    }
    EXPECT_TRUE(c->stats().used(Controller::Gesture));
    for (int f = 0; f < 66; ++f) {  // past the end (1.7 s)
      scene.update(1.0 / 60.0);
      still.update(1.0 / 60.0);
      for (const Transform& t : c->localPose())
        ASSERT_TRUE(std::isfinite(t.rotation.w) && std::isfinite(t.translation.x)) << "frame " << f;
    }
    const auto a = c->localPose(), b = s->localPose();
    for (std::size_t j = 0; j < a.size(); ++j)
      EXPECT_LT(glm::length(glm::vec4(a[j].rotation.x - b[j].rotation.x, a[j].rotation.y - b[j].rotation.y,
                                      a[j].rotation.z - b[j].rotation.z, a[j].rotation.w - b[j].rotation.w)),
                1e-5f)
          << "joint " << j << ": back to the posture";
  }
}

}  // namespace

TEST(ProceduralGesture, EveryLexemeOnRobotExpressive) {
  checkEveryLexeme("characters/RobotExpressive.glb", "RobotExpressive.json");
}

TEST(ProceduralGesture, EveryLexemeOnGodette) { checkEveryLexeme("characters/Godette_vrm_v4.vrm", "Godette_vrm_v4.json"); }

// What cannot be done is said: a lexeme outside the set (listing it), hands the rig lacks.
TEST(ProceduralGesture, UnknownLexemesAndMissingArmsAreNamed) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  const BehaviorResult unknown = c->addBehavior(gesture("FROBNICATE"));
  EXPECT_FALSE(unknown.realized);
  EXPECT_NE(unknown.message.find("gesture lexeme 'FROBNICATE' names no clip of the character and no procedural gesture (BEAT"),
            std::string::npos)
      << unknown.message;
  EXPECT_TRUE(hasProceduralGesture("beat")) << "case-insensitive";
  EXPECT_GE(proceduralGestureLexemes().size(), 13u);
  // Both hands asked for a one-handed lexeme: both move.
  ASSERT_TRUE(c->addBehavior(gesture("BEAT", PointingArms::Both)).realized);
  const GestureState* st = c->behaviors().find("g:BEAT")->as<GestureState>();
  EXPECT_TRUE(st->arm[0] && st->arm[1]);
  // A character without arms in its profile.
  CharacterProfile armless = rig->profile();
  armless.leftArm = {};
  armless.rightArm = {};
  auto noArms = std::make_shared<Rig>(*rig);
  noArms->setProfile(armless);
  Character* d = scene.addCharacter("d", noArms);
  const BehaviorResult none = d->addBehavior(gesture("WAVE"));
  EXPECT_FALSE(none.realized);
  EXPECT_NE(none.message.find("no arm to gesture with"), std::string::npos) << none.message;
}

// Other realizers' gesture names (issue 45, 4): the shipped vocabulary maps them to the procedural
// set (the most specific pattern wins), a profile's "gestureVocabulary" comes first, and the
// warning names the mapping; a name nothing maps stays unrealized, as before.
TEST(GestureVocabulary, OtherRealizersNamesPlayTheProceduralGestureTheyMapTo) {
  Diagnostics shipped;
  std::string text;
  ASSERT_TRUE(readTextFile(sourceFile("assets/gestures/vocabulary.json"), text, shipped, "cannot read")) << shipped.format();
  const GestureVocabulary fromFile = parseGestureVocabulary(text, "vocabulary.json", shipped);
  EXPECT_TRUE(shipped.items.empty()) << shipped.format();
  EXPECT_EQ(fromFile.size(), defaultGestureVocabulary().size());  // the built-in copy is the file
  for (const GestureVocabularyEntry& e : defaultGestureVocabulary())
    EXPECT_TRUE(hasProceduralGesture(e.lexeme)) << e.pattern << " -> " << e.lexeme;
  const struct {
    const char* name;
    const char* lexeme;
  } cases[] = {{"greet_wave1", "WAVE"},          {"Greeting", "WAVE"},          {"deictic_self", "ME"},
               {"Deictic_You_2", "YOU"},         {"deictic_there", "DEICTIC"},  {"INFORM_GES_3", "BEAT"},
               {"ChrBrad@Idle01_BeatLowBt01", "BEAT"}, {"METAPHORIC", "OFFER"}, {"shrug_2", "SHRUG"}};
  for (const auto& k : cases) {
    const GestureVocabularyEntry* m = matchGestureVocabulary(k.name, defaultGestureVocabulary());
    ASSERT_NE(m, nullptr) << k.name;
    EXPECT_EQ(m->lexeme, k.lexeme) << k.name << " matched '" << m->pattern << "'";
  }
  EXPECT_EQ(matchGestureVocabulary("FROBNICATE", defaultGestureVocabulary()), nullptr);
  EXPECT_TRUE(gesturePatternMatches("a*b?c*", "AxxBzCyy"));
  EXPECT_FALSE(gesturePatternMatches("a*b?c", "abc"));
  EXPECT_TRUE(gesturePatternMatches("*", ""));
  Diagnostics bad;
  EXPECT_TRUE(parseGestureVocabulary("[1]", "v.json", bad).empty());
  EXPECT_FALSE(bad.ok());
  Diagnostics odd;
  EXPECT_EQ(parseGestureVocabulary(R"({"x*": 3, "y*": "beat"})", "v.json", odd).size(), 1u);
  EXPECT_NE(odd.format().find("gesture vocabulary entry 'x*'"), std::string::npos) << odd.format();

  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  const BehaviorResult greet = c->addBehavior(gesture("greet_wave1"));
  ASSERT_TRUE(greet.realized) << greet.message;
  EXPECT_NE(greet.message.find("gesture 'greet_wave1' is played as the procedural WAVE (assets/gestures/vocabulary.json: 'greet*')"),
            std::string::npos)
      << greet.message;
  // The profile's vocabulary first.
  CharacterProfile own = rig->profile();
  own.gestureVocabulary = {{"greet*", "BEAT"}};
  auto mine = std::make_shared<Rig>(*rig);
  mine->setProfile(own);
  Character* d = scene.addCharacter("d", mine);
  const BehaviorResult beat = d->addBehavior(gesture("greet_wave1"));
  ASSERT_TRUE(beat.realized) << beat.message;
  EXPECT_NE(beat.message.find("as the procedural BEAT (the profile's gestureVocabulary: 'greet*')"), std::string::npos)
      << beat.message;
}
