#include <gtest/gtest.h>

#include <cmath>

#include "marionette/scene/scene.hpp"
#include "synthetic_rig.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
struct RecordingListener : SceneListener {
  int created = 0, removed = 0, changed = 0, warnings = 0;
  void onCharacterCreated(const Character&) override { ++created; }
  void onCharacterRemoved(const Character&) override { ++removed; }
  void onCharacterChanged(const Character&, ChangeKind, std::string_view) override { ++changed; }
  void onLog(LogLevel level, std::string_view) override { warnings += level != LogLevel::Info; }
};

std::uint64_t runAndHash(int characters, int frames, double dt) {
  auto rig = makeSyntheticRig();
  Scene scene;
  for (int i = 0; i < characters; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->setPosition({static_cast<float>(i), 0, 0});
    PlayOptions walk;
    walk.rootMotion = true;
    walk.speed = 1.0f + 0.1f * static_cast<float>(i);
    c->play(0, "walk", walk);
    PlayOptions wave;
    wave.weight = 0.5f;
    wave.fadeIn = 0.3f;
    c->play(1, "wave", wave);
  }
  std::uint64_t h = 0;
  for (int f = 0; f < frames; ++f) {
    scene.update(dt);
    for (auto& c : scene.characters()) h = h * 31 + c->transformBuffer().hash();
  }
  return h;
}
}  // namespace

TEST(Scene, RejectsNegativeAndNaNDtWithAWarning) {
  Scene scene;
  RecordingListener l;
  scene.addListener(&l);
  scene.update(-0.1);
  scene.update(NAN);
  scene.update(INFINITY);
  EXPECT_EQ(scene.time(), 0.0);
  EXPECT_EQ(scene.frame(), 0u);
  EXPECT_EQ(l.warnings, 3);
  scene.update(0.0);
  EXPECT_EQ(scene.frame(), 1u);
}

TEST(Scene, DuplicateNamesAndNullRigAreRejected) {
  Scene scene;
  RecordingListener l;
  scene.addListener(&l);
  auto rig = makeSyntheticRig();
  EXPECT_NE(scene.addCharacter("a", rig), nullptr);
  EXPECT_EQ(scene.addCharacter("a", rig), nullptr);
  EXPECT_EQ(scene.addCharacter("b", nullptr), nullptr);
  EXPECT_EQ(l.warnings, 2);
  EXPECT_EQ(scene.characters().size(), 1u);
}

TEST(Scene, ListenersAttachDetachAndHearEvents) {
  auto rig = makeSyntheticRig();
  Scene scene;
  RecordingListener a, b;
  scene.addListener(&a);
  scene.addListener(&a);  // once only
  scene.addListener(&b);
  Character* c = scene.addCharacter("x", rig);
  EXPECT_EQ(a.created, 1);
  EXPECT_EQ(b.created, 1);
  scene.removeListener(&b);
  c->play(0, "walk");
  EXPECT_EQ(a.changed, 1);
  EXPECT_EQ(b.changed, 0);
  EXPECT_FALSE(c->play(0, "no such clip"));
  EXPECT_FALSE(c->play(99, "walk"));
  EXPECT_EQ(a.warnings, 2);
  EXPECT_TRUE(scene.removeCharacter("x"));
  EXPECT_EQ(a.removed, 1);
  EXPECT_FALSE(scene.removeCharacter("x"));
}

TEST(Scene, SeveralScenesCoexist) {
  auto rig = makeSyntheticRig();
  Scene s1, s2;
  s1.addCharacter("a", rig)->play(0, "wave");
  s2.addCharacter("a", rig);
  s1.update(0.25);
  s2.update(0.5);
  EXPECT_EQ(s1.time(), 0.25);
  EXPECT_EQ(s2.time(), 0.5);
  // s2's character is at rest, s1's waves.
  EXPECT_NE(s1.characters()[0]->transformBuffer().hash(), s2.characters()[0]->transformBuffer().hash());
}

TEST(Scene, DeterministicBitIdenticalBuffers) {
  const auto a = runAndHash(5, 200, 1.0 / 60.0);
  const auto b = runAndHash(5, 200, 1.0 / 60.0);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, runAndHash(5, 200, 1.0 / 59.0));  // and the hash does see a change
}

TEST(Character, FrameCounterAndBufferLayout) {
  auto rig = makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  const TransformBuffer& b = c->transformBuffer();
  EXPECT_EQ(b.jointCount(), 4u);
  EXPECT_EQ(b.skinning().size(), 64u);
  EXPECT_EQ(b.model().size(), 64u);
  EXPECT_EQ(b.morphCount(), 2u);
  EXPECT_TRUE(b.skinning3x4().empty());
  const float* before = b.skinning().data();
  c->transformBuffer().setPacked3x4(true);
  c->play(0, "wave");
  scene.update(0.25);
  scene.update(0.0);
  EXPECT_EQ(b.frame(), 2u);
  EXPECT_EQ(b.skinning().data(), before);  // stable addresses
  ASSERT_EQ(b.skinning3x4().size(), 48u);
  // Packed 3x4 rows equal the top three rows of the 4x4.
  for (int j = 0; j < 4; ++j)
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col)
        EXPECT_EQ(b.skinning3x4()[j * 12 + r * 4 + col], b.skinning()[j * 16 + col * 4 + r]);
  // At the wave's peak the top joint is rotated 1.2 rad about Z.
  glm::mat4 m = b.modelMatrices()[3];
  EXPECT_NEAR(std::atan2(m[0][1], m[0][0]), 1.2f, 1e-3f);
}

TEST(Character, IdleCharacterIsRestAndCostsNoLayer) {
  auto rig = makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  scene.update(1.0 / 60.0);
  EXPECT_EQ(c->stats().activeLayers, 0);
  for (std::size_t j = 0; j < 4; ++j) {
    const glm::mat4& p = c->transformBuffer().skinningMatrices()[j];
    for (int col = 0; col < 4; ++col)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(p[col][r], col == r ? 1.0f : 0.0f, 1e-5f);
  }
  c->play(0, "walk");
  scene.update(1.0 / 60.0);
  EXPECT_TRUE(c->stats().sampledDirect);
}

TEST(Character, RootMotionMovesTheCharacterAndKeepsThePoseInPlace) {
  auto rig = makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  c->setHeading(glm::radians(90.0f));  // facing +X: clip +Z becomes world +X
  PlayOptions o;
  o.rootMotion = true;
  c->play(0, "walk", o);
  for (int i = 0; i < 240; ++i) scene.update(1.0 / 120.0);  // 2 s = 2 cycles of 1 m
  EXPECT_NEAR(c->position().x, 2.0f, 1e-3f);
  EXPECT_NEAR(c->position().z, 0.0f, 1e-3f);
  // The root joint's model-space horizontal position stays at the clip start.
  const glm::mat4& root = c->transformBuffer().modelMatrices()[0];
  EXPECT_NEAR(root[3].z, 0.0f, 1e-4f);
  EXPECT_NEAR(root[3].y, 1.0f, 1e-5f);  // vertical motion is kept in the pose
}

TEST(Character, DtVariantsGiveTheSamePoseAtTheSameTime) {
  // dt in {1/240, 0.5, 10}: the same clip time gives the same pose and the same
  // root-motion travel, whatever the step.
  auto rig = makeSyntheticRig();
  auto travel = [&](double dt, int steps) {
    Scene scene;
    Character* c = scene.addCharacter("x", rig);
    PlayOptions o;
    o.rootMotion = true;
    c->play(0, "walk", o);
    for (int i = 0; i < steps; ++i) scene.update(dt);
    return std::make_pair(c->position(), c->transformBuffer().hash());
  };
  auto fine = travel(1.0 / 240.0, 2400);
  auto half = travel(0.5, 20);
  auto big = travel(10.0, 1);
  EXPECT_NEAR(fine.first.z, 10.0f, 2e-3f);
  EXPECT_NEAR(half.first.z, 10.0f, 2e-3f);
  EXPECT_NEAR(big.first.z, 10.0f, 2e-3f);
  EXPECT_NEAR(big.first.x, 0.0f, 1e-3f);
}

TEST(Character, LongSceneTimeHasNoJitter) {
  auto rig = makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  PlayOptions o;
  o.startTime = 1.0e7;  // ten million seconds in: double time keeps sub-µs resolution
  c->play(0, "wave", o);
  scene.update(0.0);
  const glm::mat4 a = c->transformBuffer().modelMatrices()[3];
  Scene fresh;
  Character* d = fresh.addCharacter("x", rig);
  PlayOptions p;
  p.startTime = std::fmod(1.0e7, 0.5);
  d->play(0, "wave", p);
  fresh.update(0.0);
  const glm::mat4 b = d->transformBuffer().modelMatrices()[3];
  for (int col = 0; col < 4; ++col)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[col][r], b[col][r], 1e-5f);
}

TEST(Character, FadeOutRemovesTheLayer) {
  auto rig = makeSyntheticRig();
  Scene scene;
  RecordingListener l;
  scene.addListener(&l);
  Character* c = scene.addCharacter("x", rig);
  c->play(1, "wave");
  c->stop(1, 0.2f);
  scene.update(0.1);
  EXPECT_EQ(c->layerCount(), 1);
  scene.update(0.15);
  EXPECT_EQ(c->layerCount(), 0);
}

TEST(Character, MorphWeightsFollowTheClip) {
  auto rig = makeSyntheticRig();
  Scene scene;
  Character* c = scene.addCharacter("x", rig);
  c->play(0, "walk");
  scene.update(0.25);
  EXPECT_NEAR(c->transformBuffer().morphWeights()[1], 0.25f, 1e-5f);
  EXPECT_EQ(c->transformBuffer().morphWeights()[0], 0.0f);
}
