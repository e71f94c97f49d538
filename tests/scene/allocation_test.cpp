// Counts heap allocations made by Scene::update after warm-up: there must be none.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "marionette/scene/scene.hpp"
#include "marionette/retarget/retargeter.hpp"
#ifdef MARIONETTE_TEST_HAS_BRIDGE
#include "marionette/bridge/morph_binding.hpp"
#include "marionette/bridge/palette_binding.hpp"
#endif
#ifdef MARIONETTE_TEST_HAS_PRT
#include <glm/gtc/matrix_transform.hpp>

#include "marionette/prt/relight.hpp"
#include "marionette/prt/sh_rotation.hpp"
#endif
#include "synthetic_humanoid.hpp"
#include "synthetic_rig.hpp"
#include "synthetic_upper_body.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

// GCC cannot see that these replace the global pair together.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
// The nothrow forms too (std::stable_sort's temporary buffer uses them): all of them must pair
// with the free() below, or ASan reports an alloc-dealloc mismatch.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace marionette;

TEST(Allocation, NoHeapAllocationPerFrameAfterWarmUp) {
  auto rig = marionette::test::makeSyntheticRig();
  Scene scene;
  struct Quiet : SceneListener {
    int events = 0, visemes = 0;
    void onLog(LogLevel level, std::string_view) override { events += level != LogLevel::Info; }
    void onViseme(const Character&, std::string_view, float, double) override { ++visemes; }
  } listener;
  scene.addListener(&listener);
  // Speech: a line of three phonemes (a bilabial among them) from an in-test backend.
  struct Line : speech::SpeechBackend {
    std::string_view name() const noexcept override { return "line"; }
    speech::SpeechResult synthesize(const speech::SpeechRequest&) override {
      auto u = std::make_shared<speech::Utterance>();
      const char* names[] = {"m", "aa", "p"};
      for (int k = 0; k < 3; ++k) {
        speech::Phoneme ph;
        ph.start = 0.2 * k, ph.end = 0.2 * (k + 1), ph.name = names[k];
        ph.cls = speech::classifyPhoneme(names[k], speech::PhonemeAlphabet::Arpabet).cls;
        u->phonemes.push_back(ph);
      }
      u->duration = 0.7;
      return {u, {}};
    }
  };
  scene.speech().addBackend(std::make_shared<Line>());
  for (int i = 0; i < 20; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    PlayOptions walk;
    walk.rootMotion = true;
    c->play(0, "walk", walk);
    PlayOptions wave;
    wave.weight = 0.5f;
    wave.additive = i % 2 == 0;
    wave.jointMask = {0, 0, 1, 1};
    c->play(1, "wave", wave);
    c->transformBuffer().setPacked3x4(i % 3 == 0);
    // Behavior requests: one that ends (and is pruned) and one cancelled mid-run.
    BehaviorRequest g;
    g.id = "g";
    g.kind = BehaviorKind::Gesture;
    g.clip = "wave";
    g.syncs = {{"start", 0.0}, {"ready", 0.2}, {"relax", 1.0}, {"end", 2.0}};
    c->addBehavior(g);
    g.id = "long";
    g.clip = "walk";
    g.loop = true;
    g.syncs = {{"start", 0.5}, {"end", 1000.0}};
    c->addBehavior(g);
    BehaviorRequest say;
    say.id = "say";
    say.kind = BehaviorKind::Speech;
    say.parameters = SpeechParameters{.text = "map"};
    say.syncs = {{"start", 0.1}, {"end", 0.8}};
    EXPECT_TRUE(c->addBehavior(say).realized);
  }
  scene.setStatsEnabled(true);
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 500; ++f) {
    scene.update(f % 7 == 0 ? 0.5 : 1.0 / 60.0);
    if (f == 250)
      for (const auto& c : scene.characters()) c->cancelBehavior("long", 0.3);
  }
  for (const auto& c : scene.characters()) EXPECT_TRUE(c->behaviors().empty());
  scene.update(-1.0);  // a rejected dt warns without allocating
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(listener.events, 1);
  EXPECT_EQ(listener.visemes, 20 * 3);  // each phoneme's viseme once per character
  // The counter works: a vector allocates.
  std::vector<int> v(10);
  EXPECT_GT(g_allocations.load() - before, 0);
}

// Procedural gestures (repeated strokes, both hands), a gaze and a reach at a scene object that
// moves every frame (issue 24): bound at command time, nothing allocated per frame.
TEST(Allocation, ProceduralGesturesAndObjectTargetsAllocateNothingPerFrame) {
  Scene scene;
  ASSERT_TRUE(scene.setObject("camera", {0.0f, 1.6f, 3.0f}));
  for (int i = 0; i < 4; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), marionette::test::makeUpperBodyRig());
    BehaviorRequest g;
    g.id = "g";
    g.kind = BehaviorKind::Gesture;
    g.parameters = GestureParameters{i % 2 ? "SHRUG" : "BEAT", PointingArms::Nearest, {}};
    g.syncs = {{"start", 0.0},         {"ready", 0.2},   {"strokeStart", 0.3}, {"stroke", 0.4},
               {"strokeEnd", 0.5},     {"strokeStart:2", 0.7}, {"stroke:2", 0.8}, {"strokeEnd:2", 0.9},
               {"relax", 1.2},         {"end", 1.5}};
    ASSERT_TRUE(c->addBehavior(g).realized);
    BehaviorRequest look;
    look.id = "look";
    look.kind = BehaviorKind::Gaze;
    look.parameters = GazeParameters{BehaviorTarget::of("camera"), GazeInfluence::Neck};
    look.syncs = {{"start", 0.0}, {"ready", 0.3}, {"relax", 1.5}, {"end", 2.0}};
    ASSERT_TRUE(c->addBehavior(look).realized);
    BehaviorRequest reach;  // for the same moving object, out of reach (issue 45, 7)
    reach.id = "reach";
    reach.kind = BehaviorKind::Reach;
    reach.parameters = ReachParameters{BehaviorTarget::of("camera")};
    reach.syncs = {{"start", 0.0}, {"ready", 0.4}, {"relax", 1.4}, {"end", 1.9}};
    ASSERT_TRUE(c->addBehavior(reach).realized);
  }
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 120; ++f) {
    scene.setObject("camera", {0.01f * static_cast<float>(f), 1.6f, 3.0f});  // an existing name: moved
    scene.update(1.0 / 60.0);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  for (const auto& c : scene.characters())
    EXPECT_TRUE(c->stats().used(Controller::Gaze) && c->stats().used(Controller::Gesture) && c->stats().used(Controller::Reach));
}

// Idle life: blinks (on morphs) and breathing on four characters, over blinks, breaths and a
// replacement of each emitter's request made before the counted frames.
TEST(Allocation, IdleLifeAllocatesNothingPerFrame) {
  Scene scene;
  for (int i = 0; i < 4; ++i) {
    auto asset = marionette::test::makeUpperBodyAsset();
    asset->morphTargets = {"blink_left", "blink_right"};
    auto rig = std::make_shared<Rig>(*asset);
    CharacterProfile p = marionette::test::upperBodyProfile();
    p.face["CLOSE_EYES"] = {{"blink_left", 1.0f}, {"blink_right", 1.0f}};
    p.idleLife.blink = p.idleLife.breathing = true;
    rig->setProfile(p);
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    BehaviorRequest faster{.id = "breath", .kind = BehaviorKind::BreathingEmitter, .syncs = {{"start", 0.5}, {"end", 0.5}},
                           .parameters = BreathingParameters{.breathsPerMinute = 40.0f, .periodRangeSeconds = 0.3f}};
    faster.persistent = true;
    ASSERT_TRUE(c->addBehavior(faster).realized);
    BehaviorRequest blink{.id = "blink", .kind = BehaviorKind::BlinkEmitter, .syncs = {{"start", 0.5}, {"end", 0.5}},
                          .parameters = BlinkParameters{.meanIntervalSeconds = 0.5f}};
    blink.persistent = true;
    ASSERT_TRUE(c->addBehavior(blink).realized);
  }
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 600; ++f) scene.update(1.0 / 60.0);
  EXPECT_EQ(g_allocations.load() - before, 0);
  for (const auto& c : scene.characters())
    EXPECT_TRUE(c->stats().used(Controller::Blink) && c->stats().used(Controller::Breathing));
}

// The same with two threads: waking the workers, the shared chunk index, the
// per-thread scratch and the serialized listener calls allocate nothing either.
TEST(Allocation, NoHeapAllocationPerFrameWithTwoThreads) {
  auto rig = marionette::test::makeSyntheticRig();
  Scene scene;
  struct Counting : SceneListener {
    int stopped = 0;
    void onCharacterChanged(const Character&, ChangeKind kind, std::string_view) override {
      stopped += kind == ChangeKind::ClipStopped;
    }
  } listener;
  scene.addListener(&listener);
  for (int i = 0; i < 64; ++i) {  // four chunks of 16: the frame is really split
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->play(0, "walk", {.rootMotion = true});
    c->play(1, "wave", {.weight = 0.5f, .additive = i % 2 == 0, .jointMask = {0, 0, 1, 1}});
    BehaviorRequest g;
    g.id = "g";
    g.kind = BehaviorKind::Gesture;
    g.clip = "wave";
    g.syncs = {{"start", 0.0}, {"ready", 0.2}, {"relax", 1.0}, {"end", 2.0}};
    c->addBehavior(g);
  }
  scene.setThreadCount(2);
  scene.setStatsEnabled(true);
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 300; ++f) {
    if (f == 100)
      for (const auto& c : scene.characters()) c->stop(1, 0.2f);  // ClipStopped from inside update()
    scene.update(f % 7 == 0 ? 0.5 : 1.0 / 60.0);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(listener.stopped, 64);
  EXPECT_EQ(scene.threadCount(), 2);
}

TEST(Allocation, RetargeterApplyAllocatesNothing) {
  // Online retargeting with feet and hands IK, mirrored joints and a different
  // spine: bound once, then applied per frame with its own or a caller's scratch.
  const auto src = marionette::test::makeHumanoid({.spineJoints = 3});
  const auto dst = marionette::test::makeHumanoid({.spineJoints = 5, .armDownDegrees = 45.0f, .rollSeed = 3,
                                                   .mirrorLeftArm = true});
  marionette::retarget::RetargetOptions o;
  o.ik.feet = o.ik.hands = true;
  const auto r = marionette::retarget::Retargeter::bind(src.skeleton, src.map, dst.skeleton, dst.map, o);
  ASSERT_TRUE(r.valid());
  auto scratch = r.makeScratch();
  std::vector<Transform> pose = src.skeleton.restPose, out(dst.skeleton.jointCount());
  const long before = g_allocations.load();
  for (int f = 0; f < 200; ++f) {
    pose[0].translation.z = 0.01f * static_cast<float>(f);
    pose[3].rotation = glm::angleAxis(0.01f * static_cast<float>(f), glm::vec3(1, 0, 0));
    r.apply(pose, out, scratch, 1.0f / 60.0f);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

#ifdef MARIONETTE_TEST_HAS_BRIDGE
// The bridge's per-frame copies into an engine's palette and morph slots, in every
// layout, with unmatched bones (identity) and slots between bound runs.
TEST(Allocation, BridgeCopiesAllocateNothing) {
  const auto h = marionette::test::makeHumanoid({.spineJoints = 3, .rollSeed = 2});
  auto asset = std::make_shared<Asset>();
  asset->skeleton = h.skeleton;
  asset->morphTargets = {"smile", "blink"};
  Scene scene;
  Character* c = scene.addCharacter("h", std::make_shared<Rig>(*asset));
  std::vector<std::string> bones(h.skeleton.names.rbegin(), h.skeleton.names.rend());
  bones.insert(bones.begin() + 5, "engine_only");
  const bridge::PaletteBinding palette(c->skeleton(), bones);
  const std::vector<std::string> slots = {"blink", "jaw", "smile"};
  const bridge::MorphBinding morphs(asset->morphTargets, slots);
  std::vector<float> out(palette.floatCount(bridge::PaletteLayout::Mat4RowMajor)), weights(slots.size());
  scene.update(1.0 / 60.0);
  const long before = g_allocations.load();
  int copied = 0;
  for (int f = 0; f < 100; ++f) {
    scene.update(1.0 / 60.0);
    for (auto layout : {bridge::PaletteLayout::Mat4ColumnMajor, bridge::PaletteLayout::Mat4RowMajor,
                        bridge::PaletteLayout::Mat3x4RowMajor})
      copied += palette.copy(c->transformBuffer(), out, {layout, f % 2 == 0});
    copied += morphs.copy(c->transformBuffer(), weights);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(copied, 400);
}
#endif

#ifdef MARIONETTE_TEST_HAS_PRT
// PRT per frame: the environment's light turned into a character's frame, then relit.
TEST(Allocation, PrtRotationAndRelightingAllocateNothing) {
  using namespace marionette::prt;
  VertexTransfer transfer;
  transfer.bands = kDefaultTransferBands;
  transfer.coefficients.assign(1003u * static_cast<std::size_t>(transfer.count()), 0.25f);
  transfer.occluded.assign(1003u, 0.0f);
  const TransferRelighter relighter(transfer);
  const ShRotation rotation(kDefaultTransferBands);
  ShCoefficients world, local;
  world.bands = kDefaultTransferBands;
  for (int i = 0; i < world.count(); ++i) world.c[i] = glm::dvec3(1.0 / (1 + i));
  std::vector<glm::vec3> irradiance(1003);
  const long before = g_allocations.load();
  for (int f = 0; f < 100; ++f) {
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 0.05 * f, glm::dvec3(0.2, 1.0, 0.1)));
    rotation.rotate(r, world, local);
    relighter.relight(local, irradiance);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(irradiance[500].x, 0.0f);  // it did run
}
#endif

// Animation events (markers and foot contacts) crossed on looping, backwards and clamped
// layers, in steps up to a second and one over the cap, on two threads: nothing allocated.
TEST(Allocation, AnimationEventsAllocateNothingPerFrame) {
  Asset asset;
  asset.skeleton = marionette::test::makeChain(3);
  Clip beat;
  beat.name = "beat";
  beat.tracks.push_back(marionette::test::rotationTrack(1, {0.0f, 0.5f, 1.0f}, {0.0f, 0.5f, 0.0f}));
  beat.updateDuration();
  beat.events = {{0.0f, "start"}, {0.25f, "a_rather_long_marker_name_that_a_short_string_would_not_hold"}, {1.0f, "end"}};
  asset.clips = {beat};
  auto rig = std::make_shared<const Rig>(asset);
  Scene scene;
  scene.setThreadCount(2);
  struct Counter : SceneListener {
    long events = 0;
    void onAnimationEvent(const Character&, const AnimationEvent& e) override { events += !e.name.empty(); }
  } counter;
  scene.addListener(&counter);
  for (int i = 0; i < 40; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    PlayOptions o;
    o.speed = i % 3 == 0 ? -1.5f : 1.0f;
    o.wrap = i % 5 == 4 ? WrapMode::Clamp : WrapMode::Loop;
    o.startTime = 0.1 * i;
    c->play(0, "beat", o);
    o.weight = 0.5f;
    c->play(1 + i % 7, "beat", o);
  }
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 300; ++f) scene.update(f % 11 == 0 ? 1.0 : 1.0 / 60.0);
  scene.update(Scene::kMaxUpdateSeconds);  // over the cap: a warning, still no allocation
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(counter.events, 1000);
}

TEST(Allocation, BlendSpaceLayersAllocateNothingPerFrame) {
  // 1D and 2D spaces over the synthetic walk (root motion) and wave, on 24 characters over
  // two threads: parameters moved every frame, loops and clamps, both speeds, masks.
  auto base = marionette::test::makeSyntheticRig();
  auto rig = std::make_shared<Rig>(*base);
  std::string error;
  BlendSpaceFeet feet;  // no feet: plain normalized time, sampled the same way
  auto walk = rig->findClip("walk"), wave = rig->findClip("wave");
  auto line = BlendSpace::make("line", 1, {{walk, 0.0f}, {wave, 1.0f}, {walk, 2.0f}}, rig->skeleton(), feet, true, error);
  auto plane = BlendSpace::make("plane", 2, {{walk, 0, 0}, {wave, 1, 0}, {walk, 0, 1}, {wave, 1, 1}, {walk, 0.5f, 0.4f}},
                                rig->skeleton(), feet, true, error);
  ASSERT_TRUE(line && plane) << error;
  rig->addBlendSpace(line);
  rig->addBlendSpace(plane);
  Scene scene;
  scene.setThreadCount(2);
  std::vector<Character*> characters;
  for (int i = 0; i < 24; ++i) {
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    PlayOptions o;
    o.speed = i % 3 == 0 ? -1.5f : 1.0f;
    o.wrap = i % 5 == 4 ? WrapMode::Clamp : WrapMode::Loop;
    o.rootMotion = i % 2 == 0;
    o.fadeIn = 0.2f;
    if (i % 4 == 1) o.jointMask = {1.0f, 1.0f, 0.5f, 0.0f};
    ASSERT_TRUE(c->playBlend(i % 2, i % 2 ? "plane" : "line", o, 0.3f, 0.2f));
    if (i % 3 == 2) c->play(2, "wave", {});
    characters.push_back(c);
  }
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 300; ++f) {
    for (std::size_t i = 0; i < characters.size(); ++i)
      characters[i]->setBlendParameter(static_cast<int>(i % 2), -0.5f + 0.01f * static_cast<float>(f), std::sin(0.1f * static_cast<float>(f)));
    scene.update(f % 11 == 0 ? 0.5 : 1.0 / 60.0);
  }
  characters[0]->stop(0, 0.5f);  // a fade-out to the end
  for (int f = 0; f < 60; ++f) scene.update(1.0 / 60.0);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(characters[0]->layerBlendSpace(0), nullptr);
}

// Scene::setParallelFor: the hooked frame (context on the stack, scratch per chunk made at
// command time) allocates nothing either; the hook here runs the chunks in reverse.
TEST(Allocation, NoHeapAllocationPerFrameThroughTheParallelForHook) {
  auto rig = marionette::test::makeSyntheticRig();
  Scene scene;
  scene.setParallelFor(
      [](void*, Scene::ParallelTask task, void* context, int chunks) {
        for (int i = chunks - 1; i >= 0; --i) task(context, i);
      },
      nullptr);
  for (int i = 0; i < 50; ++i) {  // four chunks, the last of two
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->play(0, "walk", {.rootMotion = true});
    c->play(1, "wave", {.weight = 0.5f, .additive = i % 2 == 0});
  }
  scene.update(1.0 / 60.0);  // warm-up
  const long before = g_allocations.load();
  for (int f = 0; f < 300; ++f) {
    if (f == 100)
      for (const auto& c : scene.characters()) c->stop(1, 0.2f);  // ClipStopped from inside update()
    scene.update(f % 7 == 0 ? 0.5 : 1.0 / 60.0);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}
