// Blend spaces on real clips: foot skating of a walk-to-run blend at several parameter
// points, with and without phase alignment, against the single clips (blend_skating.hpp
// defines the figure). RobotExpressive's Walking and Running (in place, 0.958 s each) and
// Pab's walk (1.33 s) and jog (0.80 s) with root motion. Prints the table that
// docs/accuracy.md publishes. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "blend_skating.hpp"
#include "marionette/io/import.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

float legLength(const Rig& rig) {
  const Skeleton& s = rig.skeleton();
  const auto& leg = rig.joints().leftLeg;
  const std::vector<glm::mat4> rest = s.restModelMatrices();
  const auto at = [&](int j) { return glm::vec3(rest[static_cast<std::size_t>(j)][3]); };
  return glm::distance(at(leg.upper), at(leg.lower)) + glm::distance(at(leg.lower), at(leg.end));
}

struct Row {
  float x;
  BlendSkating aligned, plain;
};

// The table for a walk (x = 0) and a run (x = 1) of `rig`; checks that phase alignment
// skates less than plain normalized time between the clips, and no worse at them.
std::vector<Row> skatingTable(const std::shared_ptr<Rig>& rig, const char* who, const std::string& walk,
                              const std::string& run, bool rootMotion) {
  std::vector<Row> rows;
  std::string error;
  auto aligned = rig->makeBlendSpace({"aligned", 1, {{walk, 0.0f}, {run, 1.0f}}, true}, error);
  EXPECT_TRUE(aligned) << error;
  auto plain = rig->makeBlendSpace({"plain", 1, {{walk, 0.0f}, {run, 1.0f}}, false}, error);
  EXPECT_TRUE(plain) << error;
  if (!aligned || !plain) return rows;
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(aligned->samples()[i].keys.size(), 2u) << who << ": both feet's touchdowns align sample " << i;
  const int feet[2] = {rig->joints().leftLeg.end, rig->joints().rightLeg.end};
  std::vector<float> speeds;
  for (const auto& s : aligned->samples()) speeds.push_back(analyzeGait(s.clip, rig->skeleton(), feet[0], feet[1]).groundSpeed);
  const float leg = legLength(*rig);
  std::printf("%s: walk '%s' %.3f s, run '%s' %.3f s, ground speed %.3f / %.3f units/s, leg %.3f units\n",
              who, walk.c_str(), static_cast<double>(aligned->samples()[0].duration), run.c_str(),
              static_cast<double>(aligned->samples()[1].duration), static_cast<double>(speeds[0]),
              static_cast<double>(speeds[1]), static_cast<double>(leg));
  std::printf("%-5s | %-44s | %-44s\n", "x", "phase-aligned: mean p95 worst (leg/s), slide/contact (leg), % of travel, planted foot-frames/contacts",
              "normalized time: the same");
  for (float x : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    Row r{x, measureBlendSkating(rig, aligned, x, 0.0f, rootMotion, speeds),
          measureBlendSkating(rig, plain, x, 0.0f, rootMotion, speeds)};
    auto line = [&](const BlendSkating& s) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%.3f %.3f %.3f, %.4f, %5.1f %%, %d/%d", s.meanSpeed / leg, s.p95Speed / leg,
                    s.worstSpeed / leg, s.slidePerContact / leg, 100.0 * s.ratio(), s.plantedFrames, s.contacts);
      return std::string(buf);
    };
    std::printf("%-5.2f | %-44s | %-44s\n", static_cast<double>(x), line(r.aligned).c_str(), line(r.plain).c_str());
    EXPECT_GT(r.aligned.plantedFrames, 0) << who << " x " << x;
    rows.push_back(r);
  }
  return rows;
}

void expectAlignmentHelps(const std::vector<Row>& rows, const char* who, double bound) {
  ASSERT_EQ(rows.size(), 5u);
  double aligned = 0.0, plain = 0.0;
  for (std::size_t i = 1; i + 1 < rows.size(); ++i) {  // between the clips
    aligned += rows[i].aligned.ratio();
    plain += rows[i].plain.ratio();
    EXPECT_LT(rows[i].aligned.ratio(), bound) << who << " x " << rows[i].x;
  }
  EXPECT_LT(aligned, plain) << who << ": phase alignment skates less than normalized time";
  // At the clips themselves the warp only re-times one clip: no worse than it alone.
  for (std::size_t i : {std::size_t{0}, rows.size() - 1})
    EXPECT_LT(rows[i].aligned.ratio(), rows[i].plain.ratio() * 1.25 + 0.01) << who << " x " << rows[i].x;
}

}  // namespace

TEST(BlendSpaceOnRealClips, RobotExpressiveWalkToRunSkatesLessPhaseAligned) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  auto rig = loadRigWithProfile(path, "RobotExpressive.json");
  ASSERT_TRUE(rig);
  const auto rows = skatingTable(rig, "RobotExpressive", "Walking", "Running", false);
  expectAlignmentHelps(rows, "RobotExpressive", 0.6);
  // The shipped profile's space plays by name.
  Character c("robot", rig);
  ASSERT_TRUE(rig->findBlendSpace("locomotion")) << "assets/profiles/RobotExpressive.json names a 'locomotion' space";
  EXPECT_TRUE(c.playBlend(0, "locomotion"));
}

#ifdef MARIONETTE_HAS_ASSIMP  // Pab is FBX
TEST(BlendSpaceOnRealClips, PabWalkToJogSkatesLessPhaseAligned) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  auto rig = loadRigWithProfile(path, "pab_arnaud.json");
  ASSERT_TRUE(rig);
  for (const char* motion : {"walk", "jog"}) {
    const std::string file = sharedAsset(std::string("motions/fbx/pab_") + motion + ".fbx");
    MARIONETTE_REQUIRE_FILE(file);
    ImportOptions motionOnly;
    motionOnly.loadMeshes = false;
    ImportResult m = importAsset(file, motionOnly);
    ASSERT_TRUE(m.ok() && !m.asset->clips.empty()) << m.diagnostics.format();
    rig->addClip(m.asset->clips.front(), m.asset->skeleton, motion);
  }
  const auto rows = skatingTable(rig, "Pab", "walk", "jog", true);
  expectAlignmentHelps(rows, "Pab", 0.6);
}
#endif
