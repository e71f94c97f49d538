// MorphBinding: engine morph slots by name, the report, size mismatches.
#include <gtest/gtest.h>

#include "marionette/bridge/morph_binding.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::bridge;

TEST(MorphBinding, CopiesWeightsByNameAndLeavesUnmatchedSlotsAlone) {
  auto rig = test::makeSyntheticRig();  // morphs {"smile", "blink"}; "walk" animates blink 0 -> 1 over 1 s
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  c->play(0, "walk");
  scene.update(0.25);
  const TransformBuffer& b = c->transformBuffer();
  ASSERT_GT(b.morphWeights()[1], 0.1f);
  const std::vector<std::string> slots = {"blink", "jawOpen", "smile"};
  MorphBinding binding(rig->morphTargets(), slots);
  EXPECT_EQ(binding.report().unmatchedSlots, std::vector<std::string>{"jawOpen"});
  EXPECT_TRUE(binding.report().unusedMorphs.empty());
  EXPECT_EQ(binding.report().format(), "morphs: engine slot 'jawOpen' has no character morph of that name; left untouched\n");
  std::vector<float> out(3, 0.5f);
  ASSERT_TRUE(binding.copy(b, out));
  EXPECT_EQ(out[0], b.morphWeights()[1]);
  EXPECT_EQ(out[1], 0.5f);  // the engine's own value stays
  EXPECT_EQ(out[2], b.morphWeights()[0]);
}

TEST(MorphBinding, ReportsUnusedMorphsAndRejectsSizeMismatch) {
  auto rig = test::makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  scene.update(0.0);
  const std::vector<std::string> slots = {"smile"};
  MorphBinding binding(rig->morphTargets(), slots);
  EXPECT_EQ(binding.report().unusedMorphs, std::vector<std::string>{"blink"});
  EXPECT_NE(binding.report().format().find("character morph 'blink' feeds no engine slot"), std::string::npos);
  std::vector<float> none;
  EXPECT_FALSE(binding.copy(c->transformBuffer(), none));
  const std::vector<std::string> other = {"a", "b", "c"};
  MorphBinding wrong(other, slots);  // bound to a character with three morphs
  std::vector<float> out(1, 9.0f);
  EXPECT_FALSE(wrong.copy(c->transformBuffer(), out));
  EXPECT_EQ(out[0], 9.0f);
}
