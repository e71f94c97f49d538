// Character profiles guessed from synthetic assets: the name conventions, the topology checks
// and the limbs of guessCharacterProfile, and the face, clips and gestures it finds.
#include <gtest/gtest.h>

#include "character_profile_test_support.hpp"

using namespace marionette;
using namespace marionette::profile_test;

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
  const Rig rig(*asset);
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
