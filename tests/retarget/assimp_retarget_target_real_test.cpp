// Which characters the retarget command serves: every rigged character of Debian's
// assimp-testmodels and ../shared, and the other files there with a skin, with its expected
// class (issue 41), so that a human walk is never written onto a quadruped or a mesh without
// a skeleton with a report of zeros. (The survey: `marionette inspect` over the 292 models,
// those with a skinned mesh; the 16 Mesh_PrimitiveMode boxes and the BoxTextured variants
// are one box.)
#include <gtest/gtest.h>

#include <string>

#include "marionette/io/import.hpp"
#include "marionette/retarget/target_check.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette;
using retarget::TargetClass;

struct Expected {
  std::string file;
  TargetClass kind;
};

retarget::TargetCheck check(const std::string& file, bool needsMesh = true) {
  const ImportResult r = importAsset(file, ImportOptions{});
  EXPECT_TRUE(r.ok()) << file << ": " << r.diagnostics.format();
  if (!r.ok()) return {};
  const retarget::JointMapResult map = retarget::guessJointMap(*r.asset);
  return retarget::checkRetargetTarget(*r.asset, map.map, needsMesh);
}

TEST(RetargetTarget, EveryRiggedCharacterHasItsExpectedClass) {
  const std::string m = marionette::test::assimpModel("");
  const std::string s = marionette::test::sharedAsset("characters/");
  const Expected cases[] = {
      {s + "RobotExpressive.glb", TargetClass::Humanoid},
      {s + "Godette_vrm_v4.vrm", TargetClass::Humanoid},
      {s + "CesiumMan.glb", TargetClass::Humanoid},
      {s + "pab_arnaud.fbx", TargetClass::Humanoid},
      {m + "X/Testwuson.X", TargetClass::ManyLegged},
      {m + "X/BCN_Epileptic.X", TargetClass::Humanoid},
      {m + "Collada/human.zae", TargetClass::NoSkeleton},  // a mesh: two rigid nodes, no skin
      // The SMD Wuson imports as one joint (Assimp's SMD reader keeps no skeleton of it).
      {m + "SMD/WusonSMD.smd", TargetClass::NotHumanoid},
      // The other skinned files of assimp-testmodels: props, a machine and test boxes.
      {m + "SMD/holy_grailref.smd", TargetClass::NotHumanoid},
      {m + "SMD/triangle.smd", TargetClass::NotHumanoid},
      {m + "X/anim_test.x", TargetClass::NotHumanoid},
      {m + "X/test_cube_text.x", TargetClass::NotHumanoid},
      {m + "Collada/box_nested_animation.dae", TargetClass::NotHumanoid},
      {m + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", TargetClass::NotHumanoid},
      {m + "glTF2/simple_skin/simple_skin.gltf", TargetClass::NotHumanoid},
      {m + "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", TargetClass::NotHumanoid},
  };
  for (const Expected& e : cases) {
    const retarget::TargetCheck c = check(e.file);
    EXPECT_EQ(c.kind, e.kind) << e.file << ": " << retarget::targetClassName(c.kind) << " (" << c.reason << "), "
                              << c.groundLegs << " legs on the ground";
    if (e.kind != TargetClass::Humanoid) {
      EXPECT_FALSE(c.reason.empty()) << e.file;
    }
  }
}

TEST(RetargetTarget, AQuadrupedIsKnownByItsFourLegsOnTheGround) {
  const ImportResult r = importAsset(marionette::test::assimpModel("X/Testwuson.X"), ImportOptions{});
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  EXPECT_EQ(retarget::legsOnTheGround(r.asset->skeleton), 4);
  const ImportResult robot = importAsset(marionette::test::sharedAsset("characters/RobotExpressive.glb"), ImportOptions{});
  ASSERT_TRUE(robot.ok());
  EXPECT_LE(retarget::legsOnTheGround(robot.asset->skeleton), 2);
}

TEST(RetargetTarget, AMotionSkeletonWithoutAMeshServesABvhButNotACharacter) {
  const std::string bvh = marionette::test::sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh");
  EXPECT_EQ(check(bvh, false).kind, TargetClass::Humanoid);
  const retarget::TargetCheck c = check(bvh, true);
  EXPECT_EQ(c.kind, TargetClass::NoSkeleton);
  EXPECT_NE(c.reason.find("no mesh"), std::string::npos) << c.reason;
}

}  // namespace
