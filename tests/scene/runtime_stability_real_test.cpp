// Stiff and extreme cases on real data: assert bounds (no NaN, no jumps, no
// drift), not just "did not crash".
#include <gtest/gtest.h>

#include <cmath>

#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
// `optimize` off compares the runtime alone: the optimizer's tolerance is in
// metres, so it drops different tracks at different scales (by design).
std::shared_ptr<const Rig> robotRig(float scale = 1.0f, bool optimize = true) {
  ImportOptions o;
  o.loadMeshes = false;
  o.extraScale = scale;
  ImportResult r = importAsset(sharedAsset("characters/RobotExpressive.glb"), o);
  if (!r.ok()) return nullptr;
  RigSettings ro;
  ro.optimizeClips = optimize;
  return std::make_shared<Rig>(*r.asset, ro);
}

bool allFinite(const TransformBuffer& b) {
  for (float f : b.skinning())
    if (!std::isfinite(f)) return false;
  for (float f : b.model())
    if (!std::isfinite(f)) return false;
  for (float f : b.morphWeights())
    if (!std::isfinite(f)) return false;
  return true;
}

glm::vec3 worldJoint(const Character& c, std::size_t j) {
  return glm::vec3(c.transformBuffer().worldMatrix() * c.transformBuffer().modelMatrices()[j][3]);
}
}  // namespace

TEST(Stability, EveryRobotClipAtEveryStepSizeStaysFinite) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robotRig();
  ASSERT_TRUE(rig);
  for (double dt : {0.0, 1.0 / 240.0, 0.5, 10.0}) {
    Scene scene;
    int i = 0;
    for (const auto& clip : rig->clips()) {
      Character* c = scene.addCharacter(clip->clip.name, rig);
      PlayOptions o;
      o.rootMotion = (i % 2) == 0;
      o.wrap = (i % 3) == 0 ? WrapMode::Clamp : WrapMode::Loop;
      c->play(0, clip, o);
      PlayOptions wave;
      wave.weight = 0.4f;
      wave.additive = (i % 2) == 1;
      c->play(1, "Wave", wave);
      ++i;
    }
    for (int f = 0; f < 50; ++f) {
      scene.update(dt);
      for (const auto& c : scene.characters()) {
        ASSERT_TRUE(allFinite(c->transformBuffer())) << c->name() << " dt=" << dt << " frame " << f;
        ASSERT_TRUE(std::isfinite(c->position().x) && std::isfinite(c->position().z) && std::isfinite(c->heading()));
      }
    }
  }
}

TEST(Stability, NoJumpsBetweenFramesAt240Hz) {
  // A jump is a frame whose displacement is a spike against both neighbours
  // (linear keys make velocity change at keys, but never a one-frame spike).
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robotRig();
  ASSERT_TRUE(rig);
  for (const char* name : {"Walking", "Running", "Idle", "Dance", "Wave"}) {
    Scene scene;
    Character* c = scene.addCharacter("r", rig);
    ASSERT_TRUE(c->play(0, name));
    const double duration = rig->findClip(name)->clip.duration;
    const std::size_t n = c->skeleton().jointCount();
    const int frames = static_cast<int>(duration * 240.0) - 1;  // one cycle, no loop seam
    std::vector<std::vector<float>> step(n);
    scene.update(0.0);
    std::vector<glm::vec3> prev(n);
    for (std::size_t j = 0; j < n; ++j) prev[j] = worldJoint(*c, j);
    for (int f = 0; f < frames; ++f) {
      scene.update(1.0 / 240.0);
      for (std::size_t j = 0; j < n; ++j) {
        const glm::vec3 p = worldJoint(*c, j);
        step[j].push_back(glm::length(p - prev[j]));
        prev[j] = p;
      }
    }
    int spikes = 0;
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t f = 1; f + 1 < step[j].size(); ++f)
        if (step[j][f] > 4.0f * std::max(step[j][f - 1], step[j][f + 1]) + 2e-3f) {
          ++spikes;
          ADD_FAILURE() << name << ": joint " << c->skeleton().names[j] << " jumps " << step[j][f] << " m at frame " << f;
        }
    EXPECT_EQ(spikes, 0) << name;
  }
}

TEST(Stability, LoopingForAThousandCyclesDoesNotDrift) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robotRig();
  ASSERT_TRUE(rig);
  Scene a, b;
  Character* ca = a.addCharacter("a", rig);
  Character* cb = b.addCharacter("b", rig);
  ca->play(0, "Walking");
  cb->play(0, "Walking");
  const double d = rig->findClip("Walking")->clip.duration;
  // a: 1000 cycles in 1/60 s steps, plus the remainder to land on an exact multiple.
  const int steps = static_cast<int>(std::floor(1000.0 * d * 60.0));
  for (int i = 0; i < steps; ++i) a.update(1.0 / 60.0);
  a.update(1000.0 * d - steps / 60.0);
  b.update(0.0);
  for (std::size_t j = 0; j < ca->skeleton().jointCount(); ++j)
    EXPECT_LT(glm::length(worldJoint(*ca, j) - worldJoint(*cb, j)), 1e-3f) << ca->skeleton().names[j];
}

TEST(Stability, ExtremeScalesScaleLinearly) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  for (float s : {0.01f, 100.0f}) {
    auto unit = robotRig(1.0f, false), scaled = robotRig(s, false);
    ASSERT_TRUE(unit && scaled);
    Scene scene;
    Character* u = scene.addCharacter("u", unit);
    Character* k = scene.addCharacter("k", scaled);
    u->play(0, "Dance");
    k->play(0, "Dance");
    scene.update(0.7);
    ASSERT_TRUE(allFinite(k->transformBuffer()));
    for (std::size_t j = 0; j < u->skeleton().jointCount(); ++j) {
      const glm::vec3 pu = worldJoint(*u, j) * s, pk = worldJoint(*k, j);
      EXPECT_LT(glm::length(pu - pk), 1e-4f * std::max(1.0f, s) * 2.0f) << "scale " << s << " joint " << j;
    }
    // Skinning matrices are scale-invariant for rotation: palette * bind position = posed position.
    const glm::mat4& pu = u->transformBuffer().skinningMatrices()[7];
    const glm::mat4& pk = k->transformBuffer().skinningMatrices()[7];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(pu[c][r], pk[c][r], 1e-3f);
  }
}

TEST(Stability, MirroredRootKeepsHandedness) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  ImportOptions o;
  o.loadMeshes = false;
  ImportResult r = importAsset(sharedAsset("characters/RobotExpressive.glb"), o);
  ASSERT_TRUE(r.ok());
  auto asset = std::make_shared<Asset>(std::move(*r.asset));
  asset->skeleton.rootTransform = glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)) * asset->skeleton.rootTransform;
  auto rig = std::make_shared<Rig>(*asset);
  Scene scene;
  Character* c = scene.addCharacter("m", rig);
  c->play(0, "Walking");
  scene.update(0.3);
  ASSERT_TRUE(allFinite(c->transformBuffer()));
  for (const glm::mat4& m : c->transformBuffer().modelMatrices()) EXPECT_LT(glm::determinant(glm::mat3(m)), 0.0f);
}

TEST(Stability, RealDataRunsAreBitIdentical) {
  // The determinism contract on real data: two scenes fed the same calls hash
  // to the same transform buffers, frame by frame (in the style of Jolt's
  // determinism hash); a different step size gives a different hash.
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  auto rig = robotRig();
  ASSERT_TRUE(rig);
  auto run = [&](double dt) {
    Scene scene;
    int i = 0;
    for (const char* clip : {"Walking", "Dance", "Wave", "Running"}) {
      Character* c = scene.addCharacter(clip, rig);
      c->setPosition({static_cast<float>(i), 0.0f, 0.0f});
      PlayOptions o;
      o.speed = 0.8f + 0.1f * static_cast<float>(i++);
      c->play(0, clip, o);
      PlayOptions wave;
      wave.weight = 0.3f;
      wave.fadeIn = 0.5f;
      c->play(1, "Yes", wave);
    }
    std::uint64_t h = 1469598103934665603ull;
    for (int f = 0; f < 300; ++f) {
      scene.update(dt);
      for (const auto& c : scene.characters()) h = (h ^ c->transformBuffer().hash()) * 1099511628211ull;
    }
    return h;
  };
  const std::uint64_t a = run(1.0 / 60.0);
  EXPECT_EQ(a, run(1.0 / 60.0));
  EXPECT_NE(a, run(1.0 / 61.0));
}
