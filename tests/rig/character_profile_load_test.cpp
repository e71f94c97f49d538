// Character profiles loaded from files against synthetic assets: loadCharacterProfile's
// diagnostics (line:column, unknown names cleared, absent fields guessed, never throws) and
// the joint map that names the body's joints.
#include <gtest/gtest.h>

#include "character_profile_test_support.hpp"

using namespace marionette;
using namespace marionette::profile_test;

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

TEST(CharacterProfileLoad, LifeHeightIsMetresInItsRangeElseAWarningNamingTheFileAndKey) {
  TempProfile f(R"({"lifeHeight": 1.2})");
  auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  ASSERT_TRUE(r.profile.lifeHeight.has_value());
  EXPECT_FLOAT_EQ(*r.profile.lifeHeight, 1.2f);
  EXPECT_TRUE(hasNote(r.profile, "lifeHeight: 1.2 m (profile)")) << notes(r.profile);
  for (const char* edge : {"0.05", "20"}) {  // the range's ends are in it
    f.write(std::string(R"({"lifeHeight": )") + edge + "}");
    r = loadCharacterProfile(f.path(), robot());
    EXPECT_TRUE(r.diagnostics.items.empty()) << edge << ": " << r.diagnostics.format();
    EXPECT_TRUE(r.profile.lifeHeight.has_value()) << edge;
  }
  f.write(R"({"clips": {}})");  // not given: none (never guessed)
  EXPECT_FALSE(loadCharacterProfile(f.path(), robot()).profile.lifeHeight.has_value());
  const struct {
    const char* value;
    const char* says;
  } bad[] = {{"0.04", "height 0.04 m is outside [0.05, 20] m; ignored"},
             {"20.5", "height 20.5 m is outside [0.05, 20] m; ignored"},
             {"-1.7", "height -1.7 m is outside [0.05, 20] m"},
             {"0", "height 0 m is outside [0.05, 20] m"},
             {"\"1.7\"", "expected the character's life-size height in metres"},
             {"true", "expected the character's life-size height in metres"},
             {"null", "expected the character's life-size height in metres"}};
  for (const auto& b : bad) {
    SCOPED_TRACE(b.value);
    f.write(std::string("{\"comment\": \"x\",\n \"lifeHeight\": ") + b.value + "}");
    r = loadCharacterProfile(f.path(), robot());
    EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();  // a warning: the profile still loads
    EXPECT_FALSE(r.profile.lifeHeight.has_value());
    const Diagnostic* d = findDiag(r.diagnostics, std::string("lifeHeight: ") + b.says);
    ASSERT_NE(d, nullptr) << r.diagnostics.format();
    EXPECT_EQ(d->severity, Severity::Warning);
    EXPECT_EQ(d->file, f.path());
    EXPECT_EQ(d->line, 2);
    EXPECT_EQ(d->column, 16);
  }
  // A number JSON cannot hold (1e999) is no finite height: an error, as any number out of range.
  f.write(R"({"lifeHeight": 1e999})");
  r = loadCharacterProfile(f.path(), robot());
  EXPECT_FALSE(r.diagnostics.ok());
  EXPECT_FALSE(r.profile.lifeHeight.has_value());
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
  Rig rig(robot());
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

// "voices": other engines' voice names to the synthesizer's, keys lower-cased (speech::withVoiceNames).
TEST(CharacterProfileLoad, VoicesMapNamesAndBadEntriesAreWarnings) {
  TempProfile f(R"({"voices": {"OpenMARY": "en-us", "default": "en-gb"}})");
  auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  ASSERT_EQ(r.profile.voices.size(), 2u);
  EXPECT_EQ(r.profile.voices.at("openmary"), "en-us");
  EXPECT_EQ(r.profile.voices.at("default"), "en-gb");
  EXPECT_TRUE(hasNote(r.profile, "voices: 2 (profile)")) << notes(r.profile);
  f.write("{\"comment\": \"x\",\n \"voices\": {\"marytts\": 3, \"openmary\": \"en-us\", \"\": \"de\"}}");
  r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();  // warnings: the profile still loads
  EXPECT_EQ(r.profile.voices.size(), 1u);
  const Diagnostic* d = findDiag(r.diagnostics, "voices/marytts: expected a non-empty voice name");
  ASSERT_NE(d, nullptr) << r.diagnostics.format();
  EXPECT_EQ(d->severity, Severity::Warning);
  EXPECT_EQ(d->line, 2);
  f.write(R"({"voices": ["en-us"]})");
  r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.profile.voices.empty());
  EXPECT_NE(findDiag(r.diagnostics, "voices: expected an object"), nullptr) << r.diagnostics.format();
}

// "gestureVocabulary": other realizers' gesture names to procedural lexemes (rig/gesture_vocabulary.hpp).
TEST(CharacterProfileLoad, GestureVocabularyIsReadAndBadEntriesAreWarnings) {
  TempProfile f(R"({"gestureVocabulary": {"greet*": "wave", "*self*": "ME"}})");
  auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  ASSERT_EQ(r.profile.gestureVocabulary.size(), 2u);
  const GestureVocabularyEntry* m = matchGestureVocabulary("greet_1", r.profile.gestureVocabulary);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->lexeme, "WAVE");
  EXPECT_TRUE(hasNote(r.profile, "gestureVocabulary: 2 (profile)")) << notes(r.profile);
  f.write("{\"comment\": \"x\",\n \"gestureVocabulary\": {\"x*\": 1}}");
  r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok());
  EXPECT_TRUE(r.profile.gestureVocabulary.empty());
  EXPECT_NE(findDiag(r.diagnostics, "gestureVocabulary/x*: expected a non-empty pattern"), nullptr) << r.diagnostics.format();
}

// "facs": units the face shows by no AU, ARKit or VRM morph (rig/facs.hpp). They fill what
// the guess left, or take the place of eyelid and brow joints; not of morphs it found.
TEST(CharacterProfileLoad, FacsMapFillsTheUnitsTheFaceHasNoMorphFor) {
  Asset asset = robot();
  asset.morphTargets.push_back("mouthSmileLeft");
  asset.morphTargets.push_back("mouthSmileRight");
  TempProfile f(R"({"facs": {"AU10": "Angry", "AU15_L": [{"morph": "Angry", "amount": 0.5}], "AU12": "Smile",
                   "AU999": "Smile", "AU14": "NoSuchMorph"}})");
  auto r = loadCharacterProfile(f.path(), asset);
  ASSERT_EQ(r.profile.facs.count("AU10"), 1u);
  EXPECT_EQ(r.profile.facs.at("AU10").source, "the profile's facs map");
  EXPECT_EQ(r.profile.facs.at("AU10").morphs.at(0).morph, "Angry");
  EXPECT_EQ(r.profile.facs.at("AU9").source, "expression ANGER");  // the guess's Angry, before the profile
  EXPECT_FLOAT_EQ(r.profile.facs.at("AU15_L").morphs.at(0).amount, 0.5f);
  // AU12 is shown by the ARKit smiles: the profile's entry is said and not used.
  EXPECT_EQ(r.profile.facs.at("AU12").source, "ARKit blendshapes");
  EXPECT_TRUE(hasNote(r.profile, "facs AU12: the profile's entry is not used, the face has ARKit blendshapes")) << notes(r.profile);
  EXPECT_NE(findDiag(r.diagnostics, "'AU999' is not a FACS unit"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "NoSuchMorph"), nullptr) << r.diagnostics.format();
  EXPECT_EQ(r.profile.facs.count("AU14"), 0u);
  f.write(R"({"facs": ["AU9"]})");
  r = loadCharacterProfile(f.path(), asset);
  EXPECT_NE(findDiag(r.diagnostics, "facs: expected an object"), nullptr) << r.diagnostics.format();
}

// "idleLife": blinking and breathing from the character's creation (behavior/idle_life.hpp).
TEST(CharacterProfileLoad, IdleLifeIsReadAndBadEntriesAreWarnings) {
  TempProfile f(R"({"idleLife": {"blink": true, "breathing": {"rate": 14, "amplitude": 2}}})");
  auto r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  EXPECT_TRUE(r.profile.idleLife.blink);
  EXPECT_TRUE(r.profile.idleLife.breathing);
  EXPECT_FALSE(r.profile.idleLife.blinkMeanInterval);
  EXPECT_EQ(r.profile.idleLife.breathsPerMinute, 14.0f);
  EXPECT_EQ(r.profile.idleLife.breathingAmplitude, 2.0f);
  EXPECT_TRUE(hasNote(r.profile, "idleLife: blink on, breathing on (profile)")) << notes(r.profile);
  f.write("{\"idleLife\": {\"blink\": {\"meanInterval\": -2, \"rate\": 3},\n \"breathing\": \"yes\", \"sneeze\": true}}");
  r = loadCharacterProfile(f.path(), robot());
  EXPECT_TRUE(r.diagnostics.ok()) << r.diagnostics.format();  // warnings: the profile still loads
  EXPECT_TRUE(r.profile.idleLife.blink);
  EXPECT_FALSE(r.profile.idleLife.blinkMeanInterval);  // the default
  EXPECT_FALSE(r.profile.idleLife.breathing);
  EXPECT_NE(findDiag(r.diagnostics, "idleLife/blink/meanInterval: expected a number >= 0"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "rate"), nullptr) << r.diagnostics.format();
  EXPECT_NE(findDiag(r.diagnostics, "sneeze"), nullptr) << r.diagnostics.format();
  const Diagnostic* d = findDiag(r.diagnostics, "idleLife/breathing: expected true, false or an object");
  ASSERT_NE(d, nullptr) << r.diagnostics.format();
  EXPECT_EQ(d->line, 2);
}
