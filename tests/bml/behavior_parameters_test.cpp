// BML attributes read into the middleware's typed parameters: the spelling of
// targets, lexemes, influences, modes, manners, degrees and rates, and what is
// said about text that cannot be read (the middleware gets values only).
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "marionette/bml/behavior_parameters.hpp"
#include "marionette/bml/realizer.hpp"
#include "synthetic_upper_body.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {
Behavior behavior(std::string type, std::vector<std::pair<std::string, std::string>> attributes) {
  Behavior b;
  b.type = std::move(type);
  b.id = "b";
  for (auto& [name, value] : attributes) b.attributes.push_back({name, value});
  return b;
}
ReadParameters read(std::string type, std::vector<std::pair<std::string, std::string>> attributes) {
  const BehaviorKind kind = behaviorKindFromName(type).value();
  return readParameters(behavior(std::move(type), std::move(attributes)), kind);
}
constexpr float kPi = 3.14159265f;
}  // namespace

TEST(BmlParameters, HeadLexemesAndAmounts) {
  EXPECT_EQ(headLexemeFromName("nod"), HeadLexeme::Nod);
  EXPECT_FALSE(headLexemeFromName("NODD"));
  ReadParameters shake = read("head", {{"lexeme", "shake"}, {"amount", "-0.5"}});
  ASSERT_NE(std::get_if<HeadParameters>(&shake.parameters), nullptr);
  EXPECT_EQ(std::get<HeadParameters>(shake.parameters).lexeme, HeadLexeme::Shake);
  EXPECT_EQ(std::get<HeadParameters>(shake.parameters).amount, -0.5f);
  EXPECT_EQ(shake.error + shake.warning, "");
  ReadParameters odd = read("head", {{"lexeme", "JIGGLE"}});
  EXPECT_NE(odd.error.find("head lexeme 'JIGGLE' is neither NOD, SHAKE, TILT, TOSS, WIGGLE or WAGGLE nor a direction (UP, DOWN"),
            std::string::npos)
      << odd.error;
  EXPECT_TRUE(std::holds_alternative<std::monostate>(odd.parameters));
  // The catalogue, any case: SmartBody's TOSS, WIGGLE, WAGGLE; Greta's directions, held.
  for (const auto& [name, lexeme] : {std::pair{"toss", HeadLexeme::Toss}, std::pair{"Wiggle", HeadLexeme::Wiggle},
                                     std::pair{"WAGGLE", HeadLexeme::Waggle}}) {
    const ReadParameters p = read("head", {{"lexeme", name}});
    ASSERT_NE(std::get_if<HeadParameters>(&p.parameters), nullptr) << name << ": " << p.error;
    EXPECT_EQ(std::get<HeadParameters>(p.parameters).lexeme, lexeme) << name;
  }
  const struct {
    const char* name;
    glm::vec3 degrees;
  } directions[] = {{"Down", {40, 0, 0}},           {"up", {-30, 0, 0}},          {"Aside_Left", {0, 50, 0}},
                    {"RIGHT", {0, -50, 0}},          {"tilt_right", {0, 0, 30}},   {"Down_Aside_Right", {40, -50, 0}},
                    {"UP-TILT-LEFT", {-30, 0, -30}}, {"down left", {40, 50, 0}}};
  for (const auto& d : directions) {
    const ReadParameters p = read("head", {{"lexeme", d.name}});
    ASSERT_NE(std::get_if<HeadParameters>(&p.parameters), nullptr) << d.name << ": " << p.error;
    EXPECT_EQ(std::get<HeadParameters>(p.parameters).lexeme, HeadLexeme::Orient) << d.name;
    EXPECT_EQ(std::get<HeadParameters>(p.parameters).orientDegrees, d.degrees) << d.name;
  }
  for (const char* bad : {"ASIDE", "TILT_UP", "DOWN_SIDEWAYS", "_"})
    EXPECT_NE(read("head", {{"lexeme", bad}}).error.find("is neither"), std::string::npos) << bad;
  EXPECT_NE(read("head", {}).error.find("needs a lexeme"), std::string::npos);
  ReadParameters lots = read("head", {{"lexeme", "NOD"}, {"amount", "lots"}});
  EXPECT_EQ(lots.error, "");
  EXPECT_NE(lots.warning.find("amount 'lots' is not a number in [-1, 1]; 0.5 is used"), std::string::npos) << lots.warning;
  EXPECT_EQ(std::get<HeadParameters>(lots.parameters).amount, HeadParameters::kDefaultAmount);
  // A number out of range is the middleware's to check: it passes as read.
  EXPECT_EQ(std::get<HeadParameters>(read("head", {{"lexeme", "NOD"}, {"amount", "2"}}).parameters).amount, 2.0f);
}

TEST(BmlParameters, FaceLexemesAndUnits) {
  ReadParameters smile = read("faceLexeme", {{"lexeme", "smile"}, {"amount", "0.8"}});
  EXPECT_EQ(std::get<FaceParameters>(smile.parameters).expression, "SMILE");
  EXPECT_EQ(std::get<FaceParameters>(smile.parameters).amount, 0.8f);
  EXPECT_EQ(std::get<FaceParameters>(read("faceFacs", {{"au", "45"}}).parameters).expression, "AU45");
  EXPECT_NE(read("faceFacs", {}).error.find("needs an au"), std::string::npos);
  // BML's side: the character's own left or right; BOTH (or none) both; anything else said.
  EXPECT_EQ(std::get<FaceParameters>(read("faceFacs", {{"au", "45"}, {"side", "LEFT"}}).parameters).expression, "AU45_L");
  EXPECT_EQ(std::get<FaceParameters>(read("faceFacs", {{"au", "12"}, {"side", "right"}}).parameters).expression, "AU12_R");
  EXPECT_EQ(std::get<FaceParameters>(read("faceFacs", {{"au", "12"}, {"side", "BOTH"}}).parameters).expression, "AU12");
  const auto odd = read("faceFacs", {{"au", "12"}, {"side", "UP"}});
  EXPECT_EQ(std::get<FaceParameters>(odd.parameters).expression, "AU12");
  EXPECT_NE(odd.warning.find("side=\"UP\" is not LEFT, RIGHT or BOTH"), std::string::npos) << odd.warning;
  EXPECT_NE(read("faceLexeme", {}).error.find("needs a lexeme"), std::string::npos);
  EXPECT_NE(read("faceLexeme", {{"lexeme", "SMILE"}, {"amount", "x"}}).warning.find("amount 'x' is not a number in [0, 1]; 1 is used"),
            std::string::npos);
}

TEST(BmlParameters, TargetsPointsCharactersAndJoints) {
  const BehaviorTarget point = readTarget("1.5 0 -2");
  ASSERT_TRUE(point.point);
  EXPECT_EQ(*point.point, glm::vec3(1.5f, 0.0f, -2.0f));
  EXPECT_EQ(readTarget("Bob").character, "Bob");
  EXPECT_EQ(readTarget("Bob").joint, "");
  EXPECT_EQ(readTarget("Bob:Head").joint, "Head");
  EXPECT_TRUE(readTarget("").empty());
  EXPECT_FALSE(std::isfinite(readTarget("1e39 0 0").point->x));  // out of float range: infinite, refused by the middleware
  EXPECT_EQ(readTarget("1 2").character, "1 2");                  // two numbers are no point
}

TEST(BmlParameters, GazeInfluenceAndOffsets) {
  ReadParameters g = read("gaze", {{"target", "0 1 1"}, {"influence", "waist"}, {"offsetAngle", "30"}, {"offsetDirection", "upleft"}});
  const GazeParameters& p = std::get<GazeParameters>(g.parameters);
  EXPECT_EQ(p.influence, GazeInfluence::Waist);
  EXPECT_NEAR(p.offsetYaw, 0.70710678f * kPi / 6, 1e-6f);   // left is +yaw
  EXPECT_NEAR(p.offsetPitch, -0.70710678f * kPi / 6, 1e-6f);  // up is -pitch
  EXPECT_EQ(g.warning, "");
  EXPECT_NEAR(std::get<GazeParameters>(read("gaze", {{"target", "0 1 1"}, {"offsetAngle", "10"}, {"offsetDirection", "RIGHT"}}).parameters).offsetYaw,
              -10 * kPi / 180, 1e-6f);
  ReadParameters toes = read("gaze", {{"target", "0 1 1"}, {"influence", "TOES"}});
  EXPECT_NE(toes.warning.find("influence 'TOES'"), std::string::npos) << toes.warning;
  EXPECT_EQ(std::get<GazeParameters>(toes.parameters).influence, GazeInfluence::Neck);
  ReadParameters wide = read("gaze", {{"target", "0 1 1"}, {"offsetAngle", "200"}, {"offsetDirection", "LEFT"}});
  EXPECT_NE(wide.warning.find("offsetAngle '200' is not an angle in degrees"), std::string::npos) << wide.warning;
  ReadParameters sideways = read("gaze", {{"target", "0 1 1"}, {"offsetAngle", "20"}, {"offsetDirection", "AROUND"}});
  EXPECT_NE(sideways.warning.find("offsetDirection 'AROUND'"), std::string::npos) << sideways.warning;
}

TEST(BmlParameters, PointingModes) {
  EXPECT_EQ(std::get<PointingParameters>(read("pointing", {{"target", "1 1 1"}, {"mode", "left_hand"}}).parameters).arms,
            PointingArms::Left);
  EXPECT_EQ(std::get<PointingParameters>(read("pointing", {{"target", "1 1 1"}, {"mode", "BOTH_HANDS"}}).parameters).arms,
            PointingArms::Both);
  ReadParameters foot = read("pointing", {{"target", "1 1 1"}, {"mode", "FOOT"}});
  EXPECT_NE(foot.warning.find("mode 'FOOT' is not LEFT_HAND, RIGHT_HAND or BOTH_HANDS"), std::string::npos) << foot.warning;
  EXPECT_EQ(std::get<PointingParameters>(foot.parameters).arms, PointingArms::Nearest);
}

TEST(BmlParameters, LocomotionTargetsMannersAndNumbers) {
  auto loco = [](std::vector<std::pair<std::string, std::string>> a) { return read("locomotion", std::move(a)); };
  ReadParameters run = loco({{"target", "1 2"}, {"manner", "run"}});
  const auto& r = std::get<LocomotionParameters>(run.parameters);
  ASSERT_EQ(r.waypoints.size(), 1u);
  EXPECT_EQ(r.waypoints[0], glm::vec2(1.0f, 2.0f));
  EXPECT_EQ(r.manner, LocomotionManner::Run);
  EXPECT_EQ(run.warning, "");
  const auto facing = std::get<LocomotionParameters>(loco({{"target", "1 0 2"}, {"facing", "90"}}).parameters);
  EXPECT_EQ(facing.waypoints[0], glm::vec2(1.0f, 2.0f));  // y ignored
  EXPECT_NEAR(*facing.facing, kPi / 2, 1e-6f);
  EXPECT_EQ(std::get<LocomotionParameters>(loco({{"target", "0 1 2 3 4 5"}}).parameters).waypoints.size(), 3u);
  EXPECT_EQ(std::get<LocomotionParameters>(loco({{"target", "JOG"}, {"manner", "jog"}}).parameters).manner, LocomotionManner::Run);
  ReadParameters bob = loco({{"target", "Bob:Head"}, {"manner", "fly"}, {"speed", "-3"}, {"proximity", "near"}});
  const auto& b = std::get<LocomotionParameters>(bob.parameters);
  EXPECT_EQ(b.targetCharacter, "Bob");
  EXPECT_EQ(b.manner, LocomotionManner::Walk);
  EXPECT_NE(bob.warning.find("manner 'FLY'"), std::string::npos) << bob.warning;
  EXPECT_NE(bob.warning.find("proximity 'near' is not a number"), std::string::npos) << bob.warning;
  EXPECT_EQ(*b.speed, -3.0f);  // the middleware checks the range
  EXPECT_NE(loco({{"target", "1 2"}, {"facing", "400"}}).warning.find("facing '400' is not a number in [-360, 360]"),
            std::string::npos);
  for (const char* bad : {"nan 1", "1 inf", "1 2 3 4 5", "", "1"}) {
    const ReadParameters p = loco({{"target", bad}});
    EXPECT_NE(p.error, "") << bad;
    EXPECT_TRUE(std::holds_alternative<std::monostate>(p.parameters)) << bad;
    if (*bad) {
      EXPECT_NE(p.error.find(bad), std::string::npos) << p.error;
    }
  }
}

TEST(BmlParameters, SpeechTextMarksVoiceAndRate) {
  Behavior say = behavior("speech", {{"voice", "en-gb"}, {"rate", "140.4"}});
  say.text = "Hello there world";
  say.marks = {{"w1", 0}, {"w2", 6}};
  const ReadParameters s = readParameters(say, BehaviorKind::Speech);
  const auto& p = std::get<SpeechParameters>(s.parameters);
  EXPECT_EQ(p.text, "Hello there world");
  EXPECT_EQ(p.voice, "en-gb");
  EXPECT_EQ(p.wordsPerMinute, 140);
  ASSERT_EQ(p.marks.size(), 2u);
  EXPECT_EQ(p.marks[1].id, "w2");
  EXPECT_EQ(p.marks[1].characterOffset, 6u);
  Behavior fast = behavior("speech", {{"rate", "fast"}});
  EXPECT_NE(readParameters(fast, BehaviorKind::Speech).warning.find("speech rate 'fast' is not a number of words per minute"),
            std::string::npos);
}

// Through the realizer: the reader's error names the behavior's problem in place of the
// character's, its warnings come with the character's, and the request still joins
// the timeline (its timing and feedback run).
TEST(BmlParameters, TheRealizerReportsWhatCouldNotBeRead) {
  Scene scene;
  Realizer r(scene);
  r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
  scene.addCharacter("robot", test::makeUpperBodyRig());  // has a head
  std::vector<Feedback> warnings;
  r.addFeedbackListener([&](const Feedback& f) {
    if (f.kind == Feedback::Kind::Warning && f.warning.type != WarningType::ImpossibleToSchedule)  // not channel overlaps
      warnings.push_back(f);
  });
  Schedule s = r.perform("<bml id='b'><head id='odd' lexeme='JIGGLE'/><head id='lots' lexeme='NOD' amount='lots'/></bml>");
  ASSERT_FALSE(s.failed);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].warning.type, WarningType::CannotCreateBehavior);
  EXPECT_NE(warnings[0].warning.message.find("head lexeme 'JIGGLE' is neither NOD, SHAKE, TILT, TOSS, WIGGLE or WAGGLE nor"),
            std::string::npos)
      << warnings[0].warning.message;
  EXPECT_EQ(warnings[1].warning.type, WarningType::ParsingFailure);
  EXPECT_NE(warnings[1].warning.message.find("amount 'lots' is not a number in [-1, 1]; 0.5 is used"), std::string::npos)
      << warnings[1].warning.message;
  const Character& robot = *scene.findCharacter("robot");
  ASSERT_NE(robot.behaviors().find("b:odd"), nullptr);  // unrealized, still timed
  ASSERT_NE(robot.behaviors().find("b:lots")->request.as<HeadParameters>(), nullptr);
  // A locomotion whose target is not a place does not join the timeline.
  warnings.clear();
  r.perform("<bml id='c' composition='APPEND'><locomotion id='w' target='1 2 3 4 5'/></bml>");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].warning.message.find("locomotion target '1 2 3 4 5' has 5 numbers"), std::string::npos)
      << warnings[0].warning.message;
  EXPECT_EQ(robot.behaviors().find("c:w"), nullptr);
}
