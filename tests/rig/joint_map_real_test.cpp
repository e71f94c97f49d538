// Joint maps (rig/joint_map.hpp): the guess on every real skeleton we read,
// checked joint by joint against the hierarchies printed and verified by hand;
// loadJointMap's diagnostics; the JSON round trip; the name conventions and a
// skeleton whose names lie about its topology; and every shipped map
// (assets/jointmaps/*.json) against its skeletons. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/rig/joint_map.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::retarget;
using namespace marionette::test;

namespace {

Asset importSkeleton(const std::string& path) {
  ImportOptions o;
  o.loadMeshes = false;
  o.loadAnimations = false;
  ImportResult r = importAsset(path, o);
  EXPECT_TRUE(r.asset.has_value()) << r.diagnostics.format();
  return r.asset ? std::move(*r.asset) : Asset{};
}

std::string name(const Skeleton& s, int j) {
  return j >= 0 && static_cast<std::size_t>(j) < s.names.size() ? s.names[static_cast<std::size_t>(j)] : std::string();
}

std::string notesOf(const JointMapResult& r) {
  std::string out;
  for (const auto& n : r.map.notes) out += "  note: " + n + '\n';
  return out + r.diagnostics.format();
}

bool hasNote(const JointMap& m, const std::string& part) {
  for (const auto& n : m.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

// Diagnostics whose message contains `part`.
int count(const Diagnostics& d, const std::string& part) {
  int n = 0;
  for (const auto& i : d.items) n += i.message.find(part) != std::string::npos;
  return n;
}

// What a skeleton's map must be, by joint name ("" = absent).
struct Expected {
  std::map<Bone, std::string> bones;  // bones left out here must be absent
  std::map<Chain, std::vector<std::string>> chains;  // chains left out here must be empty
};

void expectMap(const JointMap& m, const Skeleton& s, const Expected& e, const std::string& context) {
  for (int b = 0; b < kBoneCount; ++b) {
    const auto bone = static_cast<Bone>(b);
    const auto it = e.bones.find(bone);
    EXPECT_EQ(name(s, m.joint(bone)), it == e.bones.end() ? "" : it->second) << context << ": " << boneName(bone);
  }
  for (int c = 0; c < kChainCount; ++c) {
    const auto chain = static_cast<Chain>(c);
    std::vector<std::string> got;
    for (int j : m.chain(chain)) got.push_back(name(s, j));
    const auto it = e.chains.find(chain);
    EXPECT_EQ(got, it == e.chains.end() ? std::vector<std::string>{} : it->second) << context << ": " << chainName(chain);
  }
}

// The body every map has; "" where a skeleton has no such joint. Arms: clavicle,
// upper arm, forearm, hand; legs: thigh, shin, foot, toes.
using Four = std::array<std::string, 4>;
Expected body(const std::string& hips, const std::string& head, std::vector<std::string> spine,
              std::vector<std::string> neck, const Four& leftArm, const Four& rightArm, const Four& leftLeg,
              const Four& rightLeg) {
  Expected e;
  e.bones[Bone::Hips] = hips;
  e.bones[Bone::Head] = head;
  const std::pair<Bone, const Four*> parts[] = {{Bone::LeftShoulder, &leftArm},
                                                {Bone::RightShoulder, &rightArm},
                                                {Bone::LeftUpperLeg, &leftLeg},
                                                {Bone::RightUpperLeg, &rightLeg}};
  for (const auto& [first, names] : parts)
    for (int k = 0; k < 4; ++k) e.bones[static_cast<Bone>(static_cast<int>(first) + k)] = (*names)[static_cast<std::size_t>(k)];
  e.chains[Chain::Spine] = std::move(spine);
  e.chains[Chain::Neck] = std::move(neck);
  return e;
}

// A guess with no warning (nothing missing, duplicated or contradicted by topology).
JointMapResult cleanGuess(const Asset& a) {
  JointMapResult r = guessJointMap(a);
  EXPECT_TRUE(r.diagnostics.items.empty()) << a.sourcePath << '\n' << notesOf(r);
  return r;
}

// ---- Expectations for the real skeletons (hierarchies printed and checked) ----

Expected robotExpressive() {
  // The legs hang from Body; "Hips" turns the upper body only. No hand joint, no toes.
  Expected e = body("Body", "Head", {"Hips", "Abdomen", "Torso"}, {"Neck"},
                    {"Shoulder.L", "UpperArm.L", "LowerArm.L", ""}, {"Shoulder.R", "UpperArm.R", "LowerArm.R", ""},
                    {"UpperLeg.L", "LowerLeg.L", "Foot.L", ""}, {"UpperLeg.R", "LowerLeg.R", "Foot.R", ""});
  for (const char* s : {"L", "R"}) {
    const std::string x = std::string(".") + s;
    const int base = s[0] == 'L' ? 0 : 5;
    e.chains[static_cast<Chain>(2 + base)] = {"Thumb" + x, "Thumb2" + x};
    e.chains[static_cast<Chain>(3 + base)] = {"Index" + x, "Index2" + x};
    e.chains[static_cast<Chain>(4 + base)] = {"Middle1" + x, "Middle2" + x};
    e.chains[static_cast<Chain>(5 + base)] = {"Ring1" + x, "Ring2" + x};
  }
  return e;
}

Expected godette() {
  auto arm = [](const std::string& x) { return Four{"shoulder" + x, "upper_arm" + x, "lowerarm" + x, "hand" + x}; };
  auto leg = [](const std::string& x) { return Four{"thigh" + x, "shin" + x, "foot" + x, "toes" + x}; };
  const std::string l = ".l_Armature", r = ".r_Armature";
  Expected e = body("pelvis_Armature", "head_Armature", {"tummy_Armature", "chest_Armature"}, {"neck_Armature"}, arm(l),
                    arm(r), leg(l), leg(r));
  for (int side = 0; side < 2; ++side) {
    const std::string& x = side == 0 ? l : r;
    const int c = side * 5;
    e.chains[static_cast<Chain>(2 + c)] = {"thumb.1" + x, "thumb.2" + x, "thumb.3" + x};
    e.chains[static_cast<Chain>(3 + c)] = {"Finger" + x, "Finger.001" + x, "Finger.002" + x};
    e.chains[static_cast<Chain>(4 + c)] = {"f2a" + x, "f2b" + x, "f2c" + x};
    e.chains[static_cast<Chain>(6 + c)] = {"f3a" + x, "f3b" + x, "f3c" + x};  // no ring finger
  }
  return e;
}

// CesiumMan's joints are unnamed: the importer calls them after their glTF nodes.
Expected cesiumMan() {
  return body("node_2", "node_20", {"node_11", "node_12"}, {"node_19"}, {"", "node_16", "node_17", "node_18"},
              {"", "node_13", "node_14", "node_15"}, {"node_7", "node_8", "node_9", "node_10"},
              {"node_3", "node_4", "node_5", "node_6"});
}

Expected vrmAnimation() {
  Expected e;
  for (int b = 0; b < kBoneCount; ++b) e.bones[static_cast<Bone>(b)] = std::string(boneName(static_cast<Bone>(b)));
  for (Bone b : {Bone::LeftEye, Bone::RightEye, Bone::Jaw}) e.bones.erase(b);
  e.chains[Chain::Spine] = {"spine", "chest"};
  e.chains[Chain::Neck] = {"neck"};
  for (int c = static_cast<int>(Chain::LeftThumb); c < kChainCount; ++c) {
    const std::string f(chainName(static_cast<Chain>(c)));
    e.chains[static_cast<Chain>(c)] = c == static_cast<int>(Chain::LeftThumb) || c == static_cast<int>(Chain::RightThumb)
                                          ? std::vector<std::string>{f + "Metacarpal", f + "Proximal", f + "Distal"}
                                          : std::vector<std::string>{f + "Proximal", f + "Intermediate", f + "Distal"};
  }
  return e;
}

#ifdef MARIONETTE_HAS_ASSIMP
Expected pab() {
  // The legs hang from Spine, below Hips and Pelvis.
  Expected e = body("Spine", "Head", {"Spine1", "Spine2", "Spine3"}, {"Neck"},
                    {"LeftShoulder", "LeftArm", "LeftForeArm", "Lefthand"},
                    {"RightShoulder", "RightArm", "RightForeArm", "RightHand"},
                    {"LeftUpLeg", "LeftLeg", "LeftFoot", "LeftFootThumb1"},
                    {"RightUpLeg", "RightLeg", "RightFoot", "RightFootThumb1"});
  for (const char* side : {"Left", "Right"}) {
    const int c = side[0] == 'L' ? 0 : 5;
    auto three = [&](const std::string& f) {
      const std::string p = std::string(side) + "Hand" + f;
      return std::vector<std::string>{p + "1", p + "2", p + "3"};
    };
    e.chains[static_cast<Chain>(2 + c)] = three("Thumb");
    e.chains[static_cast<Chain>(3 + c)] = three("Index");
    e.chains[static_cast<Chain>(4 + c)] = three("Middle");
    e.chains[static_cast<Chain>(5 + c)] = three("Ring");
    e.chains[static_cast<Chain>(6 + c)] = three(c == 0 ? "RingPinky" : "Pinky");  // Pab's left pinky name
  }
  return e;
}

// CMU, MotionBuilder-friendly names: LeftShoulder is the clavicle.
Expected cmuMotionBuilder() {
  Expected e = body("Hips", "Head", {"LowerBack", "Spine", "Spine1"}, {"Neck", "Neck1"},
                    {"LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand"},
                    {"RightShoulder", "RightArm", "RightForeArm", "RightHand"},
                    {"LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"}, {"RightUpLeg", "RightLeg", "RightFoot", "RightToeBase"});
  e.chains[Chain::LeftThumb] = {"LThumb"};
  e.chains[Chain::RightThumb] = {"RThumb"};
  return e;
}

// CMU, 3ds Max-friendly names: LeftShoulder is the upper arm, LeftCollar the clavicle.
Expected cmuMax() {
  Expected e = body("Hips", "Head", {"lowerback", "Chest", "Chest2"}, {"lowerneck", "Neck"},
                    {"LeftCollar", "LeftShoulder", "LeftElbow", "LeftWrist"},
                    {"RightCollar", "RightShoulder", "RightElbow", "RightWrist"},
                    {"LeftHip", "LeftKnee", "LeftAnkle", "LeftToe"}, {"RightHip", "RightKnee", "RightAnkle", "RightToe"});
  e.chains[Chain::LeftThumb] = {"LThumb"};
  e.chains[Chain::RightThumb] = {"RThumb"};
  return e;
}

Expected pirouette() {
  Expected e = body("hip", "head", {"abdomen", "chest"}, {"neck"}, {"lCollar", "lShldr", "lForeArm", "lHand"},
                    {"rCollar", "rShldr", "rForeArm", "rHand"}, {"lThigh", "lShin", "lFoot", ""},
                    {"rThigh", "rShin", "rFoot", ""});
  e.bones[Bone::LeftEye] = "leftEye";
  e.bones[Bone::RightEye] = "rightEye";
  for (const char* s : {"l", "r"}) {
    const int c = s[0] == 'l' ? 0 : 5;
    int f = 0;
    for (const char* finger : {"Thumb", "Index", "Mid", "Ring", "Pinky"})
      e.chains[static_cast<Chain>(2 + c + f++)] = {std::string(s) + finger + "1", std::string(s) + finger + "2"};
  }
  return e;
}

Expected boxingToes() {
  return body("Hips", "Head", {"Ab", "Chest"}, {"Neck"}, {"LeftCollar", "LeftShoulder", "LeftElbow", "LeftWrist"},
              {"RightCollar", "RightShoulder", "RightElbow", "RightWrist"}, {"LeftHip", "LeftKnee", "LeftAnkle", "LeftToes"},
              {"RightHip", "RightKnee", "RightAnkle", "RightToes"});
}

Expected bcnEpileptic() {
  // The root node "Head" is a mesh; B_Neck carries the eyes and the jaw.
  auto arm = [](const std::string& s) { return Four{"B_Clavicle_" + s, "B_UpperArm_" + s, "B_ForeArm_" + s, "B_Hand_" + s}; };
  auto leg = [](const std::string& s) { return Four{"B_Hip_" + s, "B_Knee_" + s, "B_Ankle_" + s, "B_Toe_" + s}; };
  Expected e = body("B_Root_Pelvis_L", "B_Neck", {"B_Root_Pelvis_T", "B_Spine1", "B_Spine2", "B_Spine3", "B_Spine4"},
                    {"B_Root_Neck_T", "B_Root_Neck_H"}, arm("Left"), arm("Right"), leg("Left"), leg("Right"));
  e.bones[Bone::LeftEye] = "B_Eye_Left";
  e.bones[Bone::RightEye] = "B_Eye_Right";
  e.bones[Bone::Jaw] = "B_Jaw";
  e.chains[Chain::LeftThumb] = {"B_Thumb1_Left", "B_Thumb2_Left"};
  e.chains[Chain::RightThumb] = {"B_Thumb1_Right", "B_Thumb2_Right"};
  return e;
}
#endif

}  // namespace

// ---- The guess on real skeletons -------------------------------------------

TEST(JointMapGuess, RobotExpressiveHipsFromTopologyAndNoHands) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  const Asset a = importSkeleton(path);
  const JointMapResult r = guessJointMap(a);
  expectMap(r.map, a.skeleton, robotExpressive(), path);
  // No joint turns the whole hand (palms and thumb hang from the forearm): reported.
  EXPECT_EQ(r.diagnostics.items.size(), 1u) << notesOf(r);
  EXPECT_EQ(count(r.diagnostics, "required bones not found: leftHand, rightHand"), 1) << notesOf(r);
  EXPECT_TRUE(hasNote(r.map, "hips: 'Body', not 'Hips'")) << notesOf(r);
}

TEST(JointMapGuess, GodetteFromTheVrmHumanoidMap) {
  const std::string path = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(path);
  const Asset a = importSkeleton(path);
  ASSERT_TRUE(a.hasHumanoid);
  const JointMapResult r = cleanGuess(a);
  EXPECT_TRUE(hasNote(r.map, "VRM humanoid map")) << notesOf(r);
  expectMap(r.map, a.skeleton, godette(), path);
}

TEST(JointMapGuess, CesiumManFromShapeAndRestPose) {
  const std::string path = sharedAsset("characters/CesiumMan.glb");
  MARIONETTE_REQUIRE_FILE(path);
  const Asset a = importSkeleton(path);
  const JointMapResult r = cleanGuess(a);
  expectMap(r.map, a.skeleton, cesiumMan(), path);
  EXPECT_TRUE(hasNote(r.map, "not found (the skeleton may have none): leftShoulder, rightShoulder")) << notesOf(r);
}

TEST(JointMapGuess, VrmAnimationFromItsHumanoidMap) {
  const std::string path = sharedAsset("motions/gltf/three-vrm_test.vrma");
  MARIONETTE_REQUIRE_FILE(path);
  const Asset a = importSkeleton(path);
  const JointMapResult r = cleanGuess(a);
  expectMap(r.map, a.skeleton, vrmAnimation(), path);
}

#ifdef MARIONETTE_HAS_ASSIMP
TEST(JointMapGuess, PabCharacterAndMotionsShareOneMap) {
  for (const std::string& path : {sharedAsset("characters/pab_arnaud.fbx"), sharedAsset("motions/fbx/pab_walk.fbx"),
                                  sharedAsset("motions/fbx/pab_jog.fbx"), sharedAsset("motions/fbx/pab_crossarms.fbx")}) {
    MARIONETTE_REQUIRE_FILE(path);
    const Asset a = importSkeleton(path);
    const JointMapResult r = cleanGuess(a);
    expectMap(r.map, a.skeleton, pab(), path);
    EXPECT_TRUE(hasNote(r.map, "hips: 'Spine', not 'Pelvis'")) << path << '\n' << notesOf(r);
    // pab_jog's rest pose is mid-stride, its right toes pointing back: the knees give the facing.
    if (path.find("pab_jog") != std::string::npos) {
      EXPECT_TRUE(hasNote(r.map, "lie on the character's left in the rest pose (it faces +Z, from the knees")) << notesOf(r);
    }
  }
}

TEST(JointMapGuess, CmuMotionBuilderNamesLeftShoulderIsTheClavicle) {
  for (const std::string& path : {sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), assimpModel("BVH/01_01.bvh"),
                                  assimpModel("BVH/01_03.bvh")}) {
    MARIONETTE_REQUIRE_FILE(path);
    const Asset a = importSkeleton(path);
    const JointMapResult r = cleanGuess(a);
    expectMap(r.map, a.skeleton, cmuMotionBuilder(), path);
    EXPECT_TRUE(hasNote(r.map, "leftShoulder: 'LeftShoulder' is the clavicle here")) << path << '\n' << notesOf(r);
  }
}

TEST(JointMapGuess, CmuMaxNamesLeftShoulderIsTheUpperArmAndSaysSo) {
  const std::string path = sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh");
  MARIONETTE_REQUIRE_FILE(path);
  const Asset a = importSkeleton(path);
  const JointMapResult r = cleanGuess(a);
  expectMap(r.map, a.skeleton, cmuMax(), path);
  EXPECT_TRUE(hasNote(r.map, "leftUpperArm: 'LeftShoulder' is the upper arm here (the joint above the elbow, below the "
                             "clavicle 'LeftCollar'), though the name is the clavicle's in other conventions"))
      << notesOf(r);
  EXPECT_TRUE(hasNote(r.map, "rightUpperArm: 'RightShoulder' is the upper arm here")) << notesOf(r);
}

TEST(JointMapGuess, PirouetteBoxingToesAndBcn) {
  const std::vector<std::pair<std::string, Expected>> cases = {
      {sharedAsset("motions/bvh/pirouette.bvh"), pirouette()},
      {assimpModel("BVH/Boxing_Toes.bvh"), boxingToes()},
      {assimpModel("X/BCN_Epileptic.X"), bcnEpileptic()}};
  for (const auto& [path, expected] : cases) {
    MARIONETTE_REQUIRE_FILE(path);
    const Asset a = importSkeleton(path);
    const JointMapResult r = cleanGuess(a);
    expectMap(r.map, a.skeleton, expected, path);
  }
}
#endif

// ---- loadJointMap diagnostics ------------------------------------------------

namespace {

// A small humanoid facing +Z (left is +X), with toes, clavicles and one finger.
// `rename` may change any joint's name (to make the names lie).
Skeleton humanoid(const std::function<std::string(const std::string&)>& rename = {}) {
  Skeleton s;
  auto add = [&](const std::string& n, int parent, glm::vec3 offset) {
    return s.addJoint(rename ? rename(n) : n, parent, Transform{offset, glm::quat(1, 0, 0, 0), glm::vec3(1)});
  };
  const int hips = add("Hips", -1, {0, 1.0f, 0});
  const int spine = add("Spine", hips, {0, 0.15f, 0});
  const int chest = add("Chest", spine, {0, 0.2f, 0});
  const int neck = add("Neck", chest, {0, 0.2f, 0});
  add("Head", neck, {0, 0.1f, 0});
  for (const char* side : {"Left", "Right"}) {
    const float x = side[0] == 'L' ? 1.0f : -1.0f;
    const std::string S(side);
    const int clav = add(S + "Shoulder", chest, {x * 0.05f, 0.15f, 0});
    const int arm = add(S + "Arm", clav, {x * 0.1f, 0, 0});
    const int fore = add(S + "ForeArm", arm, {x * 0.25f, 0, 0});
    const int hand = add(S + "Hand", fore, {x * 0.25f, 0, 0});
    const int idx = add(S + "HandIndex1", hand, {x * 0.08f, 0, 0.01f});
    add(S + "HandIndex2", idx, {x * 0.03f, 0, 0});
    const int up = add(S + "UpLeg", hips, {x * 0.1f, -0.05f, 0});
    const int leg = add(S + "Leg", up, {0, -0.45f, 0.02f});
    const int foot = add(S + "Foot", leg, {0, -0.45f, -0.02f});
    add(S + "ToeBase", foot, {0, -0.05f, 0.12f});
  }
  return s;
}

Asset assetOf(Skeleton s) {
  Asset a;
  a.sourcePath = "synthetic";
  a.skeleton = std::move(s);
  return a;
}

// Writes `text` to a temporary file named after the test; returns its path.
std::string writeMap(const std::string& text) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() / "marionette_joint_map_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / (std::string(info->test_suite_name()) + "." + info->name() + ".json");
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// A complete, correct map of humanoid() as JSON, with `extra` spliced into "bones".
std::string goodMap(const std::string& bonesExtra = "", const std::string& chainsExtra = "") {
  return R"({
  "comment": "test",
  "bones": {
    "hips": "Hips", "head": "Head",
    "leftShoulder": "LeftShoulder", "leftUpperArm": "LeftArm", "leftLowerArm": "LeftForeArm", "leftHand": "LeftHand",
    "rightShoulder": "RightShoulder", "rightUpperArm": "RightArm", "rightLowerArm": "RightForeArm", "rightHand": "RightHand",
    "leftUpperLeg": "LeftUpLeg", "leftLowerLeg": "LeftLeg", "leftFoot": "LeftFoot", "leftToes": "LeftToeBase",
    "rightUpperLeg": "RightUpLeg", "rightLowerLeg": "RightLeg", "rightFoot": "RightFoot", "rightToes": "RightToeBase")" +
         bonesExtra + R"(
  },
  "chains": {
    "spine": ["Spine", "Chest"], "neck": ["Neck"],
    "leftIndex": ["LeftHandIndex1", "LeftHandIndex2"], "rightIndex": ["RightHandIndex1", "RightHandIndex2"])" +
         chainsExtra + R"(
  }
}
)";
}

}  // namespace

TEST(JointMapLoad, AGoodMapLoadsWithoutDiagnosticsAndMatchesTheGuess) {
  const Asset a = assetOf(humanoid());
  const JointMapResult r = loadJointMap(writeMap(goodMap()), a);
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  const JointMapResult g = cleanGuess(a);
  EXPECT_EQ(r.map.bones, g.map.bones);
  EXPECT_EQ(r.map.chains, g.map.chains);
  EXPECT_EQ(r.map.canonicalName(a.skeleton.findJoint("Chest")), "spine[1]");
  EXPECT_EQ(r.map.canonicalName(a.skeleton.findJoint("LeftArm")), "leftUpperArm");
}

TEST(JointMapLoad, BadJsonIsAnErrorWithLineAndColumn) {
  const std::string path = writeMap("{\n  \"bones\": {\n    \"hips\": \"Hips\",,\n  }\n}\n");
  const JointMapResult r = loadJointMap(path, assetOf(humanoid()));
  ASSERT_FALSE(r.diagnostics.ok());
  ASSERT_EQ(r.diagnostics.items.size(), 1u) << r.diagnostics.format();
  const Diagnostic& d = r.diagnostics.items[0];
  EXPECT_EQ(d.file, path);
  EXPECT_EQ(d.line, 3);
  EXPECT_EQ(d.column, 20);
  EXPECT_NE(d.message.find("syntax error"), std::string::npos) << d.message;
}

TEST(JointMapLoad, AMissingFileIsAnError) {
  const JointMapResult r = loadJointMap("/nonexistent/dir/map.json", assetOf(humanoid()));
  EXPECT_FALSE(r.diagnostics.ok());
  EXPECT_EQ(count(r.diagnostics, "cannot read the joint map '/nonexistent/dir/map.json'"), 1) << r.diagnostics.format();
}

TEST(JointMapLoad, UnknownBoneAndChainKeysAreWarnedAtTheKey) {
  const std::string path = writeMap(goodMap(",\n    \"leftElbow\": \"LeftForeArm\"", ",\n    \"tail\": []"));
  const JointMapResult r = loadJointMap(path, assetOf(humanoid()));
  ASSERT_EQ(r.diagnostics.items.size(), 2u) << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items[0].line, 9);
  EXPECT_EQ(r.diagnostics.items[0].column, 5);
  EXPECT_NE(r.diagnostics.items[0].message.find("bones/leftElbow: unknown bone 'leftElbow' ignored"), std::string::npos)
      << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items[1].line, 14);
  EXPECT_NE(r.diagnostics.items[1].message.find("chains/tail: unknown chain 'tail'"), std::string::npos)
      << r.diagnostics.format();
}

TEST(JointMapLoad, AJointNameTheSkeletonLacksIsWarnedAtItsValue) {
  std::string text = goodMap();
  text.replace(text.find("\"LeftForeArm\""), 13, "\"LeftLowArm\"");
  const JointMapResult r = loadJointMap(writeMap(text), assetOf(humanoid()));
  EXPECT_EQ(r.map.joint(Bone::LeftLowerArm), -1);
  EXPECT_EQ(count(r.diagnostics, "bones/leftLowerArm: no joint named 'LeftLowArm' in the skeleton; ignored"), 1)
      << r.diagnostics.format();
  EXPECT_EQ(count(r.diagnostics, "required bones not mapped: leftLowerArm"), 1) << r.diagnostics.format();
  for (const auto& d : r.diagnostics.items) {
    if (d.message.find("LeftLowArm") == std::string::npos) continue;
    EXPECT_EQ(d.line, 5);
    EXPECT_EQ(d.column, 80);
  }
}

TEST(JointMapLoad, AJointMappedTwiceKeepsItsFirstEntry) {
  // Bones come first, then chains in canonical order (the thumb before the index).
  const std::string path = writeMap(goodMap(",\n    \"jaw\": \"Head\"", ",\n    \"leftThumb\": [\"LeftHandIndex2\"]"));
  const JointMapResult r = loadJointMap(path, assetOf(humanoid()));
  EXPECT_EQ(r.map.joint(Bone::Jaw), -1);
  EXPECT_EQ(r.map.chain(Chain::LeftIndex).size(), 1u);
  EXPECT_EQ(r.map.chain(Chain::LeftThumb).size(), 1u);
  EXPECT_EQ(count(r.diagnostics, "bones/jaw: joint 'Head' is already mapped as head (bones/head); dropped here"), 1)
      << r.diagnostics.format();
  EXPECT_EQ(count(r.diagnostics, "chains/leftIndex/1: joint 'LeftHandIndex2' is already mapped as leftThumb[0] "
                                 "(chains/leftThumb/0); dropped here"),
            1)
      << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items.size(), 2u) << r.diagnostics.format();
  for (const auto& d : r.diagnostics.items)
    if (d.message.find("leftIndex/1") != std::string::npos) {
      EXPECT_EQ(std::pair(d.line, d.column), std::pair(13, 37));
    }
}

TEST(JointMapLoad, IndicesOutOfRangeOrMalformedAreWarned) {
  const Skeleton s = humanoid();
  std::string text = goodMap(",\n    \"jaw\": \"#99\", \"leftEye\": \"#1x\"");
  text.replace(text.find("\"Hips\""), 6, "\"#0\"");  // "#N" in range is fine
  const JointMapResult r = loadJointMap(writeMap(text), assetOf(s));
  EXPECT_EQ(r.map.joint(Bone::Hips), 0);
  EXPECT_EQ(count(r.diagnostics, "bones/jaw: joint index #99 out of range: the skeleton has " +
                                     std::to_string(s.jointCount()) + " joints (#0 to #" +
                                     std::to_string(s.jointCount() - 1) + "); ignored"),
            1)
      << r.diagnostics.format();
  EXPECT_EQ(count(r.diagnostics, "bones/leftEye: '#1x' is neither a joint name nor \"#N\""), 1) << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items.size(), 2u) << r.diagnostics.format();
}

TEST(JointMapLoad, MissingRequiredBonesAndUnsaidExpectedOnesAreWarnedByName) {
  const std::string path = writeMap(R"({"bones": {"hips": "Hips", "head": "Head", "leftToes": ""}, "chains": {"spine": []}})");
  const JointMapResult r = loadJointMap(path, assetOf(humanoid()));
  EXPECT_TRUE(r.diagnostics.ok());
  EXPECT_EQ(count(r.diagnostics, "required bones not mapped: leftUpperArm, leftLowerArm, leftHand, rightUpperArm, "
                                 "rightLowerArm, rightHand, leftUpperLeg, leftLowerLeg, leftFoot, rightUpperLeg, "
                                 "rightLowerLeg, rightFoot"),
            1)
      << r.diagnostics.format();
  // leftToes and the spine are declared absent (""/[]); the others are not said at all.
  EXPECT_EQ(count(r.diagnostics, "not in the file: leftShoulder, rightShoulder, rightToes, neck"), 1)
      << r.diagnostics.format();
  for (const auto& d : r.diagnostics.items) {
    EXPECT_EQ(d.line, 1) << d.format();
    EXPECT_EQ(d.column, 11) << d.format();  // at the "bones" object
  }
}

// "" for a required bone is the author's statement that the skeleton has none
// (RobotExpressive has no hand joints): a note, so that a retarget onto it exits 0.
TEST(JointMapLoad, RequiredBonesDeclaredAbsentAreNotesNotWarnings) {
  std::string text = goodMap();
  text.replace(text.find("\"LeftHand\""), 10, "\"\"");
  const JointMapResult r = loadJointMap(writeMap(text), assetOf(humanoid()));
  EXPECT_EQ(r.map.joint(Bone::LeftHand), -1);
  EXPECT_EQ(count(r.diagnostics, "required bones"), 0) << r.diagnostics.format();
  EXPECT_TRUE(hasNote(r.map, "required bones the file declares absent (\"\"): leftHand")) << notesOf(r);
  // A name that does not resolve is still an oversight, and warned.
  std::string typo = goodMap();
  typo.replace(typo.find("\"LeftHand\""), 10, "\"LeftHnad\"");
  const JointMapResult w = loadJointMap(writeMap(typo), assetOf(humanoid()));
  EXPECT_EQ(count(w.diagnostics, "required bones not mapped: leftHand"), 1) << w.diagnostics.format();
}

TEST(JointMapLoad, TopologyContradictionsAreWarned) {
  std::string text = goodMap();
  // Upper and lower arm swapped: the lower arm is then above the upper one.
  text.replace(text.find("\"LeftArm\""), 9, "\"LeftXXX\"");
  text.replace(text.find("\"LeftForeArm\""), 13, "\"LeftArm\"");
  text.replace(text.find("\"LeftXXX\""), 9, "\"LeftForeArm\"");
  const JointMapResult r = loadJointMap(writeMap(text), assetOf(humanoid()));
  EXPECT_EQ(count(r.diagnostics, "bones/leftLowerArm: leftLowerArm 'LeftArm' is not below leftUpperArm 'LeftForeArm'"), 1)
      << r.diagnostics.format();
  EXPECT_EQ(count(r.diagnostics, "bones/leftHand: leftHand 'LeftHand' is not the child of leftLowerArm 'LeftArm': "
                                 "'LeftForeArm' lies between"),
            1)
      << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items.size(), 2u) << r.diagnostics.format();
}

TEST(JointMapLoad, LeftAndRightSwappedAreWarnedFromTheRestPose) {
  std::string text = goodMap();
  for (const char* j : {"UpLeg", "Leg\"", "Foot", "ToeBase"}) {  // the legs only: the arms stay right
    const std::string l = std::string("\"Left") + j, r = std::string("\"Right") + j;
    text.replace(text.find(l), l.size(), "\"TMP" + std::string(j));
    text.replace(text.find(r), r.size(), l);
    text.replace(text.find("\"TMP" + std::string(j)), 4 + std::string(j).size(), r);
  }
  const JointMapResult r = loadJointMap(writeMap(text), assetOf(humanoid()));
  EXPECT_EQ(count(r.diagnostics, "bones/leftUpperLeg: leftUpperLeg 'RightUpLeg' lies on the character's right of "
                                 "rightUpperLeg 'LeftUpLeg' in the rest pose (it faces +Z, from the toes; its left is +X)"),
            1)
      << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items.size(), 1u) << r.diagnostics.format();
}

TEST(JointMapLoad, DuplicateKeysAndAmbiguousNamesAreWarned) {
  Skeleton s = humanoid();
  s.addJoint("Head", s.findJoint("Head"), Transform{glm::vec3(0, 0.1f, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
  const std::string path = writeMap(goodMap(",\n    \"hips\": \"Hips\""));
  const JointMapResult r = loadJointMap(path, assetOf(s));
  EXPECT_EQ(count(r.diagnostics, "bones/hips: duplicate key; the last one is used"), 1) << r.diagnostics.format();
  EXPECT_EQ(count(r.diagnostics, "bones/head: 2 joints are named 'Head': the first one (#4) is used"), 1)
      << r.diagnostics.format();
}

// ---- Round trip --------------------------------------------------------------

TEST(JointMapJson, RoundTripEqualsOnEveryRealSkeleton) {
  std::vector<std::string> paths = {sharedAsset("characters/RobotExpressive.glb"), sharedAsset("characters/Godette_vrm_v4.vrm"),
                                    sharedAsset("characters/CesiumMan.glb"), sharedAsset("motions/gltf/three-vrm_test.vrma")};
#ifdef MARIONETTE_HAS_ASSIMP
  for (const char* p : {"characters/pab_arnaud.fbx", "motions/fbx/pab_walk.fbx", "motions/bvh/cmu_01_01_mbfriendly.bvh",
                        "motions/bvh/cmu_131_01_maxfriendly.bvh", "motions/bvh/pirouette.bvh"})
    paths.push_back(sharedAsset(p));
  for (const char* p : {"BVH/Boxing_Toes.bvh", "X/BCN_Epileptic.X"}) paths.push_back(assimpModel(p));
#endif
  for (const auto& path : paths) {
    MARIONETTE_REQUIRE_FILE(path);
    const Asset a = importSkeleton(path);
    const JointMapResult g = guessJointMap(a);
    const std::string text = jointMapJson(g.map, a.skeleton);
    const JointMapResult back = loadJointMap(writeMap(text), a);
    EXPECT_EQ(back.map.bones, g.map.bones) << path << '\n' << text;
    EXPECT_EQ(back.map.chains, g.map.chains) << path << '\n' << text;
    // The file says "" for what the guess found missing: the written map declares those
    // bones absent (a note); nothing else to warn about.
    const int missing = count(g.diagnostics, "required bones not found");
    EXPECT_EQ(back.diagnostics.items.size() + static_cast<std::size_t>(missing), g.diagnostics.items.size())
        << path << '\n' << back.diagnostics.format();
    EXPECT_EQ(hasNote(back.map, "required bones the file declares absent"), missing > 0) << path << '\n' << notesOf(back);
  }
}

TEST(JointMapJson, UnnamedAndDuplicateNamesAreWrittenByIndex) {
  Skeleton s = humanoid();
  s.names[static_cast<std::size_t>(s.findJoint("Head"))] = "#7";  // a name that reads as an index
  s.names[static_cast<std::size_t>(s.findJoint("Neck"))] = "";
  JointMap m;
  m.bones[static_cast<std::size_t>(Bone::Head)] = 4;
  m.chains[static_cast<std::size_t>(Chain::Neck)] = {3};
  m.bones[static_cast<std::size_t>(Bone::Hips)] = 0;
  const std::string text = jointMapJson(m, s);
  EXPECT_NE(text.find("\"head\": \"#4\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"neck\": [\"#3\"]"), std::string::npos) << text;
  EXPECT_NE(text.find("\"hips\": \"Hips\""), std::string::npos) << text;
  const JointMapResult back = loadJointMap(writeMap(text), assetOf(s));
  EXPECT_EQ(back.map.bones, m.bones);
  EXPECT_EQ(back.map.chains, m.chains);
}

// ---- Name conventions on synthetic skeletons ----------------------------------

namespace {

// humanoid() with its limb names in another convention: `side(S, part)` builds
// the name from "Left"/"Right" and a part in that convention.
struct Convention {
  const char* what;
  std::function<std::string(bool left, const std::string& part)> name;
  std::map<std::string, std::string> parts;  // Mixamo part -> this convention's part
};

void checkConvention(const Convention& c) {
  SCOPED_TRACE(c.what);
  const Skeleton s = humanoid([&](const std::string& n) {
    for (const char* side : {"Left", "Right"}) {
      if (n.rfind(side, 0) != 0) continue;
      const std::string part = n.substr(std::string(side).size());
      const auto it = c.parts.find(part);
      return c.name(side[0] == 'L', it != c.parts.end() ? it->second : part);
    }
    return n;
  });
  const Asset a = assetOf(s);
  const JointMapResult r = cleanGuess(a);
  auto expectJoint = [&](Bone b, bool left, const std::string& mixamo) {
    const auto it = c.parts.find(mixamo);
    EXPECT_EQ(name(s, r.map.joint(b)), c.name(left, it != c.parts.end() ? it->second : mixamo)) << boneName(b) << '\n'
                                                                                               << notesOf(r);
  };
  for (bool left : {true, false}) {
    const int o = left ? 0 : 4;
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftShoulder) + o), left, "Shoulder");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftUpperArm) + o), left, "Arm");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftLowerArm) + o), left, "ForeArm");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftHand) + o), left, "Hand");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftUpperLeg) + o), left, "UpLeg");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftLowerLeg) + o), left, "Leg");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftFoot) + o), left, "Foot");
    expectJoint(static_cast<Bone>(static_cast<int>(Bone::LeftToes) + o), left, "ToeBase");
  }
  EXPECT_EQ(name(s, r.map.joint(Bone::Hips)), "Hips");
  EXPECT_EQ(r.map.chain(Chain::Spine).size(), 2u) << notesOf(r);
}

}  // namespace

TEST(JointMapConventions, SidesAndPartWordsOfTheCommonConventions) {
  using P = std::map<std::string, std::string>;
  const P ue = {{"Shoulder", "clavicle"}, {"Arm", "upperarm"}, {"ForeArm", "lowerarm"}, {"Hand", "hand"},
                {"UpLeg", "thigh"},       {"Leg", "calf"},     {"Foot", "foot"},        {"ToeBase", "ball"},
                {"HandIndex1", "index_01"}, {"HandIndex2", "index_02"}};
  const P blender = {{"Shoulder", "shoulder"}, {"Arm", "upper_arm"}, {"ForeArm", "forearm"}, {"Hand", "hand"},
                     {"UpLeg", "thigh"},       {"Leg", "shin"},       {"Foot", "foot"},       {"ToeBase", "toe"},
                     {"HandIndex1", "f_index.01"}, {"HandIndex2", "f_index.02"}};
  const P bvh = {{"Shoulder", "Collar"}, {"Arm", "Shoulder"}, {"ForeArm", "Elbow"}, {"Hand", "Wrist"},
                 {"UpLeg", "Hip"},       {"Leg", "Knee"},      {"Foot", "Ankle"},    {"ToeBase", "Toe"},
                 {"HandIndex1", "Index1"}, {"HandIndex2", "Index2"}};
  const P lower = {{"Shoulder", "Clavicle"}, {"Arm", "UpperArm"}, {"ForeArm", "LowerArm"}, {"Hand", "Hand"},
                   {"UpLeg", "Thigh"},       {"Leg", "Shin"},      {"Foot", "Foot"},        {"ToeBase", "Toes"},
                   {"HandIndex1", "Index1"}, {"HandIndex2", "Index2"}};
  const Convention conventions[] = {
      {"Left/Right prefixes (Mixamo)", [](bool l, const std::string& p) { return (l ? "Left" : "Right") + p; }, {}},
      {"l_/r_ prefixes", [](bool l, const std::string& p) { return (l ? "l_" : "r_") + p; }, ue},
      {"_l/_r suffixes (Unreal)", [](bool l, const std::string& p) { return p + (l ? "_l" : "_r"); }, ue},
      {".L/.R suffixes (Blender)", [](bool l, const std::string& p) { return p + (l ? ".L" : ".R"); }, blender},
      {"L/R prefixes (BVH: Collar, Shoulder, Elbow, Wrist, Hip)",
       [](bool l, const std::string& p) { return (l ? "L" : "R") + p; }, bvh},
      {"Left/Right, Thigh and LowerArm", [](bool l, const std::string& p) { return (l ? "Left" : "Right") + p; }, lower},
  };
  for (const Convention& c : conventions) checkConvention(c);
}

TEST(JointMapConventions, NamesThatLieAboutTheTopologyAreRejectedAndReported) {
  // The left forearm is named as the upper arm and the upper arm as the forearm:
  // no chain upper -> lower -> hand exists, so the guess keeps what topology allows
  // and reports the bone it could not find.
  const Skeleton swapped = humanoid([](const std::string& n) {
    if (n == "LeftArm") return std::string("LeftForeArm");
    if (n == "LeftForeArm") return std::string("LeftArm");
    return n;
  });
  const JointMapResult r = guessJointMap(assetOf(swapped));
  // The names give the chain LeftShoulder, "LeftForeArm", LeftHand, with "LeftArm"
  // between forearm and hand: the guess keeps it and reports the joint between.
  EXPECT_EQ(name(swapped, r.map.joint(Bone::LeftLowerArm)), "LeftForeArm") << notesOf(r);
  EXPECT_EQ(count(r.diagnostics, "leftHand 'LeftHand' is not the child of leftLowerArm 'LeftForeArm': 'LeftArm' lies "
                                 "between (it keeps its rest rotation)"),
            1)
      << notesOf(r);
  EXPECT_EQ(r.diagnostics.items.size(), 1u) << notesOf(r);

  // Names say left where the rest pose says right (legs and arms): reported.
  const Skeleton mirrored = humanoid([](const std::string& n) {
    if (n.rfind("Left", 0) == 0) return "Right" + n.substr(4);
    if (n.rfind("Right", 0) == 0) return "Left" + n.substr(5);
    return n;
  });
  const JointMapResult m = guessJointMap(assetOf(mirrored));
  EXPECT_EQ(name(mirrored, m.map.joint(Bone::LeftUpperLeg)), "LeftUpLeg");
  EXPECT_EQ(count(m.diagnostics, "leftUpperLeg 'LeftUpLeg' lies on the character's right of rightUpperLeg 'RightUpLeg'"), 1)
      << notesOf(m);
  EXPECT_EQ(count(m.diagnostics, "leftUpperArm 'LeftArm' lies on the character's right of rightUpperArm 'RightArm'"), 1)
      << notesOf(m);
}

TEST(JointMapConventions, LegsHangingFromASpineJointMakeItTheHips) {
  // A Biped-like pelvis: Hips -> Pelvis -> Spine, legs under Spine.
  Skeleton s;
  const Transform up{glm::vec3(0, 0.1f, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)};
  const int hips = s.addJoint("Hips", -1, Transform{glm::vec3(0, 1, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
  const int pelvis = s.addJoint("Pelvis", hips, Transform{});
  const int spine = s.addJoint("Spine", pelvis, up);
  const int spine1 = s.addJoint("Spine1", spine, up);
  const int neck = s.addJoint("Neck", spine1, up);
  s.addJoint("Head", neck, up);
  for (const char* side : {"Left", "Right"}) {
    const float x = side[0] == 'L' ? 1.0f : -1.0f;
    const std::string S(side);
    const int arm = s.addJoint(S + "Arm", spine1, Transform{glm::vec3(x * 0.2f, 0.1f, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    const int fore = s.addJoint(S + "ForeArm", arm, Transform{glm::vec3(x * 0.25f, 0, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    s.addJoint(S + "Hand", fore, Transform{glm::vec3(x * 0.25f, 0, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    const int thigh = s.addJoint(S + "UpLeg", spine, Transform{glm::vec3(x * 0.1f, -0.1f, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    const int shin = s.addJoint(S + "Leg", thigh, Transform{glm::vec3(0, -0.45f, 0.02f), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    const int foot = s.addJoint(S + "Foot", shin, Transform{glm::vec3(0, -0.45f, 0), glm::quat(1, 0, 0, 0), glm::vec3(1)});
    s.addJoint(S + "ToeBase", foot, Transform{glm::vec3(0, -0.05f, 0.1f), glm::quat(1, 0, 0, 0), glm::vec3(1)});
  }
  const JointMapResult r = guessJointMap(assetOf(s));
  EXPECT_EQ(name(s, r.map.joint(Bone::Hips)), "Spine") << notesOf(r);
  ASSERT_EQ(r.map.chain(Chain::Spine).size(), 1u) << notesOf(r);
  EXPECT_EQ(name(s, r.map.chain(Chain::Spine)[0]), "Spine1");
  EXPECT_TRUE(hasNote(r.map, "hips: 'Spine', not ")) << notesOf(r);
  EXPECT_TRUE(r.diagnostics.items.empty()) << notesOf(r);
}

// ---- Shipped maps --------------------------------------------------------------

namespace {
struct ShippedMap {
  std::vector<std::string> skeletons;
  std::vector<std::string> allowed;  // warnings the file's comment documents (substrings)
};

std::map<std::string, ShippedMap> shippedMaps() {
  std::map<std::string, ShippedMap> out;
  out["RobotExpressive.json"] = {{sharedAsset("characters/RobotExpressive.glb")}, {}};
  out["Godette_vrm_v4.json"] = {{sharedAsset("characters/Godette_vrm_v4.vrm")}, {}};
  out["CesiumMan.json"] = {{sharedAsset("characters/CesiumMan.glb")}, {}};
  out["three-vrm_test.json"] = {{sharedAsset("motions/gltf/three-vrm_test.vrma")}, {}};
#ifdef MARIONETTE_HAS_ASSIMP
  out["pab.json"] = {{sharedAsset("characters/pab_arnaud.fbx"), sharedAsset("motions/fbx/pab_walk.fbx"),
                      sharedAsset("motions/fbx/pab_jog.fbx"), sharedAsset("motions/fbx/pab_crossarms.fbx")},
                     {}};
  out["cmu_mb.json"] = {{sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), assimpModel("BVH/01_01.bvh"),
                         assimpModel("BVH/01_03.bvh")},
                        {}};
  out["cmu_max.json"] = {{sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh")}, {}};
  out["pirouette.json"] = {{sharedAsset("motions/bvh/pirouette.bvh")}, {}};
  out["Boxing_Toes.json"] = {{assimpModel("BVH/Boxing_Toes.bvh")}, {}};
  out["BCN_Epileptic.json"] = {{assimpModel("X/BCN_Epileptic.X")}, {}};
#endif
  return out;
}

// The entries where two maps differ, by canonical name, for a failure message.
std::string differences(const JointMap& a, const JointMap& b, const Skeleton& s) {
  std::string out;
  for (int i = 0; i < kBoneCount; ++i)
    if (a.bones[static_cast<std::size_t>(i)] != b.bones[static_cast<std::size_t>(i)])
      out += "  " + std::string(boneName(static_cast<Bone>(i))) + ": file '" + name(s, a.bones[static_cast<std::size_t>(i)]) +
             "', guess '" + name(s, b.bones[static_cast<std::size_t>(i)]) + "'\n";
  for (int c = 0; c < kChainCount; ++c) {
    auto list = [&](const JointMap& m) {
      std::string t;
      for (int j : m.chains[static_cast<std::size_t>(c)]) t += (t.empty() ? "" : ", ") + name(s, j);
      return "[" + t + "]";
    };
    if (a.chains[static_cast<std::size_t>(c)] != b.chains[static_cast<std::size_t>(c)])
      out += "  " + std::string(chainName(static_cast<Chain>(c))) + ": file " + list(a) + ", guess " + list(b) + '\n';
  }
  return out;
}
}  // namespace

TEST(JointMapShipped, EveryFileHasItsSkeletons) {
  const auto known = shippedMaps();
  const std::string dir = sourceFile("assets/jointmaps");
  MARIONETTE_REQUIRE_FILE(dir);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++files;
#ifdef MARIONETTE_HAS_ASSIMP  // without Assimp, the maps of FBX, BVH and X skeletons cannot be checked
    EXPECT_TRUE(known.count(e.path().filename().string())) << "no skeleton listed for " << e.path();
#endif
  }
#ifdef MARIONETTE_HAS_ASSIMP
  EXPECT_EQ(files, static_cast<int>(known.size()));
#else
  EXPECT_GE(files, static_cast<int>(known.size()));
#endif
}

TEST(JointMapShipped, EveryFileLoadsCleanlyOnEachSkeletonAndEqualsTheGuess) {
  for (const auto& [file, shipped] : shippedMaps()) {
    const std::string path = sourceFile("assets/jointmaps/" + file);
    MARIONETTE_REQUIRE_FILE(path);
    for (const auto& skeleton : shipped.skeletons) {
      SCOPED_TRACE(file + " on " + skeleton);
      MARIONETTE_REQUIRE_FILE(skeleton);
      const Asset a = importSkeleton(skeleton);
      const JointMapResult r = loadJointMap(path, a);
      std::set<std::string> seen;
      for (const auto& d : r.diagnostics.items) {
        bool allowed = false;
        for (const auto& part : shipped.allowed)
          if (d.message.find(part) != std::string::npos) allowed = true, seen.insert(part);
        EXPECT_TRUE(allowed) << d.format();
      }
      EXPECT_EQ(seen.size(), shipped.allowed.size()) << "a documented absence was not reported\n" << r.diagnostics.format();
      // Hips, head and limbs at least: a file never loads empty.
      for (Bone b : {Bone::Hips, Bone::Head, Bone::LeftUpperLeg, Bone::RightFoot, Bone::LeftUpperArm})
        EXPECT_GE(r.map.joint(b), 0) << boneName(b);
      const JointMapResult g = guessJointMap(a);
      const std::string diff = differences(r.map, g.map, a.skeleton);
      EXPECT_TRUE(diff.empty()) << "the file and the guess differ:\n" << diff << notesOf(g);
    }
  }
}

// findJointMap: the CLI's retarget takes a shipped map this way. Each listed skeleton finds a
// file that maps it as its own file does (the same file, or one that agrees joint for joint).
TEST(JointMapShipped, FindJointMapGivesEachSkeletonItsOwnMapping) {
  const std::string dir = sourceFile("assets/jointmaps");
  MARIONETTE_REQUIRE_FILE(dir);
  for (const auto& [file, shipped] : shippedMaps()) {
    for (const auto& skeleton : shipped.skeletons) {
      SCOPED_TRACE(file + " on " + skeleton);
      MARIONETTE_REQUIRE_FILE(skeleton);
      const Asset a = importSkeleton(skeleton);
      const auto found = findJointMap(a, {"/nonexistent/folder", dir});
      ASSERT_TRUE(found.has_value());
      EXPECT_TRUE(found->result.diagnostics.items.empty()) << found->result.diagnostics.format();
      EXPECT_EQ(found->result.map.bones, loadJointMap(dir + "/" + file, a).map.bones) << found->file;
      EXPECT_EQ(found->result.map.chains, loadJointMap(dir + "/" + file, a).map.chains) << found->file;
    }
  }
  // A skeleton none of them fits.
  EXPECT_FALSE(findJointMap(assetOf(humanoid()), {dir}).has_value());
  EXPECT_FALSE(findJointMap(assetOf(humanoid()), {}).has_value());
}
