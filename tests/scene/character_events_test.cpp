// Animation events through a scene's clip layers (SceneListener::onAnimationEvent): markers
// and foot contacts crossed once, in order, with the clip, layer, weight, the event's clip
// time and the scene time of the crossing, across loops, large steps, negative speed, held
// and restarted layers; the cap per frame; a listener that replaces the layer mid-frame.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "marionette/scene/scene.hpp"
#include "synthetic.hpp"
#include "synthetic_walk.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

// A 1 s clip "beat" with markers a (0.25), b (0.5), c (0.75) and a 0.25 s clip "tick" with
// one at 0.125; both rotate one joint of a 3-joint chain.
std::shared_ptr<Rig> makeMarkerRig() {
  Asset asset;
  asset.skeleton = makeChain(3);
  Clip beat;
  beat.name = "beat";
  beat.tracks.push_back(rotationTrack(1, {0.0f, 0.5f, 1.0f}, {0.0f, 0.5f, 0.0f}));
  beat.updateDuration();
  beat.events = {{0.25f, "a"}, {0.5f, "b"}, {0.75f, "c"}};
  Clip tick;
  tick.name = "tick";
  tick.tracks.push_back(rotationTrack(2, {0.0f, 0.25f}, {0.0f, 0.3f}));
  tick.updateDuration();
  tick.events = {{0.125f, "t"}};
  asset.clips = {beat, tick};
  return std::make_shared<Rig>(asset);
}

struct Heard {
  std::string character, name, clip;
  AnimationEventKind kind;
  FootSide side;
  int layer;
  float weight, clipTime;
  double sceneTime;
};

struct Recorder : SceneListener {
  std::vector<Heard> heard;
  int warnings = 0;
  void onAnimationEvent(const Character& c, const AnimationEvent& e) override {
    heard.push_back({c.name(), std::string(e.name), std::string(e.clip), e.kind, e.side, e.layer, e.weight, e.clipTime,
                     e.sceneTime});
  }
  void onLog(LogLevel level, std::string_view) override { warnings += level == LogLevel::Warning; }
  [[nodiscard]] std::string names() const {
    std::string s;
    for (const Heard& h : heard) s += h.name;
    return s;
  }
};

struct Fixture {
  Scene scene;
  Recorder recorder;
  Character* character = nullptr;
  explicit Fixture(std::shared_ptr<const Rig> rig = makeMarkerRig()) {
    scene.addListener(&recorder);
    character = scene.addCharacter("hero", std::move(rig));
  }
};

}  // namespace

TEST(CharacterEvents, MarkersCrossedOncePerLoopWithTheirTimes) {
  Fixture f;
  ASSERT_TRUE(f.character->play(0, "beat"));
  for (int k = 0; k < 180; ++k) f.scene.update(1.0 / 60.0);  // 3 s: three loops
  ASSERT_EQ(f.recorder.names(), "abcabcabc");
  for (std::size_t i = 0; i < f.recorder.heard.size(); ++i) {
    const Heard& h = f.recorder.heard[i];
    EXPECT_EQ(h.character, "hero");
    EXPECT_EQ(h.clip, "beat");
    EXPECT_EQ(h.kind, AnimationEventKind::Marker);
    EXPECT_EQ(h.side, FootSide::None);
    EXPECT_EQ(h.layer, 0);
    EXPECT_FLOAT_EQ(h.weight, 1.0f);
    EXPECT_FLOAT_EQ(h.clipTime, 0.25f * static_cast<float>(i % 3 + 1));
    // Speed 1 from 0: crossed at its own time plus the loops before.
    EXPECT_NEAR(h.sceneTime, static_cast<double>(i / 3) + h.clipTime, 1e-9);
  }
}

TEST(CharacterEvents, FramesEndingExactlyOnEventsSendThemOnce) {
  Fixture f;
  ASSERT_TRUE(f.character->play(0, "beat"));
  for (int k = 0; k < 16; ++k) f.scene.update(0.125);  // frame ends fall on every event
  EXPECT_EQ(f.recorder.names(), "abcabc");
  // Each is sent in the frame that leaves it: at the frame's start.
  EXPECT_DOUBLE_EQ(f.recorder.heard[0].sceneTime, 0.25);
}

TEST(CharacterEvents, OneSecondStepsCrossEveryLoopInOrder) {
  Fixture f;
  ASSERT_TRUE(f.character->play(0, "tick"));  // 0.25 s: four loops per step
  f.scene.update(1.0);
  f.scene.update(1.0);
  ASSERT_EQ(f.recorder.heard.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(f.recorder.heard[i].sceneTime, 0.125 + 0.25 * static_cast<double>(i), 1e-9);
  EXPECT_EQ(f.recorder.warnings, 0);
}

TEST(CharacterEvents, NegativeSpeedCrossesBackwards) {
  Fixture f;
  PlayOptions back;
  back.speed = -2.0f;
  back.startTime = 1.0;
  ASSERT_TRUE(f.character->play(0, "beat", back));
  for (int k = 0; k < 60; ++k) f.scene.update(1.0 / 60.0);  // 2 s of clip, backwards
  ASSERT_EQ(f.recorder.names(), "cbacba");
  // From clip time 1 at speed -2: c (0.75) at 0.125 s, b at 0.25 s, a at 0.375 s.
  EXPECT_NEAR(f.recorder.heard[0].sceneTime, 0.125, 1e-9);
  EXPECT_NEAR(f.recorder.heard[2].sceneTime, 0.375, 1e-9);
  EXPECT_NEAR(f.recorder.heard[3].sceneTime, 0.625, 1e-9);
}

TEST(CharacterEvents, HeldLayersSendNothingAndStartTimesCount) {
  Fixture f;
  PlayOptions hold;
  hold.speed = 0.0f;
  hold.startTime = 0.5;  // on an event
  ASSERT_TRUE(f.character->play(0, "beat", hold));
  for (int k = 0; k < 30; ++k) f.scene.update(0.1);
  f.scene.update(0.0);
  EXPECT_TRUE(f.recorder.heard.empty());
  // Scrubbed to 0.5 and played: the event there is crossed as the playhead leaves it.
  PlayOptions scrub;
  scrub.startTime = 0.5;
  ASSERT_TRUE(f.character->play(0, "beat", scrub));
  const double start = f.scene.time();
  f.scene.update(0.1);
  ASSERT_EQ(f.recorder.names(), "b");
  EXPECT_NEAR(f.recorder.heard[0].sceneTime, start, 1e-9);
  f.scene.update(0.3);  // 0.6 -> 0.9: c
  f.scene.update(0.2);  // 0.9 -> 1.1: nothing (a is at 1.25)
  EXPECT_EQ(f.recorder.names(), "bc");
  // Restarted at 0.5 again (a jump: nothing between is crossed).
  ASSERT_TRUE(f.character->play(0, "beat", scrub));
  f.scene.update(0.1);
  EXPECT_EQ(f.recorder.names(), "bcb");
}

TEST(CharacterEvents, ClampedLayersSendTheirEndOnce) {
  Fixture f;
  PlayOptions once;
  once.wrap = WrapMode::Clamp;
  ASSERT_TRUE(f.character->play(0, "beat", once));
  for (int k = 0; k < 100; ++k) f.scene.update(0.05);
  EXPECT_EQ(f.recorder.names(), "abc");
}

TEST(CharacterEvents, LayerIndexAndFadingWeightAreReported) {
  Fixture f;
  PlayOptions fading;
  fading.fadeIn = 1.0f;
  fading.weight = 0.8f;
  ASSERT_TRUE(f.character->play(3, "beat", fading));
  for (int k = 0; k < 60; ++k) f.scene.update(1.0 / 60.0);
  ASSERT_EQ(f.recorder.heard.size(), 3u);
  EXPECT_EQ(f.recorder.heard[0].layer, 3);
  EXPECT_NEAR(f.recorder.heard[0].weight, 0.8f * 0.25f, 0.8f / 60.0f + 1e-4f);  // the weight at the end of that frame
  EXPECT_GT(f.recorder.heard[2].weight, f.recorder.heard[0].weight);
}

TEST(CharacterEvents, AnHourLongStepIsCappedWithAWarning) {
  Fixture f;
  ASSERT_TRUE(f.character->play(0, "beat"));
  f.scene.update(Scene::kMaxUpdateSeconds);
  EXPECT_EQ(f.recorder.heard.size(), 3u * AnimationEventTrack::kMaxPassesPerFrame);
  EXPECT_EQ(f.recorder.warnings, 1);
  for (std::size_t i = 1; i < f.recorder.heard.size(); ++i)
    EXPECT_GT(f.recorder.heard[i].sceneTime, f.recorder.heard[i - 1].sceneTime);
  f.recorder.heard.clear();
  f.scene.update(0.3);  // the next frame goes on from where the playhead is
  EXPECT_EQ(f.recorder.names(), "a");
}

TEST(CharacterEvents, FootContactsOfTheProfilesFeet) {
  SyntheticWalk walk = makeSyntheticWalk();
  Asset asset;
  asset.skeleton = walk.skeleton;
  asset.clips = {walk.clip};
  auto rig = std::make_shared<Rig>(asset);
  CharacterProfile profile = rig->profile();
  profile.leftLeg = {"", "", "LeftFoot"};
  profile.rightLeg = {"", "", "RightFoot"};
  profile.events["walk"] = {{0.3f, "swing"}};  // a profile's marker beside the feet
  rig->setProfile(profile);
  Fixture f(rig);
  PlayOptions options;
  options.rootMotion = true;
  ASSERT_TRUE(f.character->play(0, "walk", options));
  for (int k = 0; k < 120; ++k) f.scene.update(1.0 / 60.0);
  // Per loop: the right foot lifts at 0.1, "swing" at 0.3, the right lands at 0.5, the left
  // lifts at 0.6 and lands at 1.0 (the loop point), each within a sample of the analysis.
  struct Expected {
    const char* name;
    AnimationEventKind kind;
    FootSide side;
    double time;
  };
  const Expected expected[] = {{"right_foot_up", AnimationEventKind::FootUp, FootSide::Right, 0.1},
                               {"swing", AnimationEventKind::Marker, FootSide::None, 0.3},
                               {"right_foot_down", AnimationEventKind::FootDown, FootSide::Right, 0.5},
                               {"left_foot_up", AnimationEventKind::FootUp, FootSide::Left, 0.6},
                               {"left_foot_down", AnimationEventKind::FootDown, FootSide::Left, 1.0}};
  ASSERT_EQ(f.recorder.heard.size(), 10u) << f.recorder.names();
  for (std::size_t i = 0; i < 10; ++i) {
    const Heard& h = f.recorder.heard[i];
    const Expected& e = expected[i % 5];
    EXPECT_EQ(h.name, e.name) << i;
    EXPECT_EQ(h.kind, e.kind) << i;
    EXPECT_EQ(h.side, e.side) << i;
    EXPECT_NEAR(h.clipTime, e.time, 1.0 / 60.0 + 1e-4) << h.name;
  }
}

TEST(CharacterEvents, AListenerMayReplaceTheLayerWhileHearingIt) {
  Fixture f;
  struct Replacer : SceneListener {
    Character* character = nullptr;
    std::vector<std::string> heard;
    void onAnimationEvent(const Character&, const AnimationEvent& e) override {
      heard.emplace_back(e.name);
      if (e.name == "a") character->play(0, "tick");  // drops this frame's b and c of "beat"
    }
  } replacer;
  replacer.character = f.character;
  f.scene.addListener(&replacer);
  ASSERT_TRUE(f.character->play(0, "beat"));
  f.scene.update(0.9);
  EXPECT_EQ(replacer.heard, std::vector<std::string>{"a"});
  f.scene.update(0.2);  // tick from 0: t at 0.125
  EXPECT_EQ(replacer.heard, (std::vector<std::string>{"a", "t"}));
  f.scene.removeListener(&replacer);
}

TEST(CharacterEvents, ClipsFromOutsideTheRigSendTheirMarkers) {
  Fixture f;
  Clip own;
  own.name = "own";
  own.tracks.push_back(rotationTrack(1, {0.0f, 2.0f}, {0.0f, 1.0f}));
  own.updateDuration();
  own.events = {{1.0f, "half"}};
  ASSERT_TRUE(f.character->play(0, makeAnimationClip(own, f.character->skeleton())));
  f.scene.update(1.5);
  EXPECT_EQ(f.recorder.names(), "half");
  EXPECT_EQ(f.recorder.heard[0].clip, "own");
}
