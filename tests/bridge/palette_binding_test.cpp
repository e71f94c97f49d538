// PaletteBinding: each layout against glm on a posed humanoid, binding through
// joint maps (synthetic and the shipped maps of two real characters), the bind
// report, and size mismatches.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "marionette/bridge/palette_binding.hpp"
#include "marionette/scene/scene.hpp"
#include "retarget_data.hpp"
#include "synthetic.hpp"
#include "synthetic_humanoid.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::bridge;

namespace {

// A humanoid (rolled joint frames, real inverse binds) posed by a clip on the
// spine, an arm and a leg, updated to t = 0.3 s at a non-trivial placement.
struct Posed {
  test::TestHumanoid humanoid;
  Scene scene;
  Character* character = nullptr;
};

std::unique_ptr<Posed> makePosed(const test::HumanoidSpec& spec) {
  auto p = std::make_unique<Posed>();
  p->humanoid = test::makeHumanoid(spec);
  auto asset = std::make_shared<Asset>();
  asset->skeleton = p->humanoid.skeleton;
  Clip clip;
  clip.name = "move";
  const Skeleton& s = asset->skeleton;
  for (const char* joint : {"spine1", "L_upperarm", "L_forearm", "R_thigh", "neck"})
    clip.tracks.push_back(test::rotationTrack(s.findJoint(spec.prefix + joint), {0.0f, 0.5f, 1.0f},
                                              {0.0f, 0.9f, 0.2f}, glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f))));
  clip.updateDuration();
  asset->clips = {clip};
  p->character = p->scene.addCharacter("h", std::make_shared<Rig>(*asset));
  p->character->setPosition({1.0f, 0.0f, -2.0f});
  p->character->play(0, "move");
  p->scene.update(0.3);
  return p;
}

const glm::mat4& expected(const TransformBuffer& b, int joint, bool inverseBind) {
  return inverseBind ? b.skinningMatrices()[static_cast<std::size_t>(joint)]
                     : b.modelMatrices()[static_cast<std::size_t>(joint)];
}

}  // namespace

TEST(PaletteBinding, EveryLayoutMatchesGlmOnAPosedHumanoid) {
  auto p = makePosed({.spineJoints = 3, .rollSeed = 7});
  const TransformBuffer& buffer = p->character->transformBuffer();
  const Skeleton& s = p->character->skeleton();
  // The buffer itself: skinning = model * inverseBind, and the pose is not the rest pose.
  const auto rest = s.restModelMatrices();
  float moved = 0.0f;
  for (std::size_t j = 0; j < s.jointCount(); ++j) {
    const glm::mat4 skin = buffer.modelMatrices()[j] * s.inverseBind[j];
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(buffer.skinningMatrices()[j][c][r], skin[c][r], 1e-5f);
    moved = std::max(moved, glm::length(glm::vec3(buffer.modelMatrices()[j][1] - rest[j][1])));
  }
  EXPECT_GT(moved, 0.1f) << "the clip must pose the skeleton";

  // Engine order: reversed, with a run of consecutive joints, an unknown bone between.
  std::vector<std::string> bones;
  for (std::size_t j = s.jointCount(); j-- > 10;) bones.push_back(s.names[j]);
  bones.push_back("engine_only");
  for (std::size_t j = 0; j < 10; ++j) bones.push_back(s.names[j]);
  PaletteBinding binding(s, bones);
  ASSERT_EQ(binding.slotCount(), bones.size());
  ASSERT_EQ(binding.report().unmatchedBones, std::vector<std::string>{"engine_only"});
  EXPECT_TRUE(binding.report().unusedJoints.empty());

  for (PaletteLayout layout : {PaletteLayout::Mat4ColumnMajor, PaletteLayout::Mat4RowMajor, PaletteLayout::Mat3x4RowMajor})
    for (bool inverseBind : {true, false}) {
      SCOPED_TRACE(testing::Message() << "layout " << static_cast<int>(layout) << " inverseBind " << inverseBind);
      const std::size_t per = floatsPerBone(layout);
      std::vector<float> out(binding.floatCount(layout) + 3, -7.0f);
      ASSERT_TRUE(binding.copy(buffer, out, {layout, inverseBind}));
      for (std::size_t slot = 0; slot < bones.size(); ++slot) {
        const float* m = out.data() + slot * per;
        const int j = s.findJoint(bones[slot]);
        const glm::mat4 e = j < 0 ? glm::mat4(1.0f) : expected(buffer, j, inverseBind);
        for (int r = 0; r < (layout == PaletteLayout::Mat3x4RowMajor ? 3 : 4); ++r)
          for (int c = 0; c < 4; ++c) {
            const float got = layout == PaletteLayout::Mat4ColumnMajor ? m[c * 4 + r] : m[r * 4 + c];
            ASSERT_EQ(got, e[c][r]) << "slot " << slot << " (" << bones[slot] << ") row " << r << " col " << c;
          }
        if (layout == PaletteLayout::Mat3x4RowMajor && j >= 0) {
          // As a shader uses it: rows dotted with (p, 1) give glm's M * p.
          const glm::vec4 point(0.1f, -0.4f, 0.25f, 1.0f);
          const glm::vec4 want = e * point;
          for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(m[r * 4] * point.x + m[r * 4 + 1] * point.y + m[r * 4 + 2] * point.z + m[r * 4 + 3], want[r], 1e-5f);
        }
      }
      for (std::size_t k = binding.floatCount(layout); k < out.size(); ++k) EXPECT_EQ(out[k], -7.0f);  // past the end
    }
}

TEST(PaletteBinding, IdentityBindingIsTheSkinningBuffer) {
  auto p = makePosed({.spineJoints = 4, .rollSeed = 3});
  const TransformBuffer& buffer = p->character->transformBuffer();
  PaletteBinding binding(p->character->skeleton());
  EXPECT_TRUE(binding.report().complete());
  EXPECT_EQ(binding.report().format(), "");
  std::vector<float> out(binding.floatCount(PaletteLayout::Mat4ColumnMajor));
  ASSERT_TRUE(binding.copy(buffer, out));
  ASSERT_EQ(out.size(), buffer.skinning().size());
  for (std::size_t k = 0; k < out.size(); ++k) ASSERT_EQ(out[k], buffer.skinning()[k]);
  // 3x4 equals the runtime's own packing when the buffer has it.
  p->character->transformBuffer().setPacked3x4(true);
  p->scene.update(0.05);
  std::vector<float> packed(binding.floatCount(PaletteLayout::Mat3x4RowMajor));
  ASSERT_TRUE(binding.copy(buffer, packed, {PaletteLayout::Mat3x4RowMajor, true}));
  ASSERT_EQ(packed.size(), buffer.skinning3x4().size());
  for (std::size_t k = 0; k < packed.size(); ++k) EXPECT_FLOAT_EQ(packed[k], buffer.skinning3x4()[k]);
}

TEST(PaletteBinding, BindsDifferentlyNamedSkeletonsThroughJointMaps) {
  // The engine's skeleton: 5 spine joints, "mixamorig:" names; the character: 3, plain names.
  const auto engine = test::makeHumanoid({.spineJoints = 5, .prefix = "mixamorig:"});
  auto p = makePosed({.spineJoints = 3, .rollSeed = 11});
  const Skeleton& s = p->character->skeleton();
  const BindMaps maps{engine.map, p->humanoid.map};
  PaletteBinding byNameOnly(s, engine.skeleton.names);
  EXPECT_EQ(byNameOnly.report().unmatchedBones.size(), engine.skeleton.jointCount());
  PaletteBinding binding(s, engine.skeleton.names, &maps);
  const BindReport& report = binding.report();
  EXPECT_TRUE(report.byName.empty());
  EXPECT_EQ(report.throughMaps.size(), engine.skeleton.jointCount() - 2);
  // spine[3] and spine[4] have no joint in a 3-joint spine.
  EXPECT_EQ(report.unmatchedBones, (std::vector<std::string>{"mixamorig:spine3", "mixamorig:spine4"}));
  EXPECT_TRUE(report.unusedJoints.empty());
  bool sawSpine1 = false;
  for (const BindReport::Mapped& m : report.throughMaps)
    if (m.engineBone == "mixamorig:spine1") {
      sawSpine1 = true;
      EXPECT_EQ(m.canonical, "spine[1]");
      EXPECT_EQ(m.joint, "spine1");
    }
  EXPECT_TRUE(sawSpine1);
  std::vector<float> out(binding.floatCount(PaletteLayout::Mat4ColumnMajor));
  ASSERT_TRUE(binding.copy(p->character->transformBuffer(), out));
  for (std::size_t slot = 0; slot < binding.slotCount(); ++slot) {
    const std::string& bone = engine.skeleton.names[slot];
    const std::string plain = bone.substr(std::string("mixamorig:").size());
    const int j = s.findJoint(plain);
    const bool missing = plain == "spine3" || plain == "spine4";
    ASSERT_EQ(binding.jointForSlot(slot), missing ? -1 : j) << bone;
    const glm::mat4 e = missing ? glm::mat4(1.0f) : expected(p->character->transformBuffer(), j, true);
    for (int k = 0; k < 16; ++k) ASSERT_EQ(out[slot * 16 + k], (&e[0][0])[k]) << bone;
  }
  const std::string text = report.format();
  EXPECT_NE(text.find("engine bone 'mixamorig:spine3'"), std::string::npos) << text;
  EXPECT_NE(text.find("engine bone 'mixamorig:spine4'"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2) << text;
}

TEST(PaletteBinding, BindsGodetteBonesToRobotExpressiveThroughTheShippedMaps) {
  // The engine has Godette's skeleton; the character is RobotExpressive. Names
  // differ throughout (J_Bip_C_Hips / Hips, ...); the maps of assets/jointmaps join them.
  const auto targets = test::retargetTargets();
  test::RetargetSubject robot, godette;
  std::string error;
  ASSERT_TRUE(test::loadRetargetSubject(targets[0], robot, error)) << error;
  ASSERT_TRUE(test::loadRetargetSubject(targets[1], godette, error)) << error;
  auto rig = std::make_shared<Rig>(robot.asset);
  Scene scene;
  Character* c = scene.addCharacter("robot", rig);
  ASSERT_TRUE(c->play(0, "Walking"));
  scene.update(0.4);

  const BindMaps maps{godette.map, robot.map};
  PaletteBinding binding(c->skeleton(), godette.asset.skeleton.names, &maps);
  const BindReport& report = binding.report();
  auto boundTo = [&](retarget::Bone b) {
    return binding.jointForSlot(static_cast<std::size_t>(godette.map.joint(b)));
  };
  for (retarget::Bone b : {retarget::Bone::Hips, retarget::Bone::Head, retarget::Bone::LeftUpperArm,
                           retarget::Bone::RightLowerArm, retarget::Bone::LeftUpperLeg, retarget::Bone::RightFoot}) {
    ASSERT_GE(godette.map.joint(b), 0);
    EXPECT_EQ(boundTo(b), robot.map.joint(b)) << retarget::boneName(b);
  }
  // The shipped map: the legs hang from "Body", so it is the hips ("Hips" turns the upper body).
  EXPECT_EQ(c->skeleton().names[static_cast<std::size_t>(boundTo(retarget::Bone::Hips))], "Body");
  EXPECT_GE(report.throughMaps.size(), 15u);
  // Godette's fingers and hands have no counterpart on the robot (it has no hand joint);
  // the robot's palms and IK helpers drive nothing.
  EXPECT_FALSE(report.unmatchedBones.empty());
  EXPECT_FALSE(report.unusedJoints.empty());
  EXPECT_EQ(report.byName.size() + report.throughMaps.size() + report.unmatchedBones.size(), binding.slotCount());
  const std::string text = report.format();
  EXPECT_NE(text.find("engine bone '" + report.unmatchedBones.front() + "'"), std::string::npos);
  EXPECT_NE(text.find("character joint '" + report.unusedJoints.front() + "'"), std::string::npos);
  EXPECT_EQ(static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')),
            report.unmatchedBones.size() + report.unusedJoints.size());

  std::vector<float> out(binding.floatCount(PaletteLayout::Mat4RowMajor));
  ASSERT_TRUE(binding.copy(c->transformBuffer(), out, {PaletteLayout::Mat4RowMajor, false}));
  const std::size_t hipsSlot = static_cast<std::size_t>(godette.map.joint(retarget::Bone::Hips));
  const glm::mat4& hips = c->transformBuffer().modelMatrices()[static_cast<std::size_t>(robot.map.joint(retarget::Bone::Hips))];
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col) EXPECT_EQ(out[hipsSlot * 16 + r * 4 + col], hips[col][r]);
}

TEST(PaletteBinding, RejectsTooSmallOutputAndOtherSkeletonsWithoutWriting) {
  auto rig = test::makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  scene.update(0.0);
  PaletteBinding binding(c->skeleton());
  for (PaletteLayout layout : {PaletteLayout::Mat4ColumnMajor, PaletteLayout::Mat4RowMajor, PaletteLayout::Mat3x4RowMajor}) {
    std::vector<float> small(binding.floatCount(layout) - 1, 7.0f);
    EXPECT_FALSE(binding.copy(c->transformBuffer(), small, {layout, true}));
    for (float v : small) ASSERT_EQ(v, 7.0f);  // nothing written
  }
  PaletteBinding wrong(test::makeChain(2));
  std::vector<float> out(2 * 16, 7.0f);
  EXPECT_FALSE(wrong.copy(c->transformBuffer(), out));
  for (float v : out) ASSERT_EQ(v, 7.0f);
  PaletteBinding empty;
  EXPECT_FALSE(empty.copy(c->transformBuffer(), out));  // bound to no skeleton
}

// A buffer that keeps no skinning matrices (the C API's characters) gives, through the
// binding, the very bits of one that stores them: every layout, the engine's order, over
// frames of motion; the packed 3x4 copy too. Its memory is the model matrices alone.
TEST(PaletteBinding, SkinningMadeOnCopyIsBitIdenticalToStored) {
  auto stored = makePosed({.spineJoints = 3, .rollSeed = 7});
  auto made = makePosed({.spineJoints = 3, .rollSeed = 7});
  const Skeleton& s = made->character->skeleton();
  TransformBuffer& buffer = made->character->transformBuffer();
  buffer.setSkinningStored(false, s.inverseBind, &made->character->rig().paletteBasis());
  ASSERT_FALSE(buffer.skinningStored());
  EXPECT_TRUE(buffer.skinningMatrices().empty());
  stored->character->transformBuffer().setPacked3x4(true);
  buffer.setPacked3x4(true);
  std::vector<std::string> bones;
  for (std::size_t j = s.jointCount(); j-- > 0;) bones.push_back(s.names[j]);  // reversed: runs of one
  const PaletteBinding identity(s), reversed(s, bones);
  for (int frame = 0; frame < 20; ++frame) {
    stored->scene.update(1.0 / 30.0);
    made->scene.update(1.0 / 30.0);
    const TransformBuffer& a = stored->character->transformBuffer();
    for (const PaletteBinding* binding : {&identity, &reversed})
      for (PaletteLayout layout : {PaletteLayout::Mat4ColumnMajor, PaletteLayout::Mat4RowMajor, PaletteLayout::Mat3x4RowMajor}) {
        std::vector<float> fromStored(binding->floatCount(layout)), fromMade(binding->floatCount(layout));
        ASSERT_TRUE(binding->copy(a, fromStored, {layout, true}));
        ASSERT_TRUE(binding->copy(buffer, fromMade, {layout, true}));
        ASSERT_EQ(0, std::memcmp(fromStored.data(), fromMade.data(), fromStored.size() * sizeof(float)))
            << "frame " << frame << ", layout " << static_cast<int>(layout);
      }
    ASSERT_EQ(a.skinning3x4().size(), buffer.skinning3x4().size());
    ASSERT_EQ(0, std::memcmp(a.skinning3x4().data(), buffer.skinning3x4().data(), a.skinning3x4().size() * sizeof(float)));
  }
  // Inverse binds that do not cover the buffer leave it storing (nothing to make them from).
  TransformBuffer other;
  other.resize(4, 0);
  other.setSkinningStored(false, {}, nullptr);
  EXPECT_TRUE(other.skinningStored());
}
