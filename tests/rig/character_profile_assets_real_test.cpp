// The shipped profiles (assets/profiles/*.json) against the real characters they
// describe: each loads without a single diagnostic, and guessCharacterProfile finds
// the same hips, spine, neck, head, limbs and toes. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/rig/character_profile.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
struct ShippedProfile {
  std::string asset;    // path of the character file
  std::string profile;  // path of its profile
};

// Every profile we ship, by the stem it shares with its character file.
std::map<std::string, ShippedProfile> shippedProfiles() {
  std::map<std::string, ShippedProfile> out;
  for (const char* c : {"RobotExpressive.glb", "Godette_vrm_v4.vrm", "CesiumMan.glb"})
    out[std::filesystem::path(c).stem().string()] = {sharedAsset(std::string("characters/") + c), ""};
#ifdef MARIONETTE_HAS_ASSIMP  // FBX and X are read through Assimp
  out["pab_arnaud"] = {sharedAsset("characters/pab_arnaud.fbx"), ""};
  out["BCN_Epileptic"] = {assimpModel("X/BCN_Epileptic.X"), ""};
#endif
  for (auto& [stem, p] : out) p.profile = sourceFile("assets/profiles/" + stem + ".json");
  return out;
}

Asset importOrFail(const std::string& path) {
  ImportResult r = importAsset(path);
  EXPECT_TRUE(r.asset.has_value()) << r.diagnostics.format();
  return r.asset ? std::move(*r.asset) : Asset{};
}

std::string notes(const CharacterProfile& p) {
  std::string out;
  for (const auto& n : p.notes) out += "  " + n + '\n';
  return out;
}

class ShippedProfileTest : public ::testing::TestWithParam<std::string> {};
}  // namespace

TEST(CharacterProfileAssets, EveryShippedProfileHasItsCharacter) {
  const auto known = shippedProfiles();
  const std::string dir = sourceFile("assets/profiles");
  MARIONETTE_REQUIRE_FILE(dir);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++files;
#ifndef MARIONETTE_HAS_ASSIMP
    if (e.path().stem() == "pab_arnaud" || e.path().stem() == "BCN_Epileptic") continue;
#endif
    EXPECT_TRUE(known.count(e.path().stem().string()))
        << e.path() << " is not tested here: add its character to shippedProfiles()";
  }
  EXPECT_GE(files, 5);
}

TEST_P(ShippedProfileTest, LoadsWithoutDiagnosticsAndTheGuessAgrees) {
  const ShippedProfile s = shippedProfiles().at(GetParam());
  MARIONETTE_REQUIRE_FILE(s.asset);
  MARIONETTE_REQUIRE_FILE(s.profile);
  const Asset asset = importOrFail(s.asset);
  ASSERT_GT(asset.skeleton.jointCount(), 0u);

  const CharacterProfileResult loaded = loadCharacterProfile(s.profile, asset);
  EXPECT_TRUE(loaded.diagnostics.items.empty()) << loaded.diagnostics.format();
  const CharacterProfile& p = loaded.profile;
  for (const auto& n : p.notes) EXPECT_EQ(n.find("guessed"), std::string::npos) << "the profile leaves out: " << n;
  EXPECT_FALSE(p.hips.empty());
  EXPECT_FALSE(p.neck.empty());
  EXPECT_FALSE(p.head.empty());

  // The guess finds the same body chain on every shipped character. Where it
  // differs from the profile is elsewhere (see GuessedDetailsPerCharacter).
  const CharacterProfile g = guessCharacterProfile(asset);
  EXPECT_EQ(g.hips, p.hips) << notes(g);
  EXPECT_EQ(g.neck, p.neck) << notes(g);
  EXPECT_EQ(g.head, p.head) << notes(g);
  EXPECT_EQ(g.spine, p.spine) << notes(g);
  EXPECT_EQ(g.leftEye, p.leftEye) << notes(g);
  EXPECT_EQ(g.rightEye, p.rightEye) << notes(g);
  EXPECT_EQ(g.jaw, p.jaw) << notes(g);
  // Lip-sync channels: the VRM mouth shapes A I U E O are found in the file as the profile maps them.
  EXPECT_EQ(g.visemes.size(), p.visemes.size()) << notes(g);
  for (const auto& [channel, morphs] : p.visemes) {
    ASSERT_TRUE(g.visemes.count(channel)) << channel << "\n" << notes(g);
    ASSERT_EQ(g.visemes.at(channel).size(), morphs.size()) << channel;
    for (std::size_t i = 0; i < morphs.size(); ++i) EXPECT_EQ(g.visemes.at(channel)[i].morph, morphs[i].morph) << channel;
  }

  // Limbs and toes: the guess (names, the VRM map, or Cesium Man's shape and rest
  // pose) finds what the profile says, and both put the left limbs on the left.
  const std::pair<const char*, Limb CharacterProfile::*> limbs[] = {{"leftLeg", &CharacterProfile::leftLeg},
                                                                    {"rightLeg", &CharacterProfile::rightLeg},
                                                                    {"leftArm", &CharacterProfile::leftArm},
                                                                    {"rightArm", &CharacterProfile::rightArm}};
  for (const auto& [field, member] : limbs) {
    EXPECT_EQ((g.*member).upper, (p.*member).upper) << field << '\n' << notes(g);
    EXPECT_EQ((g.*member).lower, (p.*member).lower) << field << '\n' << notes(g);
    EXPECT_EQ((g.*member).end, (p.*member).end) << field << '\n' << notes(g);
    EXPECT_FALSE((p.*member).upper.empty() || (p.*member).lower.empty()) << field;
  }
  EXPECT_EQ(g.leftToe, p.leftToe) << notes(g);
  EXPECT_EQ(g.rightToe, p.rightToe) << notes(g);
  for (const CharacterProfile* q : {&g, &p}) {
    const std::string n = notes(*q);
    EXPECT_NE(n.find("sides: the left leg and arm lie on the character's left in the rest pose"), std::string::npos) << n;
  }

  // Face, clips and gestures agree too, but for what a profile knows beyond the
  // names (docs/character-profiles.md, "Guess against profile").
  CharacterProfile expected = p;
  if (GetParam() == "Godette_vrm_v4") expected.face.erase("OPEN_MOUTH");  // the "ah" viseme: no guess
  if (GetParam() == "CesiumMan") expected.walk = "";                     // "merged": no name says walk
  ASSERT_EQ(g.face.size(), expected.face.size()) << notes(g);
  for (const auto& [lexeme, morphs] : expected.face) {
    ASSERT_TRUE(g.face.count(lexeme)) << lexeme << '\n' << notes(g);
    ASSERT_EQ(g.face.at(lexeme).size(), morphs.size()) << lexeme;
    for (std::size_t i = 0; i < morphs.size(); ++i) {
      EXPECT_EQ(g.face.at(lexeme)[i].morph, morphs[i].morph) << lexeme;
      EXPECT_NEAR(g.face.at(lexeme)[i].amount, morphs[i].amount, 1e-6) << lexeme;
    }
  }
  EXPECT_EQ(g.idle, expected.idle);
  EXPECT_EQ(g.walk, expected.walk);
  EXPECT_EQ(g.run, expected.run);
  EXPECT_EQ(g.gestures, expected.gestures);
}

INSTANTIATE_TEST_SUITE_P(Characters, ShippedProfileTest, ::testing::ValuesIn([] {
                           std::vector<std::string> stems;
                           for (const auto& [stem, p] : shippedProfiles()) stems.push_back(stem);
                           return stems;
                         }()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// What the guess finds beyond the body chain, and where it knowingly differs from
// the hand-written profile.
TEST(CharacterProfileAssets, GuessedDetailsPerCharacter) {
  {
    MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
    const Asset a = importOrFail(sharedAsset("characters/RobotExpressive.glb"));
    const CharacterProfile g = guessCharacterProfile(a);
    const CharacterProfile p = loadCharacterProfile(sourceFile("assets/profiles/RobotExpressive.json"), a).profile;
    EXPECT_EQ(g.idle, "Idle");  // not "Standing", which is getting up from sitting
    EXPECT_EQ(g.walk, "Walking");
    EXPECT_EQ(g.run, "Running");
    EXPECT_EQ(g.gestures, p.gestures);  // Wave and ThumbsUp; Yes and No are head motions
    // The feet are IK targets under the root, not below the lower legs; no hand joints.
    EXPECT_EQ(p.leftLeg.end, "Foot.L");
    EXPECT_EQ(p.rightLeg.end, "Foot.R");
    EXPECT_NE(notes(g).find("'Foot.L' is not below 'LowerLeg.L'"), std::string::npos) << notes(g);
    EXPECT_NE(notes(p).find("'Foot.R' is not below 'LowerLeg.R'"), std::string::npos) << notes(p);
    EXPECT_EQ(p.leftArm.end, "");
    EXPECT_NE(notes(g).find("it faces +Z, from the knees; its left is +X"), std::string::npos) << notes(g);
    ASSERT_EQ(g.face.size(), 3u) << notes(g);
    for (const char* lexeme : {"ANGER", "SADNESS", "SURPRISE"}) {
      ASSERT_TRUE(g.face.count(lexeme)) << lexeme << '\n' << notes(g);
      EXPECT_EQ(g.face.at(lexeme)[0].morph, p.face.at(lexeme)[0].morph) << lexeme;
    }
  }
  {
    MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
    const Asset a = importOrFail(sharedAsset("characters/Godette_vrm_v4.vrm"));
    const CharacterProfile g = guessCharacterProfile(a);
    const CharacterProfile p = loadCharacterProfile(sourceFile("assets/profiles/Godette_vrm_v4.json"), a).profile;
    EXPECT_NE(notes(g).find("head: 'head_Armature' (VRM humanoid)"), std::string::npos) << notes(g);
    // The VRM expression groups, with their weights, as in the profile; the profile
    // adds OPEN_MOUTH from the "ah" viseme, which the guess never takes for an expression.
    for (const char* lexeme : {"SMILE", "ANGER", "SADNESS", "CLOSE_EYES"}) {
      ASSERT_TRUE(g.face.count(lexeme)) << lexeme << '\n' << notes(g);
      ASSERT_EQ(g.face.at(lexeme).size(), p.face.at(lexeme).size()) << lexeme;
      for (std::size_t i = 0; i < g.face.at(lexeme).size(); ++i) {
        EXPECT_EQ(g.face.at(lexeme)[i].morph, p.face.at(lexeme)[i].morph) << lexeme;
        EXPECT_NEAR(g.face.at(lexeme)[i].amount, p.face.at(lexeme)[i].amount, 1e-6) << lexeme;
      }
    }
    EXPECT_FALSE(g.face.count("OPEN_MOUTH"));
    EXPECT_TRUE(p.face.count("OPEN_MOUTH"));
  }
  {
    MARIONETTE_REQUIRE_FILE(sharedAsset("characters/CesiumMan.glb"));
    const Asset a = importOrFail(sharedAsset("characters/CesiumMan.glb"));
    const CharacterProfile g = guessCharacterProfile(a);
    EXPECT_NE(notes(g).find("(topology"), std::string::npos) << notes(g);  // no names to go by
    // Its walk is the importer's "merged" clip; no clip name says "walk", so only the profile has it.
    EXPECT_EQ(g.walk, "");
    EXPECT_EQ(loadCharacterProfile(sourceFile("assets/profiles/CesiumMan.json"), a).profile.walk, "merged");
    // Unnamed limbs from their shape; he faces +X, so his left is -Z.
    EXPECT_NE(notes(g).find("leftLeg: upper 'node_7', lower 'node_8', end 'node_9' (topology"), std::string::npos) << notes(g);
    EXPECT_NE(notes(g).find("it faces +X, from the toes; its left is -Z"), std::string::npos) << notes(g);
  }
#ifdef MARIONETTE_HAS_ASSIMP
  {
    MARIONETTE_REQUIRE_FILE(sharedAsset("characters/pab_arnaud.fbx"));
    const Asset a = importOrFail(sharedAsset("characters/pab_arnaud.fbx"));
    const CharacterProfile g = guessCharacterProfile(a);
    // The joint map's hips (one humanoid, issue 22): where the legs hang, "Spine", below the
    // root "Hips" and "Pelvis" (assets/jointmaps/pab.json); the name guess said "Pelvis".
    EXPECT_EQ(g.hips, "Spine");
    EXPECT_NE(notes(g).find("hips: 'Spine', not 'Pelvis' (the joint map's)"), std::string::npos) << notes(g);
    EXPECT_EQ(g.leftArm.upper, "LeftArm");  // LeftShoulder is the clavicle
    EXPECT_EQ(g.leftArm.end, "Lefthand");   // one word, lower-case h
    EXPECT_EQ(g.leftToe, "LeftFootThumb1");
    EXPECT_TRUE(g.face.empty());
  }
  {
    MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
    const Asset a = importOrFail(assimpModel("X/BCN_Epileptic.X"));
    const CharacterProfile g = guessCharacterProfile(a);
    // "Head" is a root mesh node: rejected; the head is the joint the eyes hang from.
    EXPECT_EQ(g.head, "B_Neck");
    EXPECT_NE(notes(g).find("'Head' rejected"), std::string::npos) << notes(g);
  }
#endif
}

#ifdef MARIONETTE_HAS_ASSIMP
// The limb names of the real motion skeletons: CMU's two conventions (where
// "LeftShoulder" is the clavicle in one and the upper arm in the other), Daz,
// and Debian's boxing BVH.
TEST(CharacterProfileAssets, LimbsOfRealBvhSkeletons) {
  struct Case {
    std::string file;
    Limb leftLeg, rightArm;
    std::string leftToe;
  };
  const Case cases[] = {
      {sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), {"LeftUpLeg", "LeftLeg", "LeftFoot"},
       {"RightArm", "RightForeArm", "RightHand"}, "LeftToeBase"},
      {sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), {"LeftHip", "LeftKnee", "LeftAnkle"},
       {"RightShoulder", "RightElbow", "RightWrist"}, "LeftToe"},
      {sharedAsset("motions/bvh/pirouette.bvh"), {"lThigh", "lShin", "lFoot"}, {"rShldr", "rForeArm", "rHand"}, ""},
      {assimpModel("BVH/Boxing_Toes.bvh"), {"LeftHip", "LeftKnee", "LeftAnkle"},
       {"RightShoulder", "RightElbow", "RightWrist"}, "LeftToes"},
  };
  for (const Case& c : cases) {
    MARIONETTE_REQUIRE_FILE(c.file);
    const CharacterProfile g = guessCharacterProfile(importOrFail(c.file));
    EXPECT_EQ(g.leftLeg.upper, c.leftLeg.upper) << c.file << '\n' << notes(g);
    EXPECT_EQ(g.leftLeg.lower, c.leftLeg.lower) << c.file;
    EXPECT_EQ(g.leftLeg.end, c.leftLeg.end) << c.file;
    EXPECT_EQ(g.rightArm.upper, c.rightArm.upper) << c.file << '\n' << notes(g);
    EXPECT_EQ(g.rightArm.lower, c.rightArm.lower) << c.file;
    EXPECT_EQ(g.rightArm.end, c.rightArm.end) << c.file;
    EXPECT_EQ(g.leftToe, c.leftToe) << c.file;
    EXPECT_NE(notes(g).find("sides: the left leg and arm lie on the character's left"), std::string::npos)
        << c.file << '\n' << notes(g);
  }
}
#endif
