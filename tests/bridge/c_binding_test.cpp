// mn_binding (marionette.h) against the C++ bridge it wraps: an engine with Godette's
// skeleton, in an order where parents come after their children, bound to
// RobotExpressive through the shipped joint maps and through guessed ones; morph slots
// by name; and every way a binding can be refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "marionette/bridge/morph_binding.hpp"
#include "marionette/bridge/palette_binding.hpp"
#include "marionette/marionette.h"
#include "retarget_data.hpp"
#include "test_data.hpp"

using namespace marionette;

namespace {

const std::string kRobot = test::sharedAsset("characters/RobotExpressive.glb");
const std::string kGodette = test::sharedAsset("characters/Godette_vrm_v4.vrm");
const std::string kRobotMap = test::sourceFile("assets/jointmaps/RobotExpressive.json");
const std::string kGodetteMap = test::sourceFile("assets/jointmaps/Godette_vrm_v4.json");

// Godette's skeleton as an engine would hand it over: slot order reversed, so that
// every parent comes after its children.
struct EngineGodette {
  Skeleton skeleton;               // marionette's order (for the C++ side)
  std::vector<std::string> names;  // engine slot order
  std::vector<int> parents;        // engine slots
  std::vector<const char*> namePtrs;
  mn_engine_skeleton engine{};

  explicit EngineGodette(std::vector<std::string> morphs = {}) : morphNames(std::move(morphs)) {
    ImportOptions o;
    o.loadMeshes = false;
    ImportResult r = importAsset(kGodette, o);
    EXPECT_TRUE(r.ok()) << r.diagnostics.format();
    skeleton = r.asset->skeleton;
    const int n = static_cast<int>(skeleton.jointCount());
    for (int slot = 0; slot < n; ++slot) {
      const int joint = n - 1 - slot;
      names.push_back(skeleton.names[static_cast<std::size_t>(joint)]);
      const int p = skeleton.parents[static_cast<std::size_t>(joint)];
      parents.push_back(p < 0 ? -1 : n - 1 - p);
    }
    for (const auto& s : names) namePtrs.push_back(s.c_str());
    for (const auto& s : morphNames) morphPtrs.push_back(s.c_str());
    engine = {namePtrs.data(), parents.data(), names.size(), morphPtrs.empty() ? nullptr : morphPtrs.data(),
              morphPtrs.size()};
  }
  // A C++ joint map of Godette's skeleton with its joints turned into engine slots.
  [[nodiscard]] retarget::JointMap inSlots(retarget::JointMap map) const {
    const int n = static_cast<int>(skeleton.jointCount());
    for (int& j : map.bones)
      if (j >= 0) j = n - 1 - j;
    for (auto& chain : map.chains)
      for (int& j : chain) j = n - 1 - j;
    return map;
  }
  std::vector<std::string> morphNames;
  std::vector<const char*> morphPtrs;
};

struct RobotScene {
  mn_scene* scene = nullptr;
  mn_character* robot = nullptr;
  RobotScene() {
    EXPECT_EQ(mn_scene_create(&scene), MN_OK);
    EXPECT_EQ(mn_scene_add_character(scene, "robot", kRobot.c_str(), nullptr, &robot), MN_OK) << mn_scene_last_error(scene);
    EXPECT_EQ(mn_character_play(robot, 0, "Walking", nullptr), MN_OK) << mn_scene_last_error(scene);
    EXPECT_EQ(mn_scene_update(scene, 0.4), MN_OK);
  }
  ~RobotScene() { mn_scene_destroy(scene); }
};

Skeleton robotSkeleton() {
  ImportOptions o;
  o.loadMeshes = false;
  ImportResult r = importAsset(kRobot, o);
  EXPECT_TRUE(r.ok());
  return r.asset->skeleton;
}

// The binding's palette is the character's own palette, rearranged: bound slots carry
// their joint's matrix, unbound ones identity.
void expectPaletteRearranged(const RobotScene& s, const mn_binding* b, mn_palette_layout layout) {
  const size_t per = mn_palette_floats_per_joint(layout);
  std::vector<float> own(mn_character_joint_count(s.robot) * per), mine(mn_binding_bone_count(b) * per);
  ASSERT_EQ(mn_character_palette(s.robot, layout, 1, own.data(), own.size()), MN_OK);
  ASSERT_EQ(mn_binding_palette(b, layout, 1, mine.data(), mine.size()), MN_OK) << mn_scene_last_error(s.scene);
  const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const float identity3x4[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  for (size_t slot = 0; slot < mn_binding_bone_count(b); ++slot) {
    const int j = mn_binding_joint_for_bone(b, slot);
    for (size_t k = 0; k < per; ++k) {
      const float want = j >= 0 ? own[static_cast<size_t>(j) * per + k] : (per == 12 ? identity3x4[k] : identity[k]);
      ASSERT_EQ(mine[slot * per + k], want) << "slot " << slot << " float " << k;
    }
  }
}

// Binding through joint maps: the given files, or guessed where NULL.
mn_binding_options throughMaps(const char* engineMap, const char* characterMap) {
  mn_binding_options o = mn_binding_options_default();
  o.through_joint_maps = 1;
  o.engine_joint_map = engineMap;
  o.character_joint_map = characterMap;
  return o;
}

}  // namespace

TEST(CBinding, ThroughTheShippedMapsItBindsAsTheCppBridgeDoes) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  MARIONETTE_REQUIRE_FILE(kGodette);
  RobotScene s;
  EngineGodette g;
  const mn_binding_options o = throughMaps(kGodetteMap.c_str(), kRobotMap.c_str());
  mn_binding* b = nullptr;
  ASSERT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_OK) << mn_scene_last_error(s.scene);
  ASSERT_NE(b, nullptr);

  // The C++ bridge with the same maps.
  const Skeleton robot = robotSkeleton();
  Asset godetteAsset;
  godetteAsset.skeleton = g.skeleton;
  const auto godetteMap = retarget::loadJointMap(kGodetteMap, godetteAsset);
  Asset robotAsset;
  robotAsset.skeleton = robot;
  const auto robotMap = retarget::loadJointMap(kRobotMap, robotAsset);
  const retarget::JointMap engineMap = g.inSlots(godetteMap.map);
  const bridge::BindMaps maps{engineMap, robotMap.map};
  const bridge::PaletteBinding cpp(robot, g.names, &maps);

  ASSERT_EQ(mn_binding_bone_count(b), cpp.slotCount());
  int bound = 0;
  for (size_t slot = 0; slot < cpp.slotCount(); ++slot) {
    EXPECT_EQ(mn_binding_joint_for_bone(b, slot), cpp.jointForSlot(slot)) << g.names[slot];
    bound += cpp.jointForSlot(slot) >= 0;
  }
  EXPECT_GE(bound, 15);
  // The hips are "Body" (the robot's legs hang from it), the head "Head".
  auto jointOf = [&](retarget::Bone bone) {
    const int j = mn_binding_joint_for_bone(b, static_cast<size_t>(engineMap.joint(bone)));
    return j < 0 ? std::string("(none)") : std::string(mn_character_joint_name(s.robot, static_cast<size_t>(j)));
  };
  EXPECT_EQ(jointOf(retarget::Bone::Hips), "Body");
  EXPECT_EQ(jointOf(retarget::Bone::Head), "Head");
  EXPECT_EQ(jointOf(retarget::Bone::LeftUpperArm), "UpperArm.L");
  // The report: the bridge's lines (the maps load cleanly, so no map lines), then the morphs'
  // (the engine takes none of the robot's three).
  ImportResult robotFull = importAsset(kRobot);
  ASSERT_TRUE(robotFull.ok());
  const bridge::MorphBinding morphs(robotFull.asset->morphTargets, {});
  EXPECT_EQ(std::string(mn_binding_report(b)), cpp.report().format() + morphs.report().format());
  const std::string hand = g.names[static_cast<size_t>(engineMap.joint(retarget::Bone::LeftHand))];
  EXPECT_NE(std::string(mn_binding_report(b)).find("engine bone '" + hand + "' has no character joint"), std::string::npos)
      << "the robot has no hand joint: " << mn_binding_report(b);
  for (mn_palette_layout layout : {MN_PALETTE_MAT4_COLUMN_MAJOR, MN_PALETTE_MAT4_ROW_MAJOR, MN_PALETTE_MAT3X4_ROW_MAJOR})
    expectPaletteRearranged(s, b, layout);
  mn_binding_destroy(b);
}

// Without map files: the engine's map is guessed from its names and parents; the robot's is
// the shipped map that fits it (as `marionette retarget` finds it), named in the report.
TEST(CBinding, WithoutMapFilesTheEngineIsGuessedAndTheCharacterGetsItsShippedMap) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  MARIONETTE_REQUIRE_FILE(kGodette);
  RobotScene s;
  EngineGodette g;
  const mn_binding_options o = throughMaps(nullptr, nullptr);
  mn_binding* b = nullptr;
  ASSERT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_OK) << mn_scene_last_error(s.scene);
  // The C++ guess on the same skeleton (rest poses unknown to the engine: identity).
  Asset engineAsset;
  for (std::size_t j = 0; j < g.skeleton.jointCount(); ++j)
    engineAsset.skeleton.addJoint(g.skeleton.names[j], g.skeleton.parents[j], Transform{});
  const Skeleton robot = robotSkeleton();
  ImportResult robotAsset = importAsset(kRobot);
  ASSERT_TRUE(robotAsset.ok());
  const retarget::JointMap engineMap = g.inSlots(retarget::guessJointMap(engineAsset).map);
  const auto shipped = retarget::findJointMap(*robotAsset.asset, {test::sourceFile("assets/jointmaps")});
  ASSERT_TRUE(shipped.has_value());
  EXPECT_NE(std::string(mn_binding_report(b)).find("character joint map: " + shipped->file + " (the shipped map that fits)"),
            std::string::npos)
      << mn_binding_report(b);
  EXPECT_NE(shipped->file.find("RobotExpressive.json"), std::string::npos) << shipped->file;
  const retarget::JointMap robotMap = shipped->result.map;
  const bridge::BindMaps maps{engineMap, robotMap};
  const bridge::PaletteBinding cpp(robot, g.names, &maps);
  for (size_t slot = 0; slot < cpp.slotCount(); ++slot)
    EXPECT_EQ(mn_binding_joint_for_bone(b, slot), cpp.jointForSlot(slot)) << g.names[slot];
  for (retarget::Bone bone : {retarget::Bone::Hips, retarget::Bone::Head, retarget::Bone::LeftUpperArm,
                              retarget::Bone::RightLowerLeg})
    EXPECT_EQ(mn_binding_joint_for_bone(b, static_cast<size_t>(engineMap.joint(bone))), robotMap.joint(bone))
        << retarget::boneName(bone);
  expectPaletteRearranged(s, b, MN_PALETTE_MAT4_COLUMN_MAJOR);
  mn_binding_destroy(b);
}

TEST(CBinding, MorphSlotsByNameLeaveTheUnboundOnesToTheEngine) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  MARIONETTE_REQUIRE_FILE(kGodette);
  RobotScene s;
  EngineGodette g({"Surprised", "engine_blink", "Angry"});
  mn_binding* b = nullptr;
  ASSERT_EQ(mn_binding_create(s.robot, &g.engine, nullptr, &b), MN_OK) << mn_scene_last_error(s.scene);
  ASSERT_EQ(mn_binding_morph_slot_count(b), 3u);
  auto morphIndex = [&](const char* name) {
    for (size_t m = 0; m < mn_character_morph_count(s.robot); ++m)
      if (std::string(mn_character_morph_name(s.robot, m)) == name) return static_cast<int>(m);
    return -1;
  };
  EXPECT_EQ(mn_binding_morph_for_slot(b, 0), morphIndex("Surprised"));
  EXPECT_EQ(mn_binding_morph_for_slot(b, 1), -1);
  EXPECT_EQ(mn_binding_morph_for_slot(b, 2), morphIndex("Angry"));
  EXPECT_EQ(mn_binding_morph_for_slot(b, 3), -1);
  const std::string report = mn_binding_report(b);
  EXPECT_NE(report.find("engine_blink"), std::string::npos) << report;
  EXPECT_NE(report.find("Sad"), std::string::npos) << "the morph no slot takes: " << report;
  // By name alone, Godette's bone names find nothing on the robot.
  EXPECT_EQ(mn_binding_joint_for_bone(b, 0), -1);

  std::vector<float> own(mn_character_morph_count(s.robot));
  ASSERT_EQ(mn_character_morph_weights(s.robot, own.data(), own.size()), MN_OK);
  float slots[3] = {42.0f, 42.0f, 42.0f};
  ASSERT_EQ(mn_binding_morph_weights(b, slots, 3), MN_OK);
  EXPECT_EQ(slots[0], own[static_cast<size_t>(morphIndex("Surprised"))]);
  EXPECT_EQ(slots[1], 42.0f) << "an unbound slot is the engine's";
  EXPECT_EQ(slots[2], own[static_cast<size_t>(morphIndex("Angry"))]);
  EXPECT_EQ(mn_binding_morph_weights(b, slots, 2), MN_ERROR_INVALID_ARGUMENT);
  mn_binding_destroy(b);
}

TEST(CBinding, BadArgumentsMapsAndStaleHandlesAreRefusedWithAReason) {
  MARIONETTE_REQUIRE_FILE(kRobot);
  MARIONETTE_REQUIRE_FILE(kGodette);
  RobotScene s;
  EngineGodette g;
  mn_binding* b = nullptr;
  auto error = [&] { return std::string(mn_scene_last_error(s.scene)); };
  EXPECT_EQ(mn_binding_create(nullptr, &g.engine, nullptr, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_binding_create(s.robot, nullptr, nullptr, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, nullptr, nullptr), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(b, nullptr);

  mn_engine_skeleton bad = g.engine;
  std::vector<const char*> names = g.namePtrs;
  names[3] = nullptr;
  bad.bone_names = names.data();
  EXPECT_EQ(mn_binding_create(s.robot, &bad, nullptr, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("bone_names[3] is NULL"), std::string::npos) << error();

  mn_binding_options o = mn_binding_options_default();
  o.engine_joint_map = kGodetteMap.c_str();  // without through_joint_maps: would be ignored
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("through_joint_maps is 0"), std::string::npos) << error();
  o.through_joint_maps = 1;
  bad = g.engine;
  bad.parents = nullptr;
  EXPECT_EQ(mn_binding_create(s.robot, &bad, &o, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("needs the engine's parents"), std::string::npos) << error();
  std::vector<int> parents = g.parents;
  parents[5] = static_cast<int>(parents.size());
  bad.parents = parents.data();
  EXPECT_EQ(mn_binding_create(s.robot, &bad, &o, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("bone 5 ('" + g.names[5] + "'): parent " + std::to_string(parents.size())), std::string::npos)
      << error();
  parents = g.parents;
  const int root = static_cast<int>(std::find(parents.begin(), parents.end(), -1) - parents.begin());
  parents[static_cast<size_t>(root)] = root == 0 ? 1 : 0;  // the root under another bone: a cycle, no root left
  bad.parents = parents.data();
  EXPECT_EQ(mn_binding_create(s.robot, &bad, &o, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("is in a cycle of parents"), std::string::npos) << error();

  o.engine_joint_map = "/nonexistent/engine_map.json";
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_ERROR_IO);
  EXPECT_NE(error().find("/nonexistent/engine_map.json: error: cannot open the engine joint map"), std::string::npos)
      << error();
  const std::string broken = ::testing::TempDir() + "c_binding_broken_map.json";
  { std::FILE* f = std::fopen(broken.c_str(), "w"); std::fputs("{\"bones\": {\"hips\": ", f); std::fclose(f); }
  o.engine_joint_map = broken.c_str();
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_ERROR_LOAD);
  EXPECT_NE(error().find(broken + ":1:"), std::string::npos) << error();
  EXPECT_EQ(b, nullptr);
  // An options struct of another size is refused before it is read.
  mn_binding_options sized = mn_binding_options_default();
  EXPECT_EQ(sized.struct_size, sizeof(mn_binding_options));
  sized.struct_size = 0;
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, &sized, &b), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("mn_binding_create: options->struct_size is 0, but this library's mn_binding_options is"),
            std::string::npos)
      << error();
  EXPECT_EQ(b, nullptr);
  // Valid JSON that is not a joint map (a profile here) binds nothing: an error, not MN_OK.
  const std::string notAMap = ::testing::TempDir() + "c_binding_not_a_map.json";
  { std::FILE* f = std::fopen(notAMap.c_str(), "w"); std::fputs("{\"idle\": \"Idle\", \"face\": {}}", f); std::fclose(f); }
  o.engine_joint_map = notAMap.c_str();
  EXPECT_EQ(mn_binding_create(s.robot, &g.engine, &o, &b), MN_ERROR_LOAD);
  EXPECT_NE(error().find(notAMap + ":1:1: error: not a joint map"), std::string::npos) << error();
  EXPECT_EQ(b, nullptr);
  // A joint map given as the character's file is not a character.
  mn_character* notACharacter = nullptr;
  EXPECT_EQ(mn_scene_add_character(s.scene, "map", notAMap.c_str(), nullptr, &notACharacter), MN_ERROR_LOAD);
  EXPECT_NE(error().find(notAMap + ": error: a '.json' file is not a character or motion"), std::string::npos) << error();
  EXPECT_EQ(notACharacter, nullptr);

  ASSERT_EQ(mn_binding_create(s.robot, &g.engine, nullptr, &b), MN_OK);
  std::vector<float> small(10);
  EXPECT_EQ(mn_binding_palette(b, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, small.data(), small.size()), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(error().find("needs " + std::to_string(g.names.size() * 16) + " floats"), std::string::npos) << error();
  EXPECT_EQ(mn_binding_palette(b, static_cast<mn_palette_layout>(7), 1, small.data(), small.size()), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(mn_binding_palette(b, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, nullptr, 0), MN_ERROR_INVALID_ARGUMENT);

  // The character removed: the binding is refused, not a use after free.
  ASSERT_EQ(mn_scene_remove_character(s.scene, s.robot), MN_OK);
  std::vector<float> palette(g.names.size() * 16);
  EXPECT_EQ(mn_binding_palette(b, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette.data(), palette.size()), MN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(mn_scene_last_error(nullptr)).find("the binding's character was removed"), std::string::npos)
      << mn_scene_last_error(nullptr);
  EXPECT_EQ(mn_binding_morph_weights(b, palette.data(), palette.size()), MN_ERROR_INVALID_ARGUMENT);
  mn_binding_destroy(b);
  mn_binding_destroy(b);  // a second destroy is refused quietly
  EXPECT_EQ(mn_binding_bone_count(b), 0u);
  EXPECT_STREQ(mn_binding_report(b), "");
  mn_binding_destroy(nullptr);
}
