// Locomotion on the real characters of ../shared/assets: RobotExpressive (in-place
// Walking and Running clips) and Pab (walk and jog with root motion, separate
// FBX files). Walks 5 m and checks arrival, final facing and foot skating.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
constexpr float kPi = 3.14159265f;

std::shared_ptr<Rig> robot() {
  return loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
}

#ifdef MARIONETTE_HAS_ASSIMP  // Pab is FBX
std::shared_ptr<Rig> pab() {
  ImportResult r = importAsset(sharedAsset("characters/pab_arnaud.fbx"));
  EXPECT_TRUE(r.ok()) << r.diagnostics.format();
  if (!r.ok()) return nullptr;
  auto a = std::make_shared<Asset>(std::move(*r.asset));
  auto rig = std::make_shared<Rig>(a);
  for (const char* motion : {"walk", "jog"}) {
    ImportResult m = importAsset(sharedAsset(std::string("motions/fbx/pab_") + motion + ".fbx"));
    EXPECT_TRUE(m.ok()) << m.diagnostics.format();
    if (!m.ok() || m.asset->clips.empty()) return nullptr;
    // The motion files carry nodes the character has not (21 of walk's and 7 of
    // jog's tracks): they are dropped; the legs and the spine bind.
    const int unbound = rig->addClip(m.asset->clips.front(), m.asset->skeleton, motion);
    EXPECT_LT(unbound, static_cast<int>(m.asset->clips.front().tracks.size()) / 3) << motion;
  }
  CharacterProfileResult p = loadCharacterProfile(sourceFile("assets/profiles/pab_arnaud.json"), *a);
  EXPECT_TRUE(p.diagnostics.ok()) << p.diagnostics.format();
  p.profile.walk = "walk";  // the motions come from other files than the character's
  p.profile.run = "jog";
  rig->setProfile(std::move(p.profile));
  return rig;
}

#endif

struct WalkResult {
  bool done = false;
  float arrivalError = 0.0f, facingError = 0.0f, skatingRatio = 0.0f, seconds = 0.0f;
  int contactFrames = 0;
};

// Walks from the origin (facing +Z) to `target` at `speed` m/s (0: the manner's
// preset) and measures it. A frame skates when a foot is within 5 cm of its
// lowest height in the trace and moves faster than 0.5 m/s horizontally; the
// ratio is skating frames over such ground-contact frames.
WalkResult walk(const std::shared_ptr<Rig>& rig, glm::vec2 target, float facingDegrees, const std::string& manner,
                float speed, float dt = 1.0f / 60.0f) {
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  if (!rig->profile().idle.empty()) c->play(0, rig->profile().idle);
  BehaviorRequest r;
  r.id = "walk";
  r.kind = BehaviorKind::Locomotion;
  r.syncs = {{"start", 0.0}, {"end", 5.0}};
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g %g", static_cast<double>(target.x), static_cast<double>(target.y));
  r.parameters = {{"target", buf}, {"manner", manner}};
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(facingDegrees));
  r.parameters.emplace_back("facing", buf);
  if (speed > 0.0f) r.parameters.emplace_back("speed", std::to_string(speed));
  const BehaviorResult added = c->addBehavior(r);
  EXPECT_TRUE(added.realized) << added.message;
  const int feet[2] = {rig->joints().leftLeg.end, rig->joints().rightLeg.end};
  EXPECT_GE(feet[0], 0);
  EXPECT_GE(feet[1], 0);
  std::vector<glm::vec3> trace[2];
  std::vector<int> planted[2];
  std::vector<float> gaitWeight;
  WalkResult result;
  for (int frame = 0; frame < static_cast<int>(30.0f / dt); ++frame) {
    scene.update(dt);
    for (int f = 0; f < 2; ++f)
      trace[f].push_back(glm::vec3(c->transformBuffer().worldMatrix() *
                                   c->transformBuffer().modelMatrices()[static_cast<std::size_t>(feet[f])][3]));
    for (int f = 0; f < 2; ++f) planted[f].push_back(c->locomotion()->feet().planted(f));
    gaitWeight.push_back(c->locomotion()->weight());
    const LocomotionStatus st = c->locomotionStatus("walk");
    if (st.state == LocomotionStatus::kDone && !result.done) {
      result.done = true;
      result.seconds = static_cast<float>(st.doneTime);
    }
    if (result.done && c->locomotion()->weight() == 0.0f) break;
  }
  result.arrivalError = glm::length(glm::vec2(c->position().x, c->position().z) - target);
  result.facingError = std::fabs(std::remainder(c->heading() - glm::radians(facingDegrees), 2.0f * kPi));
  int skating = 0;
  for (int f = 0; f < 2; ++f) {
    float lowest = 1e9f;
    for (const glm::vec3& p : trace[f]) lowest = std::min(lowest, p.y);
    for (std::size_t k = 1; k < trace[f].size(); ++k) {
      if (trace[f][k].y - lowest > 0.05f) continue;
      ++result.contactFrames;
      const glm::vec3 d = trace[f][k] - trace[f][k - 1];
      if (std::hypot(d.x, d.z) / dt > 0.5f) {
        ++skating;
        if (std::getenv("MARIONETTE_DEBUG_SKATING"))
          std::printf("skate foot %d frame %zu h %.3f v %.2f planted %d/%d w %.2f\n", f, k, trace[f][k].y - lowest,
                      std::hypot(d.x, d.z) / dt, planted[f][k - 1], planted[f][k], gaitWeight[k]);
      }
    }
  }
  result.skatingRatio = result.contactFrames ? static_cast<float>(skating) / static_cast<float>(result.contactFrames) : 1.0f;
  return result;
}

void expectGoodWalk(const WalkResult& w, const std::string& what) {
  std::printf("%-28s arrived %d in %.2f s, position error %.3f m, facing error %.2f deg, skating %.2f %% of %d contact frames\n",
              what.c_str(), w.done, static_cast<double>(w.seconds), static_cast<double>(w.arrivalError),
              static_cast<double>(glm::degrees(w.facingError)), 100.0 * static_cast<double>(w.skatingRatio),
              w.contactFrames);
  EXPECT_TRUE(w.done) << what;
  EXPECT_LE(w.arrivalError, 0.2f) << what;
  EXPECT_LE(w.facingError, glm::radians(5.0f)) << what;
  EXPECT_LT(w.skatingRatio, 0.05f) << what;
  EXPECT_GT(w.contactFrames, 20) << what;
}
}  // namespace

TEST(LocomotionOnRealCharacters, RobotGaitIsAnalysed) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robot();
  ASSERT_TRUE(rig);
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  const LocomotionSet& set = c->locomotionSet();
  for (const std::string& n : set.notes) std::printf("  %s\n", n.c_str());
  ASSERT_TRUE(set.usable());
  ASSERT_TRUE(set.run.clip);
  // The robot's hips are 1.18 units high and it strides like a cartoon: its
  // stance foot covers about 3 hip heights per second walking, more running.
  scene.update(0.0);
  const float hipHeight = glm::vec3(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(rig->joints().hips)][3]).y;
  EXPECT_GT(set.walk.groundSpeed / hipHeight, 1.5f);
  EXPECT_LT(set.walk.groundSpeed / hipHeight, 5.0f);
  EXPECT_GT(set.run.groundSpeed, set.walk.groundSpeed * 1.1f);
}

TEST(LocomotionOnRealCharacters, RobotWalksAndRunsFiveMetres) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robot();
  ASSERT_TRUE(rig);
  expectGoodWalk(walk(rig, {3.0f, 4.0f}, 90.0f, "WALK", 0.0f), "Robot WALK to (3, 4)");
  expectGoodWalk(walk(rig, {-4.0f, -3.0f}, -30.0f, "RUN", 0.0f), "Robot RUN to (-4, -3)");
  Scene scene;
  const LocomotionSet& set = scene.addCharacter("c", rig)->locomotionSet();
  const float mid = 0.5f * (set.walk.groundSpeed + set.run.groundSpeed);
  expectGoodWalk(walk(rig, {0.0f, 5.0f}, 0.0f, "WALK", mid), "Robot between walk and run");
}

#ifdef MARIONETTE_HAS_ASSIMP
TEST(LocomotionOnRealCharacters, PabWalksAndJogsFiveMetres) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/pab_arnaud.fbx"));
  auto rig = pab();
  ASSERT_TRUE(rig);
  Scene scene;
  const LocomotionSet& set = scene.addCharacter("c", rig)->locomotionSet();
  for (const std::string& n : set.notes) std::printf("  %s\n", n.c_str());
  ASSERT_TRUE(set.usable());
  ASSERT_TRUE(set.run.clip);
  EXPECT_TRUE(set.walk.hasRootMotion);
  expectGoodWalk(walk(rig, {3.0f, 4.0f}, 180.0f, "WALK", 0.0f), "Pab WALK to (3, 4)");
  expectGoodWalk(walk(rig, {0.0f, 5.0f}, 0.0f, "RUN", 0.0f), "Pab RUN (jog) to (0, 5)");
  expectGoodWalk(walk(rig, {5.0f, 0.0f}, 90.0f, "WALK", 0.5f * (set.walk.groundSpeed + set.run.groundSpeed)),
                 "Pab between walk and jog");
}

#endif

// Under time steps from 1/240 s to 0.5 s the walk stays finite and arrives.
TEST(LocomotionOnRealCharacters, AnyTimeStepArrives) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robot();
  ASSERT_TRUE(rig);
  for (float dt : {1.0f / 240.0f, 1.0f / 30.0f, 0.1f, 0.5f}) {
    const WalkResult w = walk(rig, {3.0f, 4.0f}, 90.0f, "WALK", 0.0f, dt);
    EXPECT_TRUE(w.done) << dt;
    EXPECT_LE(w.arrivalError, 0.2f) << dt;
    EXPECT_LE(w.facingError, glm::radians(5.0f)) << dt;
  }
}
