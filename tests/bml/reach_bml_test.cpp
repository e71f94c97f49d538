// Reaching in BML (issue 45, 7): SmartBody's <sbm:reach> with its sbm: attributes and
// Marionette's <reach target mode> parse, schedule with their phases (start, ready = stroke,
// relax, end) and bring the palm to a scene object on RobotExpressive and Godette; SmartBody's
// actions that do more than reach are realized as reaches with a warning saying what is left
// out; point-at is a pointing; a targetless finish and unknown attributes are named.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "marionette/bml/realizer.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {

glm::vec3 worldOf(const Character& c, int joint) {
  return glm::vec3(c.transformBuffer().worldMatrix() * c.transformBuffer().modelMatrices()[static_cast<std::size_t>(joint)][3]);
}

const BehaviorTimeline::Entry* entryEndingWith(const Character& c, const std::string& id) {
  for (const BehaviorTimeline::Entry& e : c.behaviors().entries())
    if (e.request.id.size() > id.size() && e.request.id.compare(e.request.id.size() - id.size(), id.size(), id) == 0)
      return &e;
  return nullptr;
}

struct Warnings {
  std::vector<Warning> all;
  [[nodiscard]] std::string of(WarningType type) const {
    std::string out;
    for (const Warning& w : all)
      if (w.type == type) out += w.behaviorId + ": " + w.message + "\n";
    return out;
  }
};

}  // namespace

TEST(BmlReach, SmartBodysFormParsesWithItsAttributesAndSchedulesItsPhases) {
  const std::string text =
      "<act><bml><sbm:reach sbm:action=\"touch\" sbm:reach-duration=\"0.5\" sbm:reach-finish=\"true\" "
      "sbm:reach-type=\"right\" target=\"bluebox\" sbm:frobnicate=\"1\"/></bml></act>";
  const auto parsed = parseBlock(text);
  ASSERT_TRUE(parsed.block) << parsed.format("sbm");
  ASSERT_EQ(parsed.block->behaviors.size(), 1u);
  const Behavior& b = parsed.block->behaviors[0];
  EXPECT_EQ(b.type, "reach");
  EXPECT_EQ(b.id, "reach_1");
  ASSERT_TRUE(b.attribute("action"));
  EXPECT_EQ(b.attribute("action")->value, "touch");
  ASSERT_TRUE(b.attribute("reach-duration"));
  ASSERT_TRUE(b.attribute("target"));
  EXPECT_FALSE(b.attribute("frobnicate"));
  const std::string w = parsed.format("sbm");
  EXPECT_NE(w.find("<reach> has no attribute 'frobnicate'"), std::string::npos) << w;
  const Schedule s = scheduleText(text);
  ASSERT_FALSE(s.failed);
  const std::pair<const char*, double> phases[] = {{"start", 0.0}, {"ready", 0.5}, {"stroke", 0.5}, {"relax", 1.5}, {"end", 2.0}};
  for (const auto& [sync, at] : phases) {
    ASSERT_TRUE(s.time("reach_1", sync)) << sync;
    EXPECT_NEAR(*s.time("reach_1", sync), at, 1e-9) << sync;
  }
  // Marionette's form takes the block's own timing, BML style.
  const Schedule m = scheduleText("<bml id=\"m\"><reach id=\"r\" target=\"1 1 1\" mode=\"LEFT_HAND\" end=\"4\"/></bml>");
  ASSERT_FALSE(m.failed);
  // One anchor (end): the default phases (1 s there, 1 s held, 1 s back) end there.
  EXPECT_NEAR(*m.time("r", "start"), 1.0, 1e-9);
  EXPECT_NEAR(*m.time("r", "ready"), 2.0, 1e-9);
  EXPECT_NEAR(*m.time("r", "stroke"), 2.0, 1e-9);
  EXPECT_NEAR(*m.time("r", "relax"), 3.0, 1e-9);
}

namespace {

void reachForTheBox(const char* asset, const char* profile) {
  MARIONETTE_REQUIRE_FILE(test::sharedAsset(asset));
  auto rig = test::loadRigWithProfile(test::sharedAsset(asset), profile);
  ASSERT_TRUE(rig);
  const RigJoints& j = rig->joints();
  for (const bool smartBody : {true, false}) {
    Scene scene;
    Character* c = scene.addCharacter("c", rig);
    scene.update(0.0);
    // The box in front of the right shoulder, within the arm (character's frame from its shoulders).
    const glm::vec3 shoulder = worldOf(*c, j.rightArm.upper);
    glm::vec3 left = worldOf(*c, j.leftArm.upper) - shoulder;
    left.y = 0.0f;
    left = glm::normalize(left);
    const glm::vec3 forward = glm::cross(left, glm::vec3(0, 1, 0));
    const float upper = glm::length(worldOf(*c, j.rightArm.lower) - shoulder);
    const int hand = limbWithEnd(j.rightArm, c->skeleton()).end;
    const float arm = upper + glm::length(worldOf(*c, hand) - worldOf(*c, j.rightArm.lower));
    const glm::vec3 box = shoulder + arm * (0.7f * forward - 0.3f * glm::vec3(0, 1, 0));
    ASSERT_TRUE(scene.setObject("bluebox", box));
    Realizer r(scene);
    Warnings w;
    r.addFeedbackListener([&](const Feedback& f) {
      if (f.kind == Feedback::Kind::Warning) w.all.push_back(f.warning);
    });
    const std::string text =
        smartBody ? "<act><bml><sbm:reach sbm:action=\"touch\" sbm:reach-duration=\"0.5\" sbm:reach-finish=\"true\" "
                    "target=\"bluebox\"/></bml></act>"
                  : "<bml id=\"b\"><reach id=\"reach_1\" target=\"bluebox\" mode=\"RIGHT_HAND\" start=\"0\" ready=\"0.5\" "
                    "relax=\"1.5\" end=\"2\"/></bml>";
    const Schedule s = r.perform(text, "c");
    SCOPED_TRACE(std::string(asset) + (smartBody ? ": <sbm:reach>" : ": <reach>"));
    ASSERT_FALSE(s.failed);
    for (const Warning& x : w.all)  // SmartBody's blocks say which ids were made up; nothing else is said
      EXPECT_NE(x.message.find("ids generated"), std::string::npos) << x.behaviorId << ": " << x.message;
    const BehaviorTimeline::Entry* e = entryEndingWith(*c, ":reach_1");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->request.kind, BehaviorKind::Reach);
    EXPECT_EQ(e->request.channelBits(), BodyChannel::RightHand);  // the box is on its right
    const ReachState* st = e->as<ReachState>();
    ASSERT_TRUE(st);
    float worst = 0.0f;
    for (int f = 1; f <= 150; ++f) {
      scene.update(1.0 / 60.0);
      r.update();
      const double t = f / 60.0;
      if (t > 0.55 && t < 1.45) {
        const glm::mat4 end = c->transformBuffer().modelMatrices()[static_cast<std::size_t>(st->limb[1].end)];
        const glm::vec3 palm(c->transformBuffer().worldMatrix() * end * glm::vec4(st->palmInEnd[1], 1.0f));
        worst = std::max(worst, glm::length(palm - box));
      }
    }
    EXPECT_TRUE(c->stats().used(Controller::Reach));
    EXPECT_LT(worst, 0.005f * upper) << "the palm missed the box";
  }
}

}  // namespace

TEST(BmlReach, RobotExpressiveTouchesTheBlueBox) { reachForTheBox("characters/RobotExpressive.glb", "RobotExpressive.json"); }
TEST(BmlReach, GodetteTouchesTheBlueBox) { reachForTheBox("characters/Godette_vrm_v4.vrm", "Godette_vrm_v4.json"); }

// SmartBody's actions: pick-up and put-down reach with a warning saying nothing is carried (a
// put-down without a place puts the hand in front of the character, as SmartBody does);
// point-at points; a reach that only finishes has nothing to do; ignored attributes are named.
TEST(BmlReach, SmartBodyActionsAreReachesPointingsOrNamedAsLeftOut) {
  MARIONETTE_REQUIRE_FILE(test::sharedAsset("characters/RobotExpressive.glb"));
  auto rig = test::loadRigWithProfile(test::sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  ASSERT_TRUE(scene.setObject("pawn1", {0.5f, 1.5f, 1.0f}));
  Realizer r(scene);
  Warnings w;
  r.addFeedbackListener([&](const Feedback& f) {
    if (f.kind == Feedback::Kind::Warning) w.all.push_back(f.warning);
  });
  const Schedule s = r.perform(
      "<act><bml><sbm:reach sbm:action=\"pick-up\" target=\"pawn1\" sbm:fade-in=\"1.0\" sbm:use-locomotion=\"true\"/>"
      "<sbm:reach sbm:action=\"put-down\" sbm:target-pos=\".4, 1.4, .4\" sbm:reach-finish=\"true\" sbm:reach-type=\"left\"/>"
      "<sbm:reach sbm:action=\"point-at\" sbm:reach-duration=\"1\" target=\"pawn1\"/>"
      "<sbm:reach sbm:action=\"pick-up\" sbm:reach-finish=\"true\"/>"
      "<sbm:reach sbm:action=\"put-down\" sbm:reach-finish=\"true\"/></bml></act>",
      "c");
  ASSERT_FALSE(s.failed);
  const std::string realized = w.of(WarningType::ParsingFailure), refused = w.of(WarningType::CannotCreateBehavior);
  EXPECT_NE(realized.find("reach_1: sbm:use-locomotion"), std::string::npos) << realized;
  EXPECT_NE(realized.find("pick-up is a reach here: the hand goes to the object and back; it is not grasped or carried"),
            std::string::npos) << realized;
  EXPECT_NE(realized.find("sbm:use-locomotion: the character does not walk to the target"), std::string::npos) << realized;
  EXPECT_NE(realized.find("sbm:fade-in ignored"), std::string::npos) << realized;
  EXPECT_NE(realized.find("reach_2: put-down is a reach here"), std::string::npos) << realized;
  EXPECT_NE(refused.find("reach_4: character 'c': a reach without a target"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("reach_1"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("reach_2"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("reach_3"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("reach_5"), std::string::npos) << refused;
  EXPECT_NE(realized.find("reach_5: put-down without a target: the place in front of the character; put-down is a reach"),
            std::string::npos) << realized;
  const BehaviorTimeline::Entry* inFront = entryEndingWith(*c, ":reach_5");  // RobotExpressive faces +Z
  ASSERT_TRUE(inFront && inFront->as<ReachState>());
  EXPECT_GT(inFront->as<ReachState>()->target.point.z, 0.0f);
  EXPECT_NEAR(inFront->as<ReachState>()->target.point.x, 0.0f, 1e-4f);
  const BehaviorTimeline::Entry* put = entryEndingWith(*c, ":reach_2");
  ASSERT_TRUE(put && put->as<ReachState>());
  EXPECT_EQ(put->request.channelBits(), BodyChannel::LeftHand);
  EXPECT_FLOAT_EQ(put->as<ReachState>()->target.point.y, 1.4f);
  const BehaviorTimeline::Entry* point = entryEndingWith(*c, ":reach_3");
  ASSERT_TRUE(point);
  EXPECT_EQ(point->request.kind, BehaviorKind::Pointing);
  for (int f = 0; f < 60; ++f) {
    scene.update(1.0 / 30.0);
    r.update();
  }
  EXPECT_TRUE(c->stats().used(Controller::Reach));
  EXPECT_TRUE(c->stats().used(Controller::Pointing));
}
