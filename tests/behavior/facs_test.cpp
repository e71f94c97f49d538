// FACS on any face (rig/facs.hpp): units and named expressions, the profile guess's order
// (AU morphs, ARKit, VRM, the profile's facs map, eyelid and brow joints), and the face
// controller showing them with one warning per behavior.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "joint_rotation.hpp"
#include "marionette/behavior/procedural_controllers.hpp"
#include "marionette/rig/facs.hpp"
#include "marionette/scene/scene.hpp"
#include "synthetic.hpp"

using namespace marionette;

namespace {

// A face with a bit of everything: ARKit smiles and inner brow, an AU-named left blink, VRM
// presets (blink both, joy), an upper eyelid on each side and a right brow joint.
std::shared_ptr<Asset> mixedFace() {
  auto asset = std::make_shared<Asset>();
  asset->skeleton = test::makeChain(4);  // j0..j3: hips, spine, neck, head
  for (const char* name : {"EyeLid_Upper.L", "EyeLid_Upper.R", "EyeLid_Lower.L", "Brow.R"}) {
    Transform t;
    t.translation = {0.0f, 0.1f, 0.05f};
    asset->skeleton.addJoint(name, 3, t, glm::mat4(1.0f), true);
  }
  asset->morphTargets = {"blendShape1.mouthSmileLeft", "blendShape1.mouthSmileRight", "AU_45_L", "browInnerUp",
                         "vrmBlink", "vrmJoy"};
  asset->hasHumanoid = true;
  asset->humanoid.expressions["blink"] = {{4, 1.0f}};
  asset->humanoid.expressions["joy"] = {{5, 0.8f}};
  return asset;
}

std::shared_ptr<Rig> mixedRig() {
  auto asset = mixedFace();
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfile p = guessCharacterProfile(*asset);
  p.hips = "j0", p.spine = {"j1"}, p.neck = "j2", p.head = "j3";
  p.face.clear();  // only what FACS finds
  rig->setProfile(p);
  return rig;
}

BehaviorRequest face(std::string id, BehaviorKind kind, std::string expression, float amount = 1.0f) {
  BehaviorRequest r;
  r.id = std::move(id);
  r.kind = kind;
  r.parameters = FaceParameters{std::move(expression), amount};
  r.syncs = {{"start", 0.0}, {"attackPeak", 0.2}, {"relax", 1.0}, {"end", 1.5}};
  return r;
}

int morph(const Rig& rig, const std::string& name) {
  const auto& m = rig.morphTargets();
  return static_cast<int>(std::find(m.begin(), m.end(), name) - m.begin());
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(Facs, UnitsAndNamedExpressionsAreRead) {
  struct Case {
    const char* text;
    int au, side;
  };
  for (const Case& c : {Case{"AU12", 12, 0}, Case{"au12", 12, 0}, Case{"12", 12, 0}, Case{"AU12_L", 12, -1},
                        Case{"AU12L", 12, -1}, Case{"AU45_LEFT", 45, -1}, Case{"AU1_right", 1, 1}, Case{"AU2-R", 2, 1}}) {
    const auto u = parseFacsUnit(c.text);
    ASSERT_TRUE(u) << c.text;
    EXPECT_EQ(u->au, c.au) << c.text;
    EXPECT_EQ(u->side, c.side) << c.text;
  }
  for (const char* bad : {"", "AU", "AU123", "AU12_X", "AU0", "SMILE", "AU12__L", "A12"}) EXPECT_FALSE(parseFacsUnit(bad)) << bad;
  EXPECT_EQ(facsKey(46, -1), "AU46_L");
  EXPECT_EQ(facsKey(1, 0), "AU1");
  const auto wink = facsUnitsOf("wink");
  ASSERT_EQ(wink.size(), 1u);
  EXPECT_EQ(wink[0].au, 46);
  EXPECT_EQ(wink[0].side, -1);
  const auto brow = facsUnitsOf("RAISE_LEFT_BROW");
  ASSERT_EQ(brow.size(), 2u);
  EXPECT_EQ(brow[0].au, 1);
  EXPECT_EQ(brow[1].au, 2);
  EXPECT_EQ(brow[1].side, -1);
  EXPECT_TRUE(facsUnitsOf("NOT_AN_EXPRESSION").empty());
  // Every named expression's units are in the table, so each can be shown somehow.
  for (const FacsExpression& e : facsExpressions())
    for (const FacsUnitRequest& u : e.units) EXPECT_NE(facsUnit(u.au), nullptr) << e.name << " AU" << u.au;
}

TEST(Facs, TheGuessTakesAuThenArkitThenVrmThenJoints) {
  const CharacterProfile p = guessCharacterProfile(*mixedFace());
  auto source = [&](const std::string& key) {
    const auto it = p.facs.find(key);
    return it == p.facs.end() ? std::string("none") : it->second.source;
  };
  EXPECT_EQ(source("AU45_L"), "AU morphs");                  // AU_45_L, before ARKit and VRM
  EXPECT_EQ(source("AU45"), "VRM expression 'blink'");       // no right AU morph, no ARKit blink
  EXPECT_EQ(source("AU45_R"), "eyelid joints");              // VRM's blink is both sides: not one
  EXPECT_EQ(source("AU12"), "ARKit blendshapes");            // before VRM's joy
  EXPECT_EQ(source("AU12_L"), "ARKit blendshapes");
  EXPECT_EQ(source("AU1"), "ARKit blendshapes");             // browInnerUp
  EXPECT_EQ(source("AU2_R"), "brow joints");                 // no outer brow morph: the right brow joint
  EXPECT_EQ(source("AU2_L"), "none");                        // no left brow joint
  EXPECT_EQ(source("AU15"), "none");
  ASSERT_EQ(p.facs.at("AU12").morphs.size(), 2u);
  EXPECT_EQ(p.facs.at("AU12_L").morphs.at(0).morph, "blendShape1.mouthSmileLeft");
  // The lower lid is no upper lid: only the two upper ones open the eyes wide.
  ASSERT_EQ(p.facs.at("AU5").joints.size(), 2u);
  for (const FacsJointMove& m : p.facs.at("AU5").joints) EXPECT_NE(m.joint.find("Upper"), std::string::npos) << m.joint;
  ASSERT_EQ(p.facs.at("AU43_R").joints.size(), 1u);
  EXPECT_EQ(p.facs.at("AU43_R").joints[0].joint, "EyeLid_Upper.R");
}

TEST(Facs, UnitsAndExpressionsMoveMorphsAndJointsWithOneWarning) {
  Scene scene;
  auto rig = mixedRig();
  Character* c = scene.addCharacter("c", rig);
  // AU12 at 0.8: both ARKit smiles at 0.8, said once.
  BehaviorResult smile = c->addBehavior(face("au12", BehaviorKind::FaceFacs, "AU12", 0.8f));
  ASSERT_TRUE(smile.realized) << smile.message;
  EXPECT_EQ(count(smile.message, "is shown through FACS"), 1u) << smile.message;
  EXPECT_NE(smile.message.find("AU12 by ARKit blendshapes"), std::string::npos) << smile.message;
  // WINK: the left upper lid closes (no left blink morph for AU46, no one-sided VRM preset).
  BehaviorResult wink = c->addBehavior(face("wink", BehaviorKind::FaceLexeme, "WINK"));
  ASSERT_TRUE(wink.realized) << wink.message;
  EXPECT_NE(wink.message.find("AU46_L by eyelid joints"), std::string::npos) << wink.message;
  const int leftLid = rig->skeleton().findJoint("EyeLid_Upper.L"), rightLid = rig->skeleton().findJoint("EyeLid_Upper.R");
  ASSERT_GE(leftLid, 0);
  scene.update(0.0);
  const glm::quat leftRest = test::modelRotation(*c, leftLid), rightRest = test::modelRotation(*c, rightLid);
  scene.update(0.5);  // held between attackPeak and relax
  const auto weights = c->transformBuffer().morphWeights();
  EXPECT_NEAR(weights[static_cast<std::size_t>(morph(*rig, "blendShape1.mouthSmileLeft"))], 0.8f, 1e-5f);
  EXPECT_NEAR(weights[static_cast<std::size_t>(morph(*rig, "blendShape1.mouthSmileRight"))], 0.8f, 1e-5f);
  EXPECT_NEAR(glm::degrees(test::preciseAngleBetween(leftRest, test::modelRotation(*c, leftLid))), 35.0f, 0.05f);
  EXPECT_LT(glm::degrees(test::preciseAngleBetween(rightRest, test::modelRotation(*c, rightLid))), 1e-3f);
  // The lid turns about the character's left axis: its forward tips down.
  const glm::vec3 forward = test::modelRotation(*c, leftLid) * glm::inverse(leftRest) * glm::vec3(0, 0, 1);
  EXPECT_LT(forward.y, -0.5f);
  scene.update(1.5);
  EXPECT_LT(glm::degrees(test::preciseAngleBetween(leftRest, test::modelRotation(*c, leftLid))), 1e-3f);
  EXPECT_EQ(c->transformBuffer().morphWeights()[static_cast<std::size_t>(morph(*rig, "blendShape1.mouthSmileLeft"))], 0.0f);
}

TEST(Facs, PartlyShownExpressionsSayWhatIsMissingAndUnknownOnesFail) {
  Scene scene;
  auto rig = mixedRig();
  Character* c = scene.addCharacter("c", rig);
  // RAISE_LEFT_BROW = AU1_L + AU2_L: AU1 has one shape for both sides; nothing moves AU2_L.
  BehaviorResult brow = c->addBehavior(face("brow", BehaviorKind::FaceLexeme, "RAISE_LEFT_BROW"));
  ASSERT_TRUE(brow.realized) << brow.message;
  EXPECT_NE(brow.message.find("AU1 by ARKit blendshapes (one shape for both sides)"), std::string::npos) << brow.message;
  EXPECT_NE(brow.message.find("not shown (nothing on this face moves it): AU2_L"), std::string::npos) << brow.message;
  // A unit nothing shows fails, naming it; a name neither a unit nor an expression fails too.
  BehaviorResult frown = c->addBehavior(face("frown", BehaviorKind::FaceFacs, "AU15"));
  EXPECT_FALSE(frown.realized);
  EXPECT_NE(frown.message.find("nothing shows its FACS units AU15"), std::string::npos) << frown.message;
  BehaviorResult odd = c->addBehavior(face("odd", BehaviorKind::FaceLexeme, "GRIMACE_SIDEWAYS"));
  EXPECT_FALSE(odd.realized);
  EXPECT_NE(odd.message.find("neither a FACS unit"), std::string::npos) << odd.message;
  // A unit the profile's face table maps by name is exact: no warning.
  auto exactRig = std::make_shared<Rig>(*mixedFace());
  CharacterProfile p = exactRig->profile();
  p.face["AU46_L"] = {{"AU_45_L", 1.0f}};
  exactRig->setProfile(p);
  BehaviorResult exact = scene.addCharacter("e", exactRig)->addBehavior(face("w", BehaviorKind::FaceLexeme, "WINK"));
  ASSERT_TRUE(exact.realized);
  EXPECT_EQ(exact.message.find("FACS"), std::string::npos) << exact.message;
}

// A brow joint rises by its share of the eye height, in the model frame, whatever the
// file's axes and units (a Z-up centimetre root space here).
TEST(Facs, BrowJointsRiseInTheModelFrame) {
  for (bool zUpCentimetres : {false, true}) {
    auto asset = mixedFace();
    if (zUpCentimetres)
      asset->skeleton.rootTransform =
          glm::scale(glm::mat4_cast(glm::angleAxis(-1.5707963f, glm::vec3(1, 0, 0))), glm::vec3(0.01f));
    auto rig = std::make_shared<Rig>(*asset);
    CharacterProfile p = guessCharacterProfile(*asset);
    p.hips = "j0", p.spine = {"j1"}, p.neck = "j2", p.head = "j3";
    rig->setProfile(p);
    Scene scene;
    Character* c = scene.addCharacter("c", rig);
    BehaviorResult r = c->addBehavior(face("b", BehaviorKind::FaceFacs, "AU2_R"));
    ASSERT_TRUE(r.realized) << r.message;
    const int brow = rig->skeleton().findJoint("Brow.R");
    scene.update(0.0);
    const glm::vec3 rest(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(brow)][3]);
    scene.update(0.5);
    const glm::vec3 up(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(brow)][3]);
    const glm::vec3 moved = up - rest;
    const float expected = 0.006f * rig->joints().eyeHeight;
    EXPECT_NEAR(moved.y, expected, 1e-4f * std::max(1.0f, expected)) << zUpCentimetres;
    EXPECT_NEAR(moved.x, 0.0f, 1e-5f);
    EXPECT_NEAR(moved.z, 0.0f, 1e-5f);
  }
}

// A face with upper eyelid joints and no blink morph blinks with its lids (FACS's AU45 by
// eyelid joints), and a face expression that already closes them is not closed further.
TEST(Facs, BlinksCloseEyelidJointsAndNeverBeyondAFaceThatClosesThem) {
  auto asset = std::make_shared<Asset>();
  asset->skeleton = test::makeChain(4);
  for (const char* name : {"UpperEyelid_L", "UpperEyelid_R"}) {
    Transform t;
    t.translation = {0.0f, 0.1f, 0.05f};
    asset->skeleton.addJoint(name, 3, t, glm::mat4(1.0f), true);
  }
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfile p = guessCharacterProfile(*asset);
  p.hips = "j0", p.spine = {"j1"}, p.neck = "j2", p.head = "j3";
  rig->setProfile(p);
  ASSERT_EQ(rig->joints().facs.at("AU45").source, "eyelid joints");
  const int lid = rig->skeleton().findJoint("UpperEyelid_L");
  for (float faceClosed : {0.0f, 1.0f, 0.5f}) {
    Scene scene;
    Character* c = scene.addCharacter("c", rig);
    BehaviorRequest blink;
    blink.id = "blink";
    blink.kind = BehaviorKind::BlinkEmitter;
    blink.parameters = BlinkParameters{.meanIntervalSeconds = 1.0f, .seed = 7};
    blink.syncs = {{"start", 0.0}, {"end", 20.0}};
    BehaviorResult r = c->addBehavior(blink);
    ASSERT_TRUE(r.realized) << r.message;
    if (faceClosed > 0.0f) {
      BehaviorRequest close = face("close", BehaviorKind::FaceLexeme, "CLOSE_EYES", faceClosed);
      close.syncs = {{"start", 0.0}, {"attackPeak", 0.01}, {"relax", 20.0}, {"end", 20.0}};
      ASSERT_TRUE(c->addBehavior(close).realized);
    }
    scene.update(0.0);
    const glm::quat rest = test::modelRotation(*c, rig->skeleton().findJoint("j3"));
    float most = 0.0f, least = 180.0f;
    for (int f = 0; f < 600; ++f) {  // 10 s at 60 Hz: about 10 blinks
      scene.update(1.0 / 60.0);
      // The lid's turn against the head's (it has no rest turn of its own here).
      const float angle = glm::degrees(test::preciseAngleBetween(rest, test::modelRotation(*c, lid)));
      most = std::max(most, angle);
      least = std::min(least, angle);
    }
    SCOPED_TRACE(faceClosed);
    EXPECT_GT(most, 34.0f);   // a blink closes the lid (35 degrees at full)
    EXPECT_LE(most, 35.01f);  // and never beyond, whatever the face already closed
    EXPECT_NEAR(least, 35.0f * faceClosed, 0.01f);  // between blinks: the face's own closure
  }
}
