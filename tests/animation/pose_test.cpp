#include <gtest/gtest.h>

#include "marionette/animation/pose.hpp"
#include "synthetic.hpp"

using namespace marionette;
using namespace marionette::test;

TEST(Pose, ChainRestPaletteIsIdentity) {
  Skeleton s = makeChain(5);
  ASSERT_EQ(s.validate(), "");
  std::vector<glm::mat4> model(5), palette(5);
  localToModel(s, s.restPose, model);
  EXPECT_NEAR(model[4][3].y, 4.0f, 1e-6f);
  skinningPalette(model, s.inverseBind, palette);
  for (const auto& m : palette)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(m[c][r], c == r ? 1.0f : 0.0f, 1e-5f);
}

TEST(Pose, RotatedRootCarriesChildren) {
  Skeleton s = makeChain(3);
  auto local = s.restPose;
  local[0].rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));  // +Y -> -X
  std::vector<glm::mat4> model(3);
  localToModel(s, local, model);
  EXPECT_NEAR(model[2][3].x, -2.0f, 1e-5f);
  EXPECT_NEAR(model[2][3].y, 0.0f, 1e-5f);
}

TEST(Pose, RootTransformAndNonUniformScale) {
  Skeleton s = makeChain(2);
  s.rootTransform = glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 3.0f, 4.0f));
  std::vector<glm::mat4> model(2);
  localToModel(s, s.restPose, model);
  EXPECT_NEAR(model[1][3].y, 3.0f, 1e-6f);
  // Non-uniform bind scale: the affine product equals the full product.
  glm::mat4 a = Transform{{1, 2, 3}, glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, 2, 3))), {0.5f, 2.0f, 3.0f}}.matrix();
  glm::mat4 b = Transform{{-1, 0, 4}, glm::angleAxis(-1.1f, glm::vec3(0, 1, 0)), {1.0f, 0.25f, 7.0f}}.matrix();
  glm::mat4 full = a * b, fast = affineMultiply(a, b);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(full[c][r], fast[c][r], 1e-4f);
}

TEST(Pose, DecomposeRoundTripAndMirror) {
  Transform t{{1, -2, 3}, glm::angleAxis(0.4f, glm::normalize(glm::vec3(1, 0, 1))), {2, 3, 4}};
  Transform d = decompose(t.matrix());
  EXPECT_NEAR(glm::length(d.translation - t.translation), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(d.scale - t.scale), 0.0f, 1e-4f);
  EXPECT_NEAR(angleBetween(d.rotation, t.rotation), 0.0f, 1e-3f);
  glm::mat4 mirrored = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1));
  Transform m = decompose(mirrored);
  EXPECT_LT(m.scale.x, 0.0f);
  glm::mat4 back = m.matrix();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(back[c][r], mirrored[c][r], 1e-6f);
}

TEST(Pose, ThousandJointChainStaysFiniteAndExact) {
  Skeleton s = makeChain(1000, 0.01f);
  ASSERT_EQ(s.validate(), "");
  auto local = s.restPose;
  for (auto& t : local) t.rotation = glm::angleAxis(glm::radians(0.36f), glm::vec3(0, 0, 1));
  std::vector<glm::mat4> model(1000), palette(1000);
  localToModel(s, local, model);
  skinningPalette(model, s.inverseBind, palette);
  // 1000 * 0.36° = 360°: a closed polygon of perimeter 10; the tip returns near the origin.
  glm::vec3 tip(model[999][3]);
  EXPECT_LT(glm::length(tip), 0.02f);
  for (const auto& m : palette)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) ASSERT_TRUE(std::isfinite(m[c][r]));
}

TEST(Pose, ZeroLengthBonesAndZeroScale) {
  Skeleton s = makeChain(3, 0.0f);
  auto local = s.restPose;
  local[1].scale = glm::vec3(0.0f);
  std::vector<glm::mat4> model(3);
  localToModel(s, local, model);
  for (const auto& m : model)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(m[c][r]));
}

TEST(Skeleton, ValidateCatchesOrderAndSizes) {
  Skeleton s = makeChain(3);
  s.parents[1] = 2;
  EXPECT_NE(s.validate().find("parent"), std::string::npos);
  Skeleton t = makeChain(3);
  t.names.pop_back();
  EXPECT_NE(t.validate().find("size"), std::string::npos);
  Skeleton u = makeChain(2);
  u.restPose[1].translation.x = NAN;
  EXPECT_NE(u.validate().find("non-finite"), std::string::npos);
  EXPECT_EQ(makeChain(3).findJoint("j2"), 2);
  EXPECT_EQ(makeChain(3).findJoint("nope"), -1);
}
