// SmartBody's <blend name="STATE" x= y= z=>: realized through the character's profile
// blend space of that name (the synthetic rig with a 1D space over its walk and wave).
// The block is realized (no CANNOT_CREATE_BEHAVIOR), the space plays on the realizer's
// blend layer at the behavior's start, a second <blend> moves the point only, and an
// unknown state or a z are said.
#include <gtest/gtest.h>

#include "marionette/bml/realizer.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {

std::shared_ptr<const Rig> rigWithSpace() {
  auto rig = std::make_shared<Rig>(*test::makeSyntheticRig());
  std::string error;
  auto space = BlendSpace::make("mocapWalk", 1, {{rig->findClip("walk"), 0.0f}, {rig->findClip("wave"), 1.0f}},
                                rig->skeleton(), {}, true, error);
  EXPECT_TRUE(space) << error;
  rig->addBlendSpace(space);
  return rig;
}

std::vector<Warning> warningsOf(const std::vector<Feedback>& all) {
  std::vector<Warning> out;
  for (const Feedback& f : all)
    if (f.kind == Feedback::Kind::Warning) out.push_back(f.warning);
  return out;
}

void step(Scene& scene, Realizer& r, int frames) {
  for (int f = 0; f < frames; ++f) {
    scene.update(0.05);
    r.update();
  }
}

}  // namespace

TEST(SmartBodyBlend, ABlendBlockIsRealizedThroughTheProfileBlendSpace) {
  Scene scene;
  Realizer r(scene);
  std::vector<Feedback> feedback;
  r.addFeedbackListener([&](const Feedback& f) { feedback.push_back(f); });
  Character* c = scene.addCharacter("robot", rigWithSpace());
  const Schedule s = r.perform("<bml id=\"b1\" xmlns:sbm=\"http://ict.usc.edu\"><blend id=\"s\" name=\"mocapWalk\" x=\"0.25\"/></bml>", "robot");
  ASSERT_FALSE(s.failed);
  EXPECT_TRUE(warningsOf(feedback).empty()) << warningsOf(feedback).front().message;
  EXPECT_EQ(c->layerBlendSpace(r.blendLayer()), nullptr);  // not before its start is reached
  step(scene, r, 1);
  ASSERT_NE(c->layerBlendSpace(0), nullptr);
  EXPECT_EQ(c->layerBlendSpace(0)->name(), "mocapWalk");
  ASSERT_EQ(c->layerBlendWeights(0).size(), 2u);
  EXPECT_FLOAT_EQ(c->layerBlendWeights(0)[0], 0.75f);
  EXPECT_FLOAT_EQ(c->layerBlendWeights(0)[1], 0.25f);
  step(scene, r, 10);
  const double phase = c->layerTime(0);
  EXPECT_GT(phase, 0.0);
  // The same state again: the point moves, the cycle goes on (no restart).
  ASSERT_FALSE(r.perform("<bml id=\"b2\"><blend id=\"s\" name=\"mocapWalk\" x=\"1\" y=\"\"/></bml>", "robot").failed);
  step(scene, r, 1);
  EXPECT_FLOAT_EQ(c->layerBlendWeights(0)[1], 1.0f);
  EXPECT_GT(c->layerTime(0), phase);
  EXPECT_TRUE(warningsOf(feedback).empty());
  // It keeps playing after its block ended, as a SmartBody state does.
  step(scene, r, 40);
  EXPECT_EQ(r.activeBlocks(), 0u);
  EXPECT_NE(c->layerBlendSpace(0), nullptr);
  // Another layer when asked.
  r.setBlendLayer(3);
  ASSERT_FALSE(r.perform("<bml id=\"b3\"><blend id=\"s\" name=\"mocapWalk\" x=\"0.5\"/></bml>", "robot").failed);
  step(scene, r, 1);
  EXPECT_NE(c->layerBlendSpace(3), nullptr);
}

TEST(SmartBodyBlend, AnUnknownStateAndAThirdParameterAreSaid) {
  Scene scene;
  Realizer r(scene);
  std::vector<Feedback> feedback;
  r.addFeedbackListener([&](const Feedback& f) { feedback.push_back(f); });
  Character* c = scene.addCharacter("robot", rigWithSpace());
  ASSERT_FALSE(r.perform("<bml id=\"b1\"><blend id=\"b\" name=\"allLocomotion\" x=\"1\"/></bml>", "robot").failed);
  auto w = warningsOf(feedback);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].type, WarningType::CannotCreateBehavior);
  EXPECT_NE(w[0].message.find("no blend space of that name (it has 'mocapWalk')"), std::string::npos) << w[0].message;
  step(scene, r, 2);
  EXPECT_EQ(c->layerBlendSpace(0), nullptr);
  feedback.clear();
  ASSERT_FALSE(r.perform("<bml id=\"b2\"><blend id=\"b\" name=\"mocapWalk\" x=\"0.5\" y=\"2\" z=\"3\"/></bml>", "robot").failed);
  w = warningsOf(feedback);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("z ignored: blend spaces have 1 or 2 parameters"), std::string::npos) << w[0].message;
  EXPECT_NE(w[0].message.find("y ignored: blend space 'mocapWalk' has 1 parameter"), std::string::npos) << w[0].message;
  step(scene, r, 1);
  EXPECT_NE(c->layerBlendSpace(0), nullptr);  // realized all the same
}
