#include <gtest/gtest.h>

#include "marionette/bridge/palette_binding.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::bridge;

TEST(PaletteBinding, RejectsTooSmallOutputAndOtherSkeletons) {
  auto rig = test::makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  scene.update(0.0);
  PaletteBinding binding(c->skeleton());
  std::vector<float> small(10, 7.0f);
  EXPECT_FALSE(binding.copy(c->transformBuffer(), small, PaletteLayout::Mat4ColumnMajor));
  EXPECT_EQ(small[0], 7.0f);  // nothing written
  Skeleton other = test::makeChain(2);
  PaletteBinding wrong(other);
  std::vector<float> out(2 * 16);
  EXPECT_FALSE(wrong.copy(c->transformBuffer(), out, PaletteLayout::Mat4ColumnMajor));
}

TEST(PaletteBinding, CopiesMappedJointsByNameInBothLayouts) {
  auto rig = test::makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  c->play(0, "wave");
  scene.update(0.2);
  const std::vector<std::string> engineBones = {"j3", "missing", "j0"};
  PaletteBinding binding(c->skeleton(), engineBones);
  ASSERT_EQ(binding.unmapped().size(), 1u);
  EXPECT_EQ(binding.unmapped()[0], "missing");
  std::vector<float> m4(3 * 16, -1.0f), m34(3 * 12, -1.0f);
  binding.clearUnmapped(m4, PaletteLayout::Mat4ColumnMajor);
  ASSERT_TRUE(binding.copy(c->transformBuffer(), m4, PaletteLayout::Mat4ColumnMajor));
  ASSERT_TRUE(binding.copy(c->transformBuffer(), m34, PaletteLayout::Mat3x4RowMajor));
  const auto skin = c->transformBuffer().skinning();
  for (int k = 0; k < 16; ++k) EXPECT_EQ(m4[k], skin[3 * 16 + k]);       // slot 0 = j3
  for (int k = 0; k < 16; ++k) EXPECT_EQ(m4[32 + k], skin[0 * 16 + k]);  // slot 2 = j0
  EXPECT_EQ(m4[16], 1.0f);  // unmapped slot cleared to identity
  EXPECT_EQ(m4[17], 0.0f);
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 4; ++col) EXPECT_EQ(m34[r * 4 + col], skin[3 * 16 + col * 4 + r]);
  EXPECT_EQ(m34[12], -1.0f);  // unmapped 3x4 slot untouched by copy
}
