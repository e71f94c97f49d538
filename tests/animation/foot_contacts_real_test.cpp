// Foot contacts of the real locomotion clips, feet from the shipped profiles:
// RobotExpressive's Walking and Running (in place; its feet are Foot.L/Foot.R)
// and Pab's walk and jog (with root motion). Prints the intervals found.
// Missing data fails, never skips.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "marionette/animation/foot_contacts.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/io/import.hpp"
#include "marionette/rig/rig.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {


// Hip to ankle in the rest pose (through the lower joint).
float legLength(const Rig& rig) {
  const Skeleton& s = rig.skeleton();
  const LimbIk leg = makeLimbIk(s, rig.joints().leftLeg);
  std::vector<glm::mat4> model = s.restModelMatrices();
  const glm::vec3 hip(model[static_cast<std::size_t>(leg.upper)][3]), knee(model[static_cast<std::size_t>(leg.lower)][3]);
  return glm::distance(hip, knee) + glm::distance(knee, limbEndModel(s, s.restPose, leg));
}

float coverage(const ContactInterval& c) { return c.begin <= c.end ? c.end - c.begin : 1.0f - c.begin + c.end; }

float phaseGap(float a, float b) {
  const float d = std::fabs(a - b);
  return std::min(d, 1.0f - d);
}

struct Expect {
  float minCoverage, maxCoverage;
};

// One contact per foot per cycle, covering [min, max] of it, the two feet
// touching down about half a cycle apart.
void checkClip(const Rig& rig, const std::string& clipName, const char* who, Expect expect) {
  auto clip = rig.findClip(clipName);
  ASSERT_TRUE(clip) << clipName;
  const float leg = legLength(rig);
  const FootContactOptions settings = footContactOptionsForLeg(leg);
  const Skeleton& s = rig.skeleton();
  std::vector<ContactInterval> feet[2];
  const int joints[2] = {rig.joints().leftLeg.end, rig.joints().rightLeg.end};
  for (int f = 0; f < 2; ++f) {
    ASSERT_GE(joints[f], 0) << who;
    feet[f] = detectFootContacts(*clip, s, joints[f], settings);
    std::string line;
    for (const auto& c : feet[f]) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " [%.3f, %.3f) covers %.3f", static_cast<double>(c.begin), static_cast<double>(c.end),
                    static_cast<double>(coverage(c)));
      line += buf;
    }
    glm::vec3 travel(0.0f);
    float yaw = 0.0f;
    if (!clip->rootMotion.empty()) clip->rootMotion.evaluate(clip->clip.duration, travel, yaw);
    std::printf("%-24s %-9s (%.2f s, travels %.2f m, leg %.2f m):%s\n", who,
                s.names[static_cast<std::size_t>(joints[f])].c_str(), static_cast<double>(clip->clip.duration),
                static_cast<double>(glm::length(travel)), static_cast<double>(leg), line.c_str());
  }
  for (int f = 0; f < 2; ++f) {
    ASSERT_EQ(feet[f].size(), 1u) << who << " foot " << f;
    EXPECT_GE(coverage(feet[f][0]), expect.minCoverage) << who << " foot " << f;
    EXPECT_LE(coverage(feet[f][0]), expect.maxCoverage) << who << " foot " << f;
  }
  EXPECT_NEAR(phaseGap(feet[0][0].begin, feet[1][0].begin), 0.5f, 0.1f) << who;  // touchdowns alternate
}

}  // namespace

TEST(FootContactsOnRealClips, RobotExpressiveWalkingAndRunning) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = loadRigWithProfile(sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  ASSERT_TRUE(rig);
  // A cartoon gait, not a human one (measured, see docs/foot-ik.md): the right
  // foot is within reach of the ground for only a third of the walk, and in the
  // run each foot touches down for 70 to 100 ms of the 0.96 s cycle.
  checkClip(*rig, "Walking", "RobotExpressive Walking", {0.25f, 0.6f});
  checkClip(*rig, "Running", "RobotExpressive Running", {0.04f, 0.15f});
}

#ifdef MARIONETTE_HAS_ASSIMP
TEST(FootContactsOnRealClips, PabWalkAndJog) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/pab_arnaud.fbx"));
  auto rig = loadRigWithProfile(sharedAsset("characters/pab_arnaud.fbx"), "pab_arnaud.json");
  ASSERT_TRUE(rig);
  for (const char* motion : {"walk", "jog"}) {
    const std::string path = sharedAsset(std::string("motions/fbx/pab_") + motion + ".fbx");
    MARIONETTE_REQUIRE_FILE(path);
    ImportOptions motionOnly;
    motionOnly.loadMeshes = false;
    ImportResult m = importAsset(path, motionOnly);
    ASSERT_TRUE(m.ok() && !m.asset->clips.empty()) << m.diagnostics.format();
    rig->addClip(m.asset->clips.front(), m.asset->skeleton, motion);
  }
  checkClip(*rig, "walk", "Pab walk", {0.45f, 0.75f});
  // The left foot lands gliding (about 1.7 m/s for 50 ms), which shortens its contact.
  checkClip(*rig, "jog", "Pab jog", {0.15f, 0.5f});
}
#endif
