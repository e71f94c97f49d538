// Character profiles on synthetic assets: the name conventions and the topology
// checks of guessCharacterProfile, and loadCharacterProfile's diagnostics
// (line:column, unknown names cleared, absent fields guessed, never throws).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "marionette/rig/character_profile.hpp"
#include "marionette/rig/rig.hpp"

using namespace marionette;

namespace {
using Joints = std::vector<std::pair<std::string, std::string>>;  // name, parent name ("" for a root)

Asset makeAsset(const Joints& joints, std::vector<std::string> morphs = {}, const std::vector<std::string>& clips = {}) {
  Asset a;
  a.sourcePath = "synthetic.glb";
  for (const auto& [name, parent] : joints) a.skeleton.addJoint(name, a.skeleton.findJoint(parent), Transform{});
  a.morphTargets = std::move(morphs);
  for (const auto& c : clips) {
    Clip clip;
    clip.name = c;
    a.clips.push_back(clip);
  }
  return a;
}

// Hips with two legs, a spine of `spine` joints, a chest with two arms, neck, head.
Joints body(const std::string& hips, const std::vector<std::string>& spine, const std::string& neck,
            const std::string& head, const std::string& left, const std::string& right) {
  Joints j = {{hips, ""}, {left + "UpLeg", hips}, {left + "Leg", left + "UpLeg"}, {right + "UpLeg", hips},
              {right + "Leg", right + "UpLeg"}};
  std::string parent = hips;
  for (const auto& s : spine) j.emplace_back(s, parent), parent = s;
  j.insert(j.end(), {{left + "Arm", parent}, {left + "Hand", left + "Arm"}, {right + "Arm", parent},
                     {right + "Hand", right + "Arm"}, {neck, parent}, {head, neck}});
  return j;
}

bool hasNote(const CharacterProfile& p, const std::string& text) {
  return std::any_of(p.notes.begin(), p.notes.end(), [&](const std::string& n) { return n.find(text) != std::string::npos; });
}
std::string notes(const CharacterProfile& p) {
  std::string out;
  for (const auto& n : p.notes) out += n + '\n';
  return out;
}

// A profile file in a fresh temporary folder, removed with the object.
class TempProfile {
 public:
  explicit TempProfile(const std::string& text, const std::string& name = "profile.json") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("marionette_profile_" + std::string(info->test_suite_name()) + "_" + info->name());
    std::filesystem::create_directories(dir_);
    path_ = (dir_ / name).string();
    write(text);
  }
  ~TempProfile() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  void write(const std::string& text) const { std::ofstream(path_, std::ios::binary) << text; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::filesystem::path dir_;
  std::string path_;
};

const Diagnostic* findDiag(const Diagnostics& d, const std::string& text) {
  for (const auto& i : d.items)
    if (i.message.find(text) != std::string::npos) return &i;
  return nullptr;
}

// A small Mixamo-like character with morphs and clips, used by the loader tests.
Asset robot() {
  return makeAsset(body("Hips", {"Spine", "Chest"}, "Neck", "Head", "Left", "Right"), {"Smile", "Angry", "Blink"},
                   {"Idle", "Walking", "Running", "Wave"});
}

// Joints with their offsets from the parent, for the tests that need a rest pose.
struct PlacedJoint {
  std::string name, parent;
  glm::vec3 offset;
};
Asset makePlacedAsset(const std::vector<PlacedJoint>& joints) {
  Asset a;
  a.sourcePath = "placed.glb";
  for (const auto& j : joints) {
    Transform t;
    t.translation = j.offset;
    a.skeleton.addJoint(j.name, a.skeleton.findJoint(j.parent), t);
  }
  return a;
}

// A standing body facing +Z (toes ahead of the ankles), +Y up, its left at +X,
// with the limb joints named `L...` / `R...` + part: UpLeg, Leg, Foot, ToeBase,
// Shoulder, Arm, ForeArm, Hand. `leftX` is where the names called "L" go: +1 on
// the character's left, -1 (mislabelled) on its right.
std::vector<PlacedJoint> placedBody(const std::string& l, const std::string& r, float leftX = 1.0f) {
  std::vector<PlacedJoint> j = {{"Hips", "", {0, 1.0f, 0}},
                                {"Spine", "Hips", {0, 0.2f, 0}},
                                {"Chest", "Spine", {0, 0.2f, 0}},
                                {"Neck", "Chest", {0, 0.2f, 0}},
                                {"Head", "Neck", {0, 0.1f, 0}}};
  for (const auto& [side, x] : {std::pair{l, leftX}, std::pair{r, -leftX}}) {
    j.insert(j.end(), {{side + "UpLeg", "Hips", {0.1f * x, 0, 0}},
                       {side + "Leg", side + "UpLeg", {0, -0.45f, 0}},
                       {side + "Foot", side + "Leg", {0, -0.45f, 0}},
                       {side + "ToeBase", side + "Foot", {0, -0.08f, 0.12f}},
                       {side + "Shoulder", "Chest", {0.05f * x, 0.15f, 0}},
                       {side + "Arm", side + "Shoulder", {0.12f * x, 0, 0}},
                       {side + "ForeArm", side + "Arm", {0.28f * x, 0, 0}},
                       {side + "Hand", side + "ForeArm", {0.25f * x, 0, 0}}});
  }
  return j;
}

void expectLimb(const Limb& l, const std::string& upper, const std::string& lower, const std::string& end,
                const CharacterProfile& p) {
  EXPECT_EQ(l.upper, upper) << notes(p);
  EXPECT_EQ(l.lower, lower) << notes(p);
  EXPECT_EQ(l.end, end) << notes(p);
}
}  // namespace

// ---- guessing: name conventions ---------------------------------------------------

TEST(CharacterProfileGuess, Mixamo) {
  Joints j = body("mixamorig:Hips", {"mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2"}, "mixamorig:Neck",
                  "mixamorig:Head", "mixamorig:Left", "mixamorig:Right");
  j.insert(j.end(), {{"mixamorig:HeadTop_End", "mixamorig:Head"}, {"mixamorig:LeftEye", "mixamorig:Head"},
                     {"mixamorig:RightEye", "mixamorig:Head"}});
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "mixamorig:Hips");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2"}));
  EXPECT_EQ(p.neck, "mixamorig:Neck");
  EXPECT_EQ(p.head, "mixamorig:Head");
  EXPECT_EQ(p.leftEye, "mixamorig:LeftEye");
  EXPECT_EQ(p.rightEye, "mixamorig:RightEye");
  EXPECT_EQ(p.jaw, "");
  EXPECT_TRUE(hasNote(p, "head: 'mixamorig:Head' (name)")) << notes(p);
  EXPECT_TRUE(hasNote(p, "jaw: none")) << notes(p);
}

TEST(CharacterProfileGuess, VrmJBip) {
  Joints j = body("J_Bip_C_Hips", {"J_Bip_C_Spine", "J_Bip_C_Chest", "J_Bip_C_UpperChest"}, "J_Bip_C_Neck",
                  "J_Bip_C_Head", "J_Bip_L_", "J_Bip_R_");
  j.insert(j.end(), {{"J_Adj_L_FaceEye", "J_Bip_C_Head"}, {"J_Adj_R_FaceEye", "J_Bip_C_Head"}});
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "J_Bip_C_Hips");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"J_Bip_C_Spine", "J_Bip_C_Chest", "J_Bip_C_UpperChest"}));
  EXPECT_EQ(p.neck, "J_Bip_C_Neck");
  EXPECT_EQ(p.head, "J_Bip_C_Head");
  EXPECT_EQ(p.leftEye, "J_Adj_L_FaceEye");
  EXPECT_EQ(p.rightEye, "J_Adj_R_FaceEye");
}

TEST(CharacterProfileGuess, BlenderDotAndUnderscoreSides) {
  for (const auto& [l, r] : {std::pair<std::string, std::string>{".L", ".R"}, {"_L", "_R"}, {"_l", "_r"}}) {
    Joints j = {{"pelvis", ""}, {"thigh" + l, "pelvis"}, {"shin" + l, "thigh" + l}, {"thigh" + r, "pelvis"},
                {"shin" + r, "thigh" + r}, {"spine", "pelvis"}, {"chest", "spine"}, {"shoulder" + l, "chest"},
                {"shoulder" + r, "chest"}, {"neck", "chest"}, {"head", "neck"}, {"eye" + r, "head"},
                {"eye" + l, "head"}, {"jaw", "head"}};
    const CharacterProfile p = guessCharacterProfile(makeAsset(j));
    EXPECT_EQ(p.hips, "pelvis") << l;
    EXPECT_EQ(p.spine, (std::vector<std::string>{"spine", "chest"})) << l;
    EXPECT_EQ(p.neck, "neck") << l;
    EXPECT_EQ(p.head, "head") << l;
    EXPECT_EQ(p.leftEye, "eye" + l) << l;  // not fooled by the right eye coming first
    EXPECT_EQ(p.rightEye, "eye" + r) << l;
    EXPECT_EQ(p.jaw, "jaw") << l;
  }
}

TEST(CharacterProfileGuess, CmuBvhNeckAndNeck1) {
  const Joints j = {{"Hips", ""},         {"LHipJoint", "Hips"},    {"LeftUpLeg", "LHipJoint"}, {"RHipJoint", "Hips"},
                    {"RightUpLeg", "RHipJoint"}, {"LowerBack", "Hips"}, {"Spine", "LowerBack"},  {"Spine1", "Spine"},
                    {"LeftShoulder", "Spine1"}, {"RightShoulder", "Spine1"}, {"Neck", "Spine1"}, {"Neck1", "Neck"},
                    {"Head", "Neck1"}};
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "Hips");  // not the one-sided LHipJoint
  EXPECT_EQ(p.spine, (std::vector<std::string>{"LowerBack", "Spine", "Spine1"}));
  EXPECT_EQ(p.neck, "Neck");  // where the neck starts; Neck1 lies between it and the head
  EXPECT_EQ(p.head, "Head");
}

TEST(CharacterProfileGuess, PabHipsAbovePelvisAndShouldersOnTheNeck) {
  const Joints j = {{"Hips", ""},          {"Pelvis", "Hips"},      {"Spine", "Pelvis"},     {"Spine1", "Spine"},
                    {"Spine2", "Spine1"},  {"Spine3", "Spine2"},    {"Neck", "Spine3"},      {"Head", "Neck"},
                    {"LeftShoulder", "Neck"}, {"RightShoulder", "Neck"}, {"LeftUpLeg", "Pelvis"}, {"RightUpLeg", "Pelvis"}};
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "Pelvis");  // the deepest hips-like name above the neck: where the legs branch
  EXPECT_EQ(p.spine, (std::vector<std::string>{"Spine", "Spine1", "Spine2", "Spine3"}));
  EXPECT_EQ(p.neck, "Neck");
  EXPECT_EQ(p.head, "Head");
}

TEST(CharacterProfileGuess, DazStyleLowerCaseWithSidePrefixes) {
  const Joints j = {{"hip", ""},          {"lThigh", "hip"},     {"rThigh", "hip"},  {"abdomen", "hip"},
                    {"chest", "abdomen"}, {"lCollar", "chest"},  {"rCollar", "chest"}, {"neck", "chest"},
                    {"head", "neck"},     {"leftEye", "head"},   {"rightEye", "head"}};
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "hip");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"abdomen", "chest"}));
  EXPECT_EQ(p.head, "head");
  EXPECT_EQ(p.leftEye, "leftEye");
  EXPECT_EQ(p.rightEye, "rightEye");
}

TEST(CharacterProfileGuess, VrmHumanoidMapWinsOverNames) {
  Asset a = makeAsset(body("Root", {"Bone.001", "Bone.002"}, "Bone.003", "Bone.004", "L", "R"));
  a.hasHumanoid = true;
  a.humanoid.bones = {{"hips", "Root"}, {"neck", "Bone.003"}, {"head", "Bone.004"}};
  const CharacterProfile p = guessCharacterProfile(a);
  EXPECT_EQ(p.hips, "Root");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"Bone.001", "Bone.002"}));
  EXPECT_EQ(p.neck, "Bone.003");
  EXPECT_EQ(p.head, "Bone.004");
  EXPECT_TRUE(hasNote(p, "(VRM humanoid)")) << notes(p);
}

TEST(CharacterProfileGuess, UnnamedJointsByTopology) {
  // Cesium Man's shape: root with two 4-joint legs and a torso; chest with two arms and a neck.
  const Joints j = {{"joint_0", ""},          {"joint_1", "joint_0"},   {"joint_2", "joint_1"},   {"joint_3", "joint_2"},
                    {"joint_4", "joint_3"},   {"joint_5", "joint_2"},   {"joint_6", "joint_2"},   {"joint_7", "joint_5"},
                    {"joint_8", "joint_6"},   {"joint_9", "joint_0"},   {"joint_10", "joint_0"},  {"joint_11", "joint_9"},
                    {"joint_12", "joint_10"}, {"joint_13", "joint_11"}, {"joint_14", "joint_12"}, {"joint_15", "joint_7"},
                    {"joint_16", "joint_8"}};
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.hips, "joint_0");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"joint_1", "joint_2"}));
  EXPECT_EQ(p.neck, "joint_3");
  EXPECT_EQ(p.head, "joint_4");
  EXPECT_TRUE(hasNote(p, "hips: 'joint_0' (topology")) << notes(p);
}

TEST(CharacterProfileGuess, NothingToFindGivesEmptyFieldsAndNotes) {
  const CharacterProfile p = guessCharacterProfile(makeAsset({{"a", ""}, {"b", "a"}}));
  EXPECT_EQ(p.hips, "");
  EXPECT_EQ(p.neck, "");
  EXPECT_EQ(p.head, "");
  EXPECT_TRUE(p.spine.empty());
  EXPECT_TRUE(p.face.empty());
  for (const char* field : {"hips:", "spine:", "neck:", "head:", "leftEye:", "rightEye:", "jaw:", "face:", "idle:",
                            "walk:", "run:", "gestures:"})
    EXPECT_TRUE(hasNote(p, field)) << field << '\n' << notes(p);
  (void)guessCharacterProfile(Asset{});  // empty asset: no crash
}

namespace {
// Every joint a profile names (body fields only).
std::vector<std::string> namedJoints(const CharacterProfile& p) {
  std::vector<std::string> all = {p.hips, p.neck, p.head, p.leftEye, p.rightEye, p.jaw, p.leftToe, p.rightToe};
  all.insert(all.end(), p.spine.begin(), p.spine.end());
  for (const Limb* l : {&p.leftLeg, &p.rightLeg, &p.leftArm, &p.rightArm}) all.insert(all.end(), {l->upper, l->lower, l->end});
  all.erase(std::remove(all.begin(), all.end(), std::string()), all.end());
  return all;
}
}  // namespace

// A malformed skeleton is guessed as the tree it is: a joint whose parent is not before it
// is a root, joints without a parent entry are left out; nothing is invented.
TEST(CharacterProfileGuess, MalformedSkeletonIsGuessedAsTheTreeItIs) {
  Asset a;
  a.skeleton.names = {"Head", "Neck", "Hips"};
  a.skeleton.parents = {2, 0, 7};  // parents after children and out of range
  CharacterProfile p = guessCharacterProfile(a);
  EXPECT_FALSE(hasNote(p, "guess failed")) << notes(p);
  for (const char* field : {"hips:", "spine:", "neck:", "head:", "face:", "idle:", "walk:", "run:", "gestures:"})
    EXPECT_TRUE(hasNote(p, field)) << field << '\n' << notes(p);
  for (const std::string& n : namedJoints(p))
    EXPECT_NE(std::find(a.skeleton.names.begin(), a.skeleton.names.end(), n), a.skeleton.names.end()) << n;
  // "Neck" hangs from "Head" (the only parent that comes first) and "Hips" is a root alone:
  // "Head" is above the neck and not below the hips, so it is not the head.
  EXPECT_EQ(p.hips, "Hips") << notes(p);
  EXPECT_EQ(p.head, "") << notes(p);
  EXPECT_EQ(p.neck, "") << notes(p);
  EXPECT_TRUE(hasNote(p, "'Head' rejected")) << notes(p);

  a.skeleton.parents = {-1};  // fewer parents than names: only "Head" is a joint here
  p = guessCharacterProfile(a);
  EXPECT_FALSE(hasNote(p, "guess failed")) << notes(p);
  EXPECT_EQ(namedJoints(p), std::vector<std::string>{"Head"}) << notes(p);

  // One bad parent in a whole body: the rest is found as in a well-formed one.
  Asset body1 = makeAsset(body("Hips", {"Spine", "Chest"}, "Neck", "Head", "Left", "Right"));
  body1.skeleton.parents[static_cast<std::size_t>(body1.skeleton.findJoint("RightLeg"))] = 99;  // out of range
  p = guessCharacterProfile(body1);
  EXPECT_EQ(p.neck, "Neck") << notes(p);
  EXPECT_EQ(p.head, "Head") << notes(p);
  EXPECT_EQ(p.spine, (std::vector<std::string>{"Spine", "Chest"})) << notes(p);
  EXPECT_EQ(p.hips, "Hips") << notes(p);
  EXPECT_EQ(p.leftLeg.upper, "LeftUpLeg") << notes(p);
  EXPECT_EQ(p.leftLeg.lower, "LeftLeg") << notes(p);
  EXPECT_NE(p.rightLeg.lower, "RightLeg") << notes(p);  // a root now, not below the right hip
}

// ---- guessing: topology checks ----------------------------------------------------

TEST(CharacterProfileGuess, HeadNotBelowTheNeckIsRejected) {
  // "Head" hangs from the hips (a prop or a mesh node); the neck's only child is the real head.
  Joints j = body("Hips", {"Spine", "Chest"}, "Neck", "Skull", "Left", "Right");
  j.emplace_back("Head", "Hips");
  CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.neck, "Neck");
  EXPECT_EQ(p.head, "Skull");
  EXPECT_TRUE(hasNote(p, "'Head' rejected")) << notes(p);

  // Without a joint below the neck there is no head at all, rather than the wrong one.
  j = body("Hips", {"Spine", "Chest"}, "Neck", "Skull", "Left", "Right");
  j.erase(std::remove_if(j.begin(), j.end(), [](const auto& e) { return e.first == "Skull"; }), j.end());
  j.emplace_back("Head", "Hips");
  p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.neck, "Neck");
  EXPECT_EQ(p.head, "");
  EXPECT_TRUE(hasNote(p, "'Head' rejected")) << notes(p);
}

TEST(CharacterProfileGuess, HeadFoundFromTheEyesWhenItsNameMisleads) {
  // BCN_Epileptic's shape: "Head" is a root mesh node, the head joint is named B_Neck.
  Joints j = body("B_Root", {"B_Spine1", "B_Spine2"}, "B_Root_Neck_T", "B_Neck", "B_Left", "B_Right");
  j.insert(j.end(), {{"B_Eye_Left", "B_Neck"}, {"B_Eye_Right", "B_Neck"}, {"B_Jaw", "B_Neck"}, {"Head", ""}});
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.head, "B_Neck");
  EXPECT_EQ(p.neck, "B_Root_Neck_T");
  EXPECT_EQ(p.hips, "B_Root");  // where the legs branch off, below the arms
  EXPECT_EQ(p.spine, (std::vector<std::string>{"B_Spine1", "B_Spine2"}));
  EXPECT_EQ(p.leftEye, "B_Eye_Left");
  EXPECT_EQ(p.jaw, "B_Jaw");
}

TEST(CharacterProfileGuess, NeckFromTopologyWhenUnnamed) {
  Joints j = body("Hips", {"Spine", "Chest"}, "joint_9", "Head", "Left", "Right");
  const CharacterProfile p = guessCharacterProfile(makeAsset(j));
  EXPECT_EQ(p.neck, "joint_9");
  EXPECT_TRUE(hasNote(p, "neck: 'joint_9' (topology")) << notes(p);
  EXPECT_EQ(p.spine, (std::vector<std::string>{"Spine", "Chest"}));
}

// ---- guessing: limbs ------------------------------------------------------------------

TEST(CharacterProfileLimbs, MixamoAndCmuMotionBuilderNames) {
  // CMU's MotionBuilder skeleton: LHipJoint (a pelvis bone named like a hip) above LeftUpLeg.
  std::vector<PlacedJoint> j = placedBody("mixamorig:Left", "mixamorig:Right");
  j.push_back({"LHipJoint", "Hips", {0.05f, 0, 0}});
  const CharacterProfile p = guessCharacterProfile(makePlacedAsset(j));
  expectLimb(p.leftLeg, "mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot", p);
  expectLimb(p.rightLeg, "mixamorig:RightUpLeg", "mixamorig:RightLeg", "mixamorig:RightFoot", p);
  // LeftShoulder is the clavicle when an "Arm" lies below it.
  expectLimb(p.leftArm, "mixamorig:LeftArm", "mixamorig:LeftForeArm", "mixamorig:LeftHand", p);
  expectLimb(p.rightArm, "mixamorig:RightArm", "mixamorig:RightForeArm", "mixamorig:RightHand", p);
  EXPECT_EQ(p.leftToe, "mixamorig:LeftToeBase");
  EXPECT_EQ(p.rightToe, "mixamorig:RightToeBase");
  EXPECT_TRUE(hasNote(p, "leftLeg: upper 'mixamorig:LeftUpLeg', lower 'mixamorig:LeftLeg', end 'mixamorig:LeftFoot' (name)"))
      << notes(p);
  EXPECT_TRUE(hasNote(p, "sides: the left leg and arm lie on the character's left in the rest pose (it faces +Z, from "
                         "the toes; its left is +X)"))
      << notes(p);
}

TEST(CharacterProfileLimbs, OtherConventions) {
  struct Case {
    Joints joints;
    Limb leg, arm;
    std::string toe;
  };
  const std::vector<Case> cases = {
      // CMU 3dsMax-friendly: Hip is the thigh (the knee's parent, not LHipJoint), Shoulder the upper arm.
      {{{"Hips", ""}, {"LHipJoint", "Hips"}, {"LeftHip", "LHipJoint"}, {"LeftKnee", "LeftHip"},
        {"LeftAnkle", "LeftKnee"}, {"LeftToe", "LeftAnkle"}, {"Chest", "Hips"}, {"LeftCollar", "Chest"},
        {"LeftShoulder", "LeftCollar"}, {"LeftElbow", "LeftShoulder"}, {"LeftWrist", "LeftElbow"}, {"lhand", "LeftWrist"}},
       {"LeftHip", "LeftKnee", "LeftAnkle"}, {"LeftShoulder", "LeftElbow", "LeftWrist"}, "LeftToe"},
      // Blender ".L".
      {{{"Hips", ""}, {"UpperLeg.L", "Hips"}, {"LowerLeg.L", "UpperLeg.L"}, {"Foot.L", "LowerLeg.L"},
        {"Toe.L", "Foot.L"}, {"Chest", "Hips"}, {"Shoulder.L", "Chest"}, {"UpperArm.L", "Shoulder.L"},
        {"LowerArm.L", "UpperArm.L"}, {"Hand.L", "LowerArm.L"}},
       {"UpperLeg.L", "LowerLeg.L", "Foot.L"}, {"UpperArm.L", "LowerArm.L", "Hand.L"}, "Toe.L"},
      // VRoid J_Bip.
      {{{"J_Bip_C_Hips", ""}, {"J_Bip_L_UpperLeg", "J_Bip_C_Hips"}, {"J_Bip_L_LowerLeg", "J_Bip_L_UpperLeg"},
        {"J_Bip_L_Foot", "J_Bip_L_LowerLeg"}, {"J_Bip_L_ToeBase", "J_Bip_L_Foot"}, {"J_Bip_C_Chest", "J_Bip_C_Hips"},
        {"J_Bip_L_Shoulder", "J_Bip_C_Chest"}, {"J_Bip_L_UpperArm", "J_Bip_L_Shoulder"},
        {"J_Bip_L_LowerArm", "J_Bip_L_UpperArm"}, {"J_Bip_L_Hand", "J_Bip_L_LowerArm"}},
       {"J_Bip_L_UpperLeg", "J_Bip_L_LowerLeg", "J_Bip_L_Foot"}, {"J_Bip_L_UpperArm", "J_Bip_L_LowerArm", "J_Bip_L_Hand"},
       "J_Bip_L_ToeBase"},
      // Pab: "Lefthand" in one word, toes "LeftFootThumb1".
      {{{"Pelvis", ""}, {"LeftUpLeg", "Pelvis"}, {"LeftLeg", "LeftUpLeg"}, {"LeftFoot", "LeftLeg"},
        {"LeftFootThumb1", "LeftFoot"}, {"Neck", "Pelvis"}, {"LeftShoulder", "Neck"}, {"LeftArm", "LeftShoulder"},
        {"LeftForeArm", "LeftArm"}, {"Lefthand", "LeftForeArm"}, {"LeftHandThumb1", "Lefthand"}},
       {"LeftUpLeg", "LeftLeg", "LeftFoot"}, {"LeftArm", "LeftForeArm", "Lefthand"}, "LeftFootThumb1"},
      // Unreal thigh/calf/ball, Daz-style prefixes lThigh/lShin/lShldr.
      {{{"pelvis", ""}, {"thigh_l", "pelvis"}, {"calf_l", "thigh_l"}, {"foot_l", "calf_l"}, {"ball_l", "foot_l"},
        {"spine", "pelvis"}, {"clavicle_l", "spine"}, {"upperarm_l", "clavicle_l"}, {"lowerarm_l", "upperarm_l"},
        {"hand_l", "lowerarm_l"}},
       {"thigh_l", "calf_l", "foot_l"}, {"upperarm_l", "lowerarm_l", "hand_l"}, "ball_l"},
      {{{"hip", ""}, {"lButtock", "hip"}, {"lThigh", "lButtock"}, {"lShin", "lThigh"}, {"lFoot", "lShin"},
        {"chest", "hip"}, {"lCollar", "chest"}, {"lShldr", "lCollar"}, {"lForeArm", "lShldr"}, {"lHand", "lForeArm"}},
       {"lThigh", "lShin", "lFoot"}, {"lShldr", "lForeArm", "lHand"}, ""},
  };
  for (const Case& c : cases) {
    const CharacterProfile p = guessCharacterProfile(makeAsset(c.joints));
    SCOPED_TRACE(c.leg.upper);
    expectLimb(p.leftLeg, c.leg.upper, c.leg.lower, c.leg.end, p);
    expectLimb(p.leftArm, c.arm.upper, c.arm.lower, c.arm.end, p);
    EXPECT_EQ(p.leftToe, c.toe) << notes(p);
    expectLimb(p.rightLeg, "", "", "", p);  // only left joints in these skeletons
    EXPECT_TRUE(hasNote(p, "rightLeg: none")) << notes(p);
  }
}

TEST(CharacterProfileLimbs, TheChainMustHangTogether) {
  // "LeftLeg" is not below "LeftUpLeg" (a prop, or a second rig): the leg is thigh and foot only.
  Joints j = {{"Hips", ""},          {"LeftUpLeg", "Hips"}, {"LeftFoot", "LeftUpLeg"}, {"LeftLeg", "Hips"},
              {"Chest", "Hips"},     {"LeftArm", "Chest"},  {"LeftForeArm", "LeftArm"}, {"LeftHand", "Chest"}};
  CharacterProfile p = guessCharacterProfile(makeAsset(j));
  expectLimb(p.leftLeg, "LeftUpLeg", "", "LeftFoot", p);
  // An arm's hand must hang from its forearm: a hand elsewhere is no end of this arm.
  expectLimb(p.leftArm, "LeftArm", "LeftForeArm", "", p);

  // One joint alone is no limb (Blender's "shoulder.L" is a clavicle).
  p = guessCharacterProfile(makeAsset({{"pelvis", ""}, {"spine", "pelvis"}, {"shoulder.L", "spine"}}));
  expectLimb(p.leftArm, "", "", "", p);
  EXPECT_TRUE(hasNote(p, "leftArm: none")) << notes(p);
  EXPECT_TRUE(hasNote(p, "leftToe: none")) << notes(p);
}

TEST(CharacterProfileLimbs, FootElsewhereIsTakenWhenItsNameIsUnambiguous) {
  // RobotExpressive: the feet are Blender IK targets under the root, not below the lower legs.
  const Joints j = {{"Bone", ""},           {"Foot.L", "Bone"},           {"Body", "Bone"},
                    {"Hips", "Body"},       {"UpperLeg.L", "Body"},       {"LowerLeg.L", "UpperLeg.L"},
                    {"Foot.R", "Bone"},     {"UpperLeg.R", "Body"},       {"LowerLeg.R", "UpperLeg.R"},
                    {"Torso", "Hips"},      {"Shoulder.L", "Torso"},      {"UpperArm.L", "Shoulder.L"},
                    {"LowerArm.L", "UpperArm.L"}, {"Hand.L", "Torso"}};
  CharacterProfile p = guessCharacterProfile(makeAsset(j));
  expectLimb(p.leftLeg, "UpperLeg.L", "LowerLeg.L", "Foot.L", p);
  expectLimb(p.rightLeg, "UpperLeg.R", "LowerLeg.R", "Foot.R", p);
  EXPECT_TRUE(hasNote(p, "'Foot.L' is not below 'LowerLeg.L'")) << notes(p);
  expectLimb(p.leftArm, "UpperArm.L", "LowerArm.L", "", p);  // never for an arm

  // Two left feet elsewhere: no telling which one is the ankle.
  Joints two = j;
  two.emplace_back("foot_L", "Bone");
  p = guessCharacterProfile(makeAsset(two));
  expectLimb(p.leftLeg, "UpperLeg.L", "LowerLeg.L", "", p);
  // A foot above the leg is no end of it either.
  p = guessCharacterProfile(makeAsset({{"Foot.L", ""}, {"UpperLeg.L", "Foot.L"}, {"LowerLeg.L", "UpperLeg.L"}}));
  expectLimb(p.leftLeg, "UpperLeg.L", "LowerLeg.L", "", p);
}

TEST(CharacterProfileLimbs, VrmHumanoidMapWinsOverNames) {
  Asset a = makeAsset({{"Root", ""},       {"Hips", "Root"},   {"LeftUpLeg", "Hips"}, {"A", "Hips"},
                       {"B", "A"},         {"C", "B"},         {"D", "C"},            {"LeftLeg", "LeftUpLeg"},
                       {"LeftFoot", "LeftLeg"}});
  a.hasHumanoid = true;
  a.humanoid.bones = {{"leftUpperLeg", "A"}, {"leftLowerLeg", "B"}, {"leftFoot", "C"}, {"leftToes", "D"},
                      {"rightUpperLeg", "C"}, {"rightLowerLeg", "B"}, {"rightFoot", "A"}};  // right: not a chain
  const CharacterProfile p = guessCharacterProfile(a);
  expectLimb(p.leftLeg, "A", "B", "C", p);
  EXPECT_EQ(p.leftToe, "D");
  EXPECT_TRUE(hasNote(p, "leftLeg: upper 'A', lower 'B', end 'C' (VRM humanoid)")) << notes(p);
  expectLimb(p.rightLeg, "", "", "", p);  // an inconsistent map is not used, and no name says right
}

TEST(CharacterProfileLimbs, UnnamedSkeletonBySideFromTheRestPose) {
  // Cesium Man's shape, facing +X: its left is -Z. Leg and arm chains have no names.
  auto leg = [](const std::string& p, const std::string& a, const std::string& b, const std::string& c,
                const std::string& d, float z) {
    return std::vector<PlacedJoint>{{a, p, {0, -0.07f, z}}, {b, a, {0, -0.26f, 0}}, {c, b, {0, -0.27f, 0}},
                                    {d, c, {0.03f, -0.06f, 0}}};
  };
  std::vector<PlacedJoint> j = {{"n0", "", {0, 0.68f, 0}}, {"n1", "n0", {0, 0.15f, 0}}, {"n2", "n1", {0, 0.25f, 0}},
                                {"n3", "n2", {0, 0.07f, 0}}, {"n4", "n3", {0, 0.05f, 0}}};
  for (const auto& part : {leg("n0", "n5", "n6", "n7", "n8", -0.07f), leg("n0", "n9", "n10", "n11", "n12", 0.07f)})
    j.insert(j.end(), part.begin(), part.end());
  j.insert(j.end(), {{"n13", "n2", {0, 0, 0.1f}}, {"n14", "n13", {0, -0.1f, 0.2f}}, {"n15", "n14", {0.05f, -0.1f, 0.15f}},
                     {"n16", "n2", {0, 0, -0.1f}}, {"n17", "n16", {0, -0.1f, -0.2f}}, {"n18", "n17", {0.05f, -0.1f, -0.15f}}});
  CharacterProfile p = guessCharacterProfile(makePlacedAsset(j));
  ASSERT_EQ(p.hips, "n0") << notes(p);
  expectLimb(p.leftLeg, "n5", "n6", "n7", p);  // at -Z: the character's left
  expectLimb(p.rightLeg, "n9", "n10", "n11", p);
  EXPECT_EQ(p.leftToe, "n8");
  EXPECT_EQ(p.rightToe, "n12");
  expectLimb(p.leftArm, "n16", "n17", "n18", p);
  expectLimb(p.rightArm, "n13", "n14", "n15", p);
  EXPECT_TRUE(hasNote(p, "(topology: a mirror pair of chains below the hips; side from the rest pose)")) << notes(p);
  EXPECT_TRUE(hasNote(p, "it faces +X, from the toes; its left is -Z")) << notes(p);

  // The same shape with every joint at one place: no telling left from right, so no limbs.
  for (auto& x : j) x.offset = glm::vec3(0.0f);
  p = guessCharacterProfile(makePlacedAsset(j));
  expectLimb(p.leftLeg, "", "", "", p);
  expectLimb(p.leftArm, "", "", "", p);
  EXPECT_TRUE(hasNote(p, "does not tell left from right")) << notes(p);
}

TEST(CharacterProfileLimbs, NamesThatContradictTheRestPoseAreKeptWithANote) {
  const CharacterProfile p = guessCharacterProfile(makePlacedAsset(placedBody("Left", "Right", -1.0f)));
  expectLimb(p.leftLeg, "LeftUpLeg", "LeftLeg", "LeftFoot", p);  // the names rule
  EXPECT_TRUE(hasNote(p, "sides: the left leg and arm lie on the character's right in the rest pose; kept as named"))
      << notes(p);
}

TEST(CharacterProfileLimbs, RigResolvesTheLimbsToIndices) {
  const auto asset = std::make_shared<Asset>(makePlacedAsset(placedBody("Left", "Right")));
  const Rig rig(asset);
  const Skeleton& s = asset->skeleton;
  const RigJoints& j = rig.joints();
  EXPECT_EQ(j.leftLeg.upper, s.findJoint("LeftUpLeg"));
  EXPECT_EQ(j.leftLeg.lower, s.findJoint("LeftLeg"));
  EXPECT_EQ(j.leftLeg.end, s.findJoint("LeftFoot"));
  EXPECT_EQ(j.rightArm.upper, s.findJoint("RightArm"));
  EXPECT_EQ(j.rightArm.lower, s.findJoint("RightForeArm"));
  EXPECT_EQ(j.rightArm.end, s.findJoint("RightHand"));
  EXPECT_EQ(j.leftToe, s.findJoint("LeftToeBase"));
  EXPECT_EQ(j.rightToe, s.findJoint("RightToeBase"));
  EXPECT_GE(j.rightLeg.end, 0);
  EXPECT_GE(j.leftArm.end, 0);
}

// ---- guessing: face, clips, gestures ------------------------------------------------

TEST(CharacterProfileGuess, FaceLexemesFromMorphNames) {
  const Asset a = makeAsset({{"Root", ""}}, {"Angry", "Surprised", "Sad", "Fcl_MTH_Joy", "Fcl_ALL_Joy", "Fcl_EYE_Close",
                                             "browDownLeft", "browDownRight", "mouthPucker", "jawOpen", "ah", "Fear"});
  const CharacterProfile p = guessCharacterProfile(a);
  auto morphs = [&](const std::string& lexeme) {
    std::vector<std::string> out;
    if (auto it = p.face.find(lexeme); it != p.face.end())
      for (const auto& m : it->second) {
        out.push_back(m.morph);
        EXPECT_EQ(m.amount, 1.0f);
      }
    return out;
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(morphs("ANGER"), V{"Angry"});
  EXPECT_EQ(morphs("SURPRISE"), V{"Surprised"});
  EXPECT_EQ(morphs("SADNESS"), V{"Sad"});
  EXPECT_EQ(morphs("FEAR"), V{"Fear"});
  EXPECT_EQ(morphs("SMILE"), V{"Fcl_ALL_Joy"});  // the whole-face morph before the mouth-only one
  EXPECT_EQ(morphs("CLOSE_EYES"), V{"Fcl_EYE_Close"});
  EXPECT_EQ(morphs("LOWER_BROWS"), (V{"browDownLeft", "browDownRight"}));
  EXPECT_EQ(morphs("LOWER_LEFT_BROW"), V{"browDownLeft"});
  EXPECT_EQ(morphs("LOWER_RIGHT_BROW"), V{"browDownRight"});
  EXPECT_EQ(morphs("PUCKER_LIPS"), V{"mouthPucker"});
  EXPECT_EQ(morphs("OPEN_MOUTH"), V{"jawOpen"});
  EXPECT_FALSE(p.face.count("DISGUST"));
  for (const auto& [lexeme, list] : p.face)
    for (const auto& m : list) EXPECT_NE(m.morph, "ah") << lexeme << ": a viseme is no expression";
  EXPECT_TRUE(hasNote(p, "face ANGER: 'Angry' (name)")) << notes(p);
}

TEST(CharacterProfileGuess, BlinkPairAndVrmExpressionGroups) {
  Asset a = makeAsset({{"Root", ""}}, {"blink_left", "blink_right", "oh", "look_up"});
  CharacterProfile p = guessCharacterProfile(a);
  ASSERT_EQ(p.face["CLOSE_EYES"].size(), 2u);
  EXPECT_EQ(p.face["CLOSE_EYES"][0].morph, "blink_left");
  EXPECT_EQ(p.face["CLOSE_EYES"][1].morph, "blink_right");
  EXPECT_FALSE(p.face.count("SMILE"));

  a.hasHumanoid = true;
  a.humanoid.expressions["joy"] = {{2, 0.5f}, {3, 0.25f}};
  a.humanoid.expressions["angry"] = {{9, 1.0f}};  // a bad index is skipped, not a crash
  p = guessCharacterProfile(a);
  ASSERT_EQ(p.face["SMILE"].size(), 2u);
  EXPECT_EQ(p.face["SMILE"][0].morph, "oh");
  EXPECT_FLOAT_EQ(p.face["SMILE"][0].amount, 0.5f);
  EXPECT_FALSE(p.face.count("ANGER"));
  EXPECT_TRUE(hasNote(p, "(VRM expression 'joy')")) << notes(p);
}

TEST(CharacterProfileGuess, LocomotionClipsAndGestures) {
  Asset a = makeAsset({{"Root", ""}}, {}, {"Standing", "WalkJump", "Idle", "Walking", "Running", "Wave", "ThumbsUp",
                                           "Yes", "No", "Idle_to_Walk"});
  CharacterProfile p = guessCharacterProfile(a);
  EXPECT_EQ(p.idle, "Idle");  // before "Standing"
  EXPECT_EQ(p.walk, "Walking");  // not "WalkJump"
  EXPECT_EQ(p.run, "Running");
  EXPECT_EQ(p.gestures, (std::map<std::string, std::string>{{"WAVE", "Wave"}, {"THUMBS_UP", "ThumbsUp"}}));

  a = makeAsset({{"Root", ""}}, {}, {"Armature|walk_loop", "Armature|jog", "mixamo.com", "Slow Run", "pointing"});
  p = guessCharacterProfile(a);
  EXPECT_EQ(p.idle, "");
  EXPECT_EQ(p.walk, "Armature|walk_loop");
  EXPECT_EQ(p.run, "Slow Run");  // "run" ranks before "jog"
  EXPECT_EQ(p.gestures, (std::map<std::string, std::string>{{"POINT", "pointing"}}));
  EXPECT_TRUE(hasNote(p, "idle: none")) << notes(p);
}

// ---- loading --------------------------------------------------------------------------

TEST(CharacterProfileLoad, FullProfileLoadsWithoutDiagnostics) {
  TempProfile f(R"({
  "comment": "a robot",
  "joints": {"hips": "Hips", "spine": ["Spine", "Chest"], "neck": "Neck", "head": "Head",
             "leftEye": "", "rightEye": "", "jaw": ""},
  "face": {"SMILE": [{"morph": "Smile", "amount": 0.8}], "AU12": [{"morph": "Smile"}], "ANGER": "Angry"},
  "clips": {"idle": "Idle", "walk": "Walking", "run": ""},
  "gestures": {"BEAT": "Wave"}
})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  EXPECT_EQ(r.profile.hips, "Hips");
  EXPECT_EQ(r.profile.spine, (std::vector<std::string>{"Spine", "Chest"}));
  EXPECT_EQ(r.profile.head, "Head");
  ASSERT_EQ(r.profile.face.at("SMILE").size(), 1u);
  EXPECT_FLOAT_EQ(r.profile.face.at("SMILE")[0].amount, 0.8f);
  EXPECT_FLOAT_EQ(r.profile.face.at("AU12")[0].amount, 1.0f);  // amount defaults to 1
  EXPECT_EQ(r.profile.face.at("ANGER")[0].morph, "Angry");      // string shorthand
  EXPECT_EQ(r.profile.face.size(), 3u);                         // "face" given: nothing guessed into it
  EXPECT_EQ(r.profile.run, "");                                 // "" is "none", not "guess"
  EXPECT_EQ(r.profile.gestures, (std::map<std::string, std::string>{{"BEAT", "Wave"}}));
  EXPECT_TRUE(hasNote(r.profile, "hips: 'Hips' (profile)")) << notes(r.profile);
}

TEST(CharacterProfileLoad, MalformedJsonIsAnErrorWithLineAndColumn) {
  TempProfile f("{\n  \"joints\": {\n    \"head\": \"Head\",,\n  }\n}");
  const auto r = loadCharacterProfile(f.path(), robot());
  ASSERT_FALSE(r.diagnostics.ok());
  ASSERT_EQ(r.diagnostics.items.size(), 1u);
  const Diagnostic& d = r.diagnostics.items[0];
  EXPECT_EQ(d.file, f.path());
  EXPECT_EQ(d.line, 3);
  EXPECT_EQ(d.column, 20);
  EXPECT_NE(d.format().find(f.path() + ":3:20: error: syntax error"), std::string::npos) << d.format();
  EXPECT_EQ(r.profile.head, "Head");  // still usable: the guess
  EXPECT_TRUE(hasNote(r.profile, "not used")) << notes(r.profile);

  f.write("{\"face\": {\"SMILE\": [{\"morph\": \"Smile\",\n \"amount\": 1e999}]}}");
  const auto overflow = loadCharacterProfile(f.path(), robot());
  ASSERT_FALSE(overflow.diagnostics.ok());
  EXPECT_EQ(overflow.diagnostics.items[0].line, 2) << overflow.diagnostics.format();
  EXPECT_EQ(overflow.diagnostics.items[0].column, 12) << overflow.diagnostics.format();
  EXPECT_NE(overflow.diagnostics.items[0].message.find("1e999"), std::string::npos) << overflow.diagnostics.format();

  f.write("[1, 2]");
  const auto top = loadCharacterProfile(f.path(), robot());
  ASSERT_FALSE(top.diagnostics.ok());
  EXPECT_NE(top.diagnostics.format().find("expected an object"), std::string::npos);
}

TEST(CharacterProfileLoad, MissingFileIsAnErrorNamingIt) {
  const std::string path = "/nonexistent/dir/Nobody.json";
  const auto r = loadCharacterProfile(path, robot());
  ASSERT_FALSE(r.diagnostics.ok());
  EXPECT_EQ(r.diagnostics.items[0].file, path);
  EXPECT_NE(r.diagnostics.items[0].message.find(path), std::string::npos);
  EXPECT_EQ(r.profile.neck, "Neck");  // guessed
}

TEST(CharacterProfileLoad, UnknownKeysWarnWithPlace) {
  TempProfile f("{\n  \"joints\": {\"hips\": \"Hips\", \"pelvis\": \"Hips\"},\n  \"colour\": \"red\"\n}");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok());
  const Diagnostic* top = findDiag(r.diagnostics, "unknown key 'colour'");
  ASSERT_NE(top, nullptr) << r.diagnostics.format();
  EXPECT_EQ(top->severity, Severity::Warning);
  EXPECT_EQ(top->file, f.path());
  EXPECT_EQ(top->line, 3);
  EXPECT_EQ(top->column, 3);
  const Diagnostic* inner = findDiag(r.diagnostics, "joints/pelvis: unknown key 'pelvis'");
  ASSERT_NE(inner, nullptr) << r.diagnostics.format();
  EXPECT_EQ(inner->line, 2);
  EXPECT_EQ(inner->column, 30);
}

TEST(CharacterProfileLoad, NamesTheAssetLacksWarnAndAreCleared) {
  TempProfile f(R"({"joints": {"head": "Hed", "spine": ["Spine", "Torso"]},
"face": {"SMILE": [{"morph": "Grin"}, {"morph": "Smile"}]},
"clips": {"walk": "Walk"},
"gestures": {"WAVE": "Waving"}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();
  const Diagnostic* head = findDiag(r.diagnostics, "joints/head: no joint named 'Hed'");
  ASSERT_NE(head, nullptr) << r.diagnostics.format();
  EXPECT_EQ(head->severity, Severity::Warning);
  EXPECT_EQ(head->line, 1);
  EXPECT_EQ(head->column, 21);
  EXPECT_EQ(r.profile.head, "");  // cleared, not guessed
  ASSERT_NE(findDiag(r.diagnostics, "joints/spine/1: no joint named 'Torso'"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.spine, std::vector<std::string>{"Spine"});
  const Diagnostic* morph = findDiag(r.diagnostics, "face/SMILE/0/morph: no morph target named 'Grin'");
  ASSERT_NE(morph, nullptr) << r.diagnostics.format();
  EXPECT_EQ(morph->line, 2);
  ASSERT_EQ(r.profile.face.at("SMILE").size(), 1u);
  EXPECT_EQ(r.profile.face.at("SMILE")[0].morph, "Smile");
  ASSERT_NE(findDiag(r.diagnostics, "clips/walk: no clip named 'Walk'"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.walk, "");
  ASSERT_NE(findDiag(r.diagnostics, "gestures/WAVE: no clip named 'Waving'"), nullptr) << r.diagnostics.format();
  EXPECT_TRUE(r.profile.gestures.empty());
}

TEST(CharacterProfileLoad, AmountsOutsideTheRangeAreClamped) {
  TempProfile f(R"({"face": {"SMILE": [{"morph": "Smile", "amount": 1.5}], "ANGER": [{"morph": "Angry", "amount": -2}],
  "CLOSE_EYES": [{"morph": "Blink", "amount": "full"}], "SADNES": [{"morph": "Angry", "amount": 7}]}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();
  EXPECT_FLOAT_EQ(r.profile.face.at("SMILE")[0].amount, 1.0f);
  EXPECT_FLOAT_EQ(r.profile.face.at("ANGER")[0].amount, 0.0f);
  EXPECT_FLOAT_EQ(r.profile.face.at("CLOSE_EYES")[0].amount, 1.0f);
  const Diagnostic* big = findDiag(r.diagnostics, "face/SMILE/0/amount: amount 1.5 is outside [0, 1]");
  ASSERT_NE(big, nullptr) << r.diagnostics.format();
  EXPECT_EQ(big->line, 1);
  EXPECT_EQ(big->column, 50);
  EXPECT_NE(findDiag(r.diagnostics, "face/ANGER/0/amount"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "face/CLOSE_EYES/0/amount: expected a number"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "'SADNES' is not a BML face lexeme"), nullptr) << r.diagnostics.format();
}

TEST(CharacterProfileLoad, AbsentFieldsAreGuessedWithANote) {
  TempProfile f(R"({"joints": {"head": "Head"}, "clips": {"run": ""}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  EXPECT_EQ(r.profile.hips, "Hips");
  EXPECT_EQ(r.profile.neck, "Neck");
  EXPECT_EQ(r.profile.spine, (std::vector<std::string>{"Spine", "Chest"}));
  EXPECT_EQ(r.profile.idle, "Idle");
  EXPECT_EQ(r.profile.walk, "Walking");
  EXPECT_EQ(r.profile.run, "");  // given as none
  EXPECT_EQ(r.profile.face.at("SMILE")[0].morph, "Smile");
  EXPECT_EQ(r.profile.face.at("CLOSE_EYES")[0].morph, "Blink");
  EXPECT_EQ(r.profile.gestures.at("WAVE"), "Wave");
  EXPECT_TRUE(hasNote(r.profile, "hips: 'Hips' (name); not in the profile, guessed")) << notes(r.profile);
  EXPECT_TRUE(hasNote(r.profile, "head: 'Head' (profile)")) << notes(r.profile);
  EXPECT_TRUE(hasNote(r.profile, "face ANGER: 'Angry' (name); not in the profile, guessed")) << notes(r.profile);
}

TEST(CharacterProfileLoad, TypeErrorsTopologyAndDuplicatesWarn) {
  TempProfile f(R"({"joints": {"hips": 3, "neck": "Head", "head": "Neck", "spine": "Spine"},
  "face": [], "gestures": {"WAVE": "Wave", "WAVE": "Idle"}, "clips": 7})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "joints/hips: expected a joint name"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.hips, "Hips");  // a value of the wrong type counts as absent: guessed
  EXPECT_NE(findDiag(r.diagnostics, "joints/head: 'Neck' is not below the neck 'Head'"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "joints/spine: expected an array"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "face: expected an object"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.face.at("SMILE")[0].morph, "Smile");
  EXPECT_NE(findDiag(r.diagnostics, "clips: expected an object"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.walk, "Walking");
  const Diagnostic* dup = findDiag(r.diagnostics, "gestures/WAVE: duplicate key");
  ASSERT_NE(dup, nullptr) << r.diagnostics.format();
  EXPECT_EQ(dup->line, 2);
  EXPECT_EQ(r.profile.gestures.at("WAVE"), "Idle");  // nlohmann keeps the last
}

TEST(CharacterProfileLoad, LimbsFromTheFile) {
  const Asset asset = makePlacedAsset(placedBody("Left", "Right"));
  TempProfile f(R"({"limbs": {
  "leftLeg": {"upper": "LeftUpLeg", "lower": "LeftLeg", "end": "LeftFoot"},
  "rightLeg": {"upper": "RightUpLeg", "lower": "RightLeg"},
  "leftArm": {"upper": "LeftShoulder", "lower": "LeftForeArm", "end": ""},
  "leftToe": ""
}})");
  const auto r = loadCharacterProfile(f.path(), asset);
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  const CharacterProfile& p = r.profile;
  expectLimb(p.leftLeg, "LeftUpLeg", "LeftLeg", "LeftFoot", p);
  expectLimb(p.rightLeg, "RightUpLeg", "RightLeg", "RightFoot", p);  // its end left out: guessed
  expectLimb(p.leftArm, "LeftShoulder", "LeftForeArm", "", p);       // the file rules, "" is none
  expectLimb(p.rightArm, "RightArm", "RightForeArm", "RightHand", p);  // absent: guessed
  EXPECT_EQ(p.leftToe, "");
  EXPECT_EQ(p.rightToe, "RightToeBase");
  EXPECT_TRUE(hasNote(p, "leftLeg: upper 'LeftUpLeg', lower 'LeftLeg', end 'LeftFoot' (profile)")) << notes(p);
  EXPECT_TRUE(hasNote(p, "rightLeg: upper 'RightUpLeg', lower 'RightLeg', end 'RightFoot' (profile; end not in the "
                         "profile, guessed)"))
      << notes(p);
  EXPECT_TRUE(hasNote(p, "rightArm: upper 'RightArm', lower 'RightForeArm', end 'RightHand' (name); not in the profile, "
                         "guessed"))
      << notes(p);
  EXPECT_TRUE(hasNote(p, "sides: the left leg and arm lie on the character's left")) << notes(p);
}

TEST(CharacterProfileLoad, LimbJointsTheAssetLacksWarnNamingTheField) {
  const Asset asset = makePlacedAsset(placedBody("Left", "Right"));
  TempProfile f(R"({"limbs": {
  "leftLeg": {"upper": "LeftUpLeg", "lower": "LeftLeg", "end": "LeftAnkle"},
  "rightArm": {"upper": "RightArm", "lower": "RightForeArm", "end": "RightHand", "wrist": "RightHand"},
  "leftArm": "LeftArm",
  "rightToe": "RightToes",
  "tail": {}
}})");
  const auto r = loadCharacterProfile(f.path(), asset);
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();  // warnings only
  const Diagnostic* end = findDiag(r.diagnostics, "limbs/leftLeg/end: no joint named 'LeftAnkle' in 'placed.glb'; cleared");
  ASSERT_NE(end, nullptr) << r.diagnostics.format();
  EXPECT_EQ(end->severity, Severity::Warning);
  EXPECT_EQ(end->file, f.path());
  EXPECT_EQ(end->line, 2);
  EXPECT_EQ(end->column, 64);
  EXPECT_EQ(r.profile.leftLeg.end, "");  // cleared, not guessed
  ASSERT_NE(findDiag(r.diagnostics, "limbs/rightToe: no joint named 'RightToes'"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.rightToe, "");
  ASSERT_NE(findDiag(r.diagnostics, "limbs/rightArm/wrist: unknown key 'wrist'"), nullptr) << r.diagnostics.format();
  ASSERT_NE(findDiag(r.diagnostics, "limbs/tail: unknown key 'tail'"), nullptr) << r.diagnostics.format();
  ASSERT_NE(findDiag(r.diagnostics, "limbs/leftArm: expected an object"), nullptr) << r.diagnostics.format();
  expectLimb(r.profile.leftArm, "LeftArm", "LeftForeArm", "LeftHand", r.profile);  // wrong type: guessed

  f.write(R"({"limbs": 3})");
  const auto notAnObject = loadCharacterProfile(f.path(), asset);
  ASSERT_NE(findDiag(notAnObject.diagnostics, "limbs: expected an object"), nullptr) << notAnObject.diagnostics.format();
  expectLimb(notAnObject.profile.leftLeg, "LeftUpLeg", "LeftLeg", "LeftFoot", notAnObject.profile);
}

TEST(CharacterProfileLoad, LimbChainsThatDoNotHangTogetherWarn) {
  std::vector<PlacedJoint> j = placedBody("Left", "Right");
  j.push_back({"Target.L", "Hips", {0.1f, -0.9f, 0}});  // an IK target beside the leg
  const Asset asset = makePlacedAsset(j);
  TempProfile f(R"({"limbs": {
  "leftLeg": {"upper": "LeftUpLeg", "lower": "LeftLeg", "end": "Target.L"},
  "rightLeg": {"upper": "RightUpLeg", "lower": "LeftLeg", "end": "RightFoot"},
  "leftArm": {"upper": "LeftArm", "lower": "LeftForeArm", "end": "RightHand"},
  "leftToe": "RightToeBase"
}})");
  const auto r = loadCharacterProfile(f.path(), asset);
  EXPECT_NE(findDiag(r.diagnostics, "limbs/rightLeg/lower: 'LeftLeg' is not below the upper joint 'RightUpLeg'"), nullptr)
      << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "limbs/leftArm/end: 'RightHand' is not below the lower joint 'LeftForeArm'"), nullptr)
      << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "limbs/leftToe: 'RightToeBase' is not below the foot 'Target.L'"), nullptr)
      << r.diagnostics.format();
  // A leg's end elsewhere is allowed (RobotExpressive): a note, no warning.
  EXPECT_EQ(findDiag(r.diagnostics, "limbs/leftLeg"), nullptr) << r.diagnostics.format();
  EXPECT_TRUE(hasNote(r.profile, "'Target.L' is not below 'LeftLeg': the end point is its rest offset")) << notes(r.profile);
  EXPECT_EQ(r.diagnostics.items.size(), 3u) << r.diagnostics.format();
  EXPECT_EQ(r.profile.leftArm.end, "RightHand");  // kept: the file has the last word
}

TEST(CharacterProfileLoad, SurvivesRandomMutations) {
  const std::string valid = R"({"comment": "x\u00e9\"/",
  "joints": {"hips": "Hips", "spine": ["Spine", "Chest"], "neck": "Neck", "head": "Head", "leftEye": "", "jaw": ""},
  "face": {"SMILE": [{"morph": "Smile", "amount": 0.5}], "AU45": "Blink", "ANGER": [{"morph": "Angry"}]},
  "limbs": {"leftLeg": {"upper": "LeftUpLeg", "lower": "LeftLeg", "end": ""}, "rightArm": {"upper": "RightArm"},
            "leftToe": ""},
  "clips": {"idle": "Idle", "walk": "Walking", "run": "Running"},
  "gestures": {"WAVE": "Wave", "BEAT": "Idle"}})";
  const Asset asset = robot();
  TempProfile f(valid);
  std::mt19937 rng(20240611);
  const std::string alphabet = "{}[]:,\"\\0123456789.eE+-tfnul aZ\n\x80\xff";
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(rng() % std::max<std::size_t>(n, 1)); };
  int errors = 0;
  for (int round = 0; round < 400; ++round) {
    std::string text = valid;
    for (int edits = 1 + static_cast<int>(pick(4)); edits-- > 0;) {
      const std::size_t at = pick(text.size());
      switch (pick(5)) {
        case 0: text[at] = alphabet[pick(alphabet.size())]; break;
        case 1: text.erase(at, 1 + pick(8)); break;
        case 2: text.insert(at, 1, alphabet[pick(alphabet.size())]); break;
        case 3: text.insert(at, text.substr(pick(text.size()), pick(40))); break;  // duplicate a span
        default: text.resize(at); break;
      }
    }
    f.write(text);
    const auto r = loadCharacterProfile(f.path(), asset);
    errors += !r.diagnostics.ok();
    for (const auto& d : r.diagnostics.items) {
      EXPECT_EQ(d.file, f.path()) << text;
      EXPECT_GE(d.line, 0);
      EXPECT_GE(d.column, 0);
    }
    // Whatever survives names things the asset has, with amounts in range.
    for (const std::string* j : {&r.profile.hips, &r.profile.neck, &r.profile.head, &r.profile.leftEye,
                                 &r.profile.rightEye, &r.profile.jaw, &r.profile.leftLeg.upper,
                                 &r.profile.leftLeg.lower, &r.profile.leftLeg.end, &r.profile.rightArm.upper,
                                 &r.profile.rightArm.end, &r.profile.leftToe})
      EXPECT_TRUE(j->empty() || asset.skeleton.findJoint(*j) >= 0) << *j << '\n' << text;
    for (const auto& [lexeme, morphs] : r.profile.face)
      for (const auto& m : morphs) {
        EXPECT_NE(std::find(asset.morphTargets.begin(), asset.morphTargets.end(), m.morph), asset.morphTargets.end());
        EXPECT_TRUE(m.amount >= 0.0f && m.amount <= 1.0f) << m.amount;
      }
  }
  EXPECT_GT(errors, 50);  // the mutations did break the syntax often
  EXPECT_LT(errors, 400);
}

// ---- the joint map names the body's joints (one humanoid, issue 22) ----------------------

namespace {
// A map that disagrees with the name guess (hips "Hips"), so the test sees where the joints came from.
constexpr const char* kRobotMap = R"({"bones": {"hips": "Spine", "head": "Head"},
 "chains": {"spine": ["Chest"], "neck": ["Neck"]}})";
}  // namespace

TEST(CharacterProfileJointMap, TheNamedMapGivesTheBodyJoints) {
  TempProfile map(kRobotMap, "robot_map.json");
  TempProfile f(R"({"jointMap": "robot_map.json", "clips": {"idle": "Idle"}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  EXPECT_EQ(r.profile.hips, "Spine");
  EXPECT_EQ(r.profile.spine, std::vector<std::string>{"Chest"});
  EXPECT_EQ(r.profile.neck, "Neck");
  EXPECT_EQ(r.profile.head, "Head");
  EXPECT_EQ(r.profile.idle, "Idle");
  EXPECT_TRUE(hasNote(r.profile, "joints: from the joint map")) << notes(r.profile);
  // The map's own warnings (required bones it leaves out) are notes of the profile, not diagnostics.
  EXPECT_TRUE(hasNote(r.profile, "joint map: ")) << notes(r.profile);
  EXPECT_TRUE(hasNote(r.profile, "required bones not mapped")) << notes(r.profile);
  // The rig resolves the same joints.
  Rig rig(std::make_shared<const Asset>(robot()));
  rig.setProfile(r.profile);
  EXPECT_EQ(rig.joints().hips, rig.skeleton().findJoint("Spine"));
  ASSERT_EQ(rig.joints().spine.size(), 1u);
  EXPECT_EQ(rig.joints().spine[0], rig.skeleton().findJoint("Chest"));
}

TEST(CharacterProfileJointMap, JointsBesideAMapAreIgnoredWithAWarningAtTheirKey) {
  TempProfile map(kRobotMap, "robot_map.json");
  TempProfile f(R"({"jointMap": "robot_map.json",
  "joints": {"hips": "Hips"},
  "limbs": {}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_EQ(r.profile.hips, "Spine");  // the map's
  ASSERT_NE(findDiag(r.diagnostics, "ignored: the profile names a joint map"), nullptr) << r.diagnostics.format();
  ASSERT_EQ(r.diagnostics.items.size(), 2u) << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items[0].line, 2) << r.diagnostics.format();  // at "joints"
  EXPECT_EQ(r.diagnostics.items[1].line, 3) << r.diagnostics.format();  // at "limbs"
}

TEST(CharacterProfileJointMap, AMapThatCannotBeReadIsAWarningNamingItAndTheFileJointsAreUsed) {
  TempProfile f(R"({"jointMap": "no_such_map.json",
  "joints": {"hips": "Hips", "spine": ["Spine", "Chest"], "neck": "Neck", "head": "Head"}})");
  const auto r = loadCharacterProfile(f.path(), robot());
  // The profile still loads (a scene or the C API would otherwise refuse it): warnings only.
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();
  ASSERT_EQ(r.diagnostics.items.size(), 1u) << r.diagnostics.format();
  EXPECT_EQ(r.diagnostics.items[0].file, f.path());  // the profile's warning, at "jointMap", naming the map
  EXPECT_EQ(r.diagnostics.items[0].line, 1);
  EXPECT_EQ(r.diagnostics.items[0].severity, Severity::Warning);
  EXPECT_NE(r.diagnostics.items[0].message.find("cannot be used"), std::string::npos);
  EXPECT_NE(r.diagnostics.items[0].message.find("no_such_map.json"), std::string::npos) << r.diagnostics.format();
  EXPECT_EQ(r.profile.hips, "Hips");  // the file's own joints
  EXPECT_EQ(r.profile.spine, (std::vector<std::string>{"Spine", "Chest"}));
}

TEST(CharacterProfileJointMap, AJointMapValueThatIsNoPathIsWarnedAndTheJointsGuessed) {
  for (const char* value : {"3", "\"\"", "null", "[\"a.json\"]"}) {
    TempProfile f(std::string(R"({"jointMap": )") + value + "}");
    const auto r = loadCharacterProfile(f.path(), robot());
    EXPECT_NE(findDiag(r.diagnostics, "expected the path of a joint-map file"), nullptr) << value << '\n' << r.diagnostics.format();
    EXPECT_TRUE(r.diagnostics.ok()) << value;
    EXPECT_EQ(r.profile.hips, guessCharacterProfile(robot()).hips) << value;
  }
}

TEST(CharacterProfileJointMap, SetProfileJointsNamesEveryBodyFieldFromTheMap) {
  const Asset a = robot();
  retarget::JointMap m;
  m.bones[static_cast<std::size_t>(retarget::Bone::Hips)] = a.skeleton.findJoint("Hips");
  m.bones[static_cast<std::size_t>(retarget::Bone::Head)] = a.skeleton.findJoint("Head");
  m.chains[static_cast<std::size_t>(retarget::Chain::Spine)] = {a.skeleton.findJoint("Spine"), a.skeleton.findJoint("Chest")};
  m.chains[static_cast<std::size_t>(retarget::Chain::Neck)] = {a.skeleton.findJoint("Neck")};
  m.bones[static_cast<std::size_t>(retarget::Bone::LeftHand)] = 999;  // outside the skeleton: no name
  CharacterProfile p;
  p.hips = "stale";
  p.leftArm.end = "stale";
  p.idle = "Idle";
  setProfileJoints(p, m, a.skeleton);
  EXPECT_EQ(p.hips, "Hips");
  EXPECT_EQ(p.spine, (std::vector<std::string>{"Spine", "Chest"}));
  EXPECT_EQ(p.neck, "Neck");
  EXPECT_EQ(p.head, "Head");
  EXPECT_EQ(p.leftArm.end, "");  // cleared, not left stale
  EXPECT_EQ(p.leftEye, "");
  EXPECT_EQ(p.idle, "Idle");     // not a body joint: untouched
  // A joint whose name an earlier joint shares cannot be named: left out, with a note.
  Asset twin = robot();
  const int second = static_cast<int>(twin.skeleton.jointCount());
  twin.skeleton.addJoint("Head", twin.skeleton.findJoint("Neck"), Transform{}, glm::mat4(1.0f), false);
  retarget::JointMap m2;
  m2.bones[static_cast<std::size_t>(retarget::Bone::Head)] = second;
  CharacterProfile q;
  setProfileJoints(q, m2, twin.skeleton);
  EXPECT_EQ(q.head, "");
  EXPECT_TRUE(hasNote(q, "cannot be named in a profile")) << notes(q);
}
