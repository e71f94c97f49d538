// Scene files with retargeted clips (scene_file.hpp "clips": "retarget", "range",
// "loop"), the retargeted CMU walk on BCN_Epileptic, and the AR demo scene
// (assets/scenes/ar_demo_walk.json) run headless. Data from Debian's
// assimp-testmodels (BVH/01_03.bvh, X/BCN_Epileptic.X): needs Assimp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "marionette/animation/cycle.hpp"
#include "marionette/behavior/locomotion.hpp"
#include "marionette/scene/character.hpp"
#include "marionette/scene/listener.hpp"
#include "marionette/rig/rig.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "test_data.hpp"
#ifdef MARIONETTE_HAS_BML
#include "marionette/bml/realizer.hpp"
#ifdef MARIONETTE_HAS_TTS
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif
#endif

namespace marionette {
namespace {

using test::assimpModel;
using test::sourceFile;

const std::string kBcn = "/usr/share/assimp/models/X/BCN_Epileptic.X";
const std::string kWalk = "/usr/share/assimp/models/BVH/01_03.bvh";

// A scene with BCN and one clip entry (`clip`: the entry's JSON object body after "file").
std::string sceneWithClip(const std::string& clipFields, const std::string& profile = "") {
  return "{\n  \"characters\": [\n    { \"name\": \"bcn\", \"asset\": \"" + assimpModel("X/BCN_Epileptic.X") + "\"," +
         (profile.empty() ? "" : " \"profile\": \"" + profile + "\",") + "\n      \"clips\": [\n        { \"file\": \"" +
         assimpModel("BVH/01_03.bvh") + "\", " + clipFields + " } ] } ] }\n";
}

SceneLoadResult load(const std::string& text, Scene& scene) {
  return loadSceneText(text, "clips.json", sourceFile("assets/scenes"), scene);
}

// The error or warning text, with "clips.json:LINE:COL" checked.
void expectProblem(const std::string& clipFields, const std::string& expected, int line, bool error = true) {
  Scene scene;
  const SceneLoadResult r = load(sceneWithClip(clipFields), scene);
  const std::string all = r.diagnostics.format();
  EXPECT_EQ(r.ok(), !error) << all;
  bool found = false;
  for (const Diagnostic& d : r.diagnostics.items) {
    if (d.message.find(expected) == std::string::npos) continue;
    found = true;
    EXPECT_EQ(d.file, "clips.json") << all;
    EXPECT_EQ(d.line, line) << all;
    EXPECT_GT(d.column, 0) << all;
    EXPECT_EQ(d.severity == Severity::Error, error) << all;
  }
  EXPECT_TRUE(found) << "expected '" << expected << "' in:\n" << all;
  if (error) {
    EXPECT_EQ(scene.characters().size(), 0u);
  }
}

class SceneClipsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
    MARIONETTE_REQUIRE_FILE(assimpModel("BVH/01_03.bvh"));
  }
};

TEST_F(SceneClipsTest, RetargetedRangeWithMapsLoadsWithoutDiagnostics) {
  Scene scene;
  const SceneLoadResult r = load(sceneWithClip(
      "\"name\": \"w\", \"retarget\": {\"sourceMap\": \"../jointmaps/cmu_mb.json\", \"targetMap\": "
      "\"../jointmaps/BCN_Epileptic.json\"}, \"range\": [0.5, 2.0]"), scene);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  ASSERT_EQ(r.clips.size(), 1u);
  EXPECT_EQ(r.clips[0].name, "w");
  EXPECT_NEAR(r.clips[0].duration, 1.5f, 0.01f);
  EXPECT_LT(r.clips[0].loopResidual, 0.0f);  // no loop asked
  ASSERT_EQ(scene.characters().size(), 1u);
  const auto clip = scene.characters()[0]->rig().findClip("w");
  ASSERT_TRUE(clip);
  EXPECT_NEAR(clip->clip.duration, 1.5f, 0.01f);
}

TEST_F(SceneClipsTest, RetargetTrueGuessesTheMaps) {
  Scene scene;
  const SceneLoadResult r = load(sceneWithClip("\"name\": \"w\", \"retarget\": true, \"range\": [0, 1]"), scene);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  EXPECT_TRUE(scene.characters().size() == 1 && scene.characters()[0]->rig().findClip("w"));
}

TEST_F(SceneClipsTest, BadClipFieldsNameTheFileAndPlace) {
  // Line 5 holds the clip entry (see sceneWithClip).
  expectProblem("\"retarget\": true, \"range\": [0, 900]", "ends after the clip", 5);
  expectProblem("\"retarget\": true, \"range\": [2, 1]", "the end must come after the start", 5);
  expectProblem("\"retarget\": true, \"range\": [0, NaN]", "syntax error", 5);  // JSON has no NaN
  expectProblem("\"retarget\": true, \"range\": [-1, 1]", "expected a finite number", 5);
  expectProblem("\"retarget\": true, \"range\": [1]", "expected [start, end]", 5);
  expectProblem("\"retarget\": {\"sourceMap\": \"no_such_map.json\"}", "could not use the joint map 'no_such_map.json'", 5);
  expectProblem("\"retarget\": \"yes\"", "expected true, false or", 5);
  expectProblem("\"retarget\": true, \"loop\": \"worst\"", "expected \"best\"", 5);
  expectProblem("\"retarget\": true, \"range\": [0, 0.5], \"loop\": \"best\"", "needs a range of at least", 5);
  expectProblem("\"retarget\": true, \"range\": [0, 1], \"speed\": 2", "unknown key 'speed'", 5, false);
}

TEST_F(SceneClipsTest, AssetCacheKeysIncludeTheNewFields) {
  Scene scene;
  const std::string entry = "\"name\": \"w\", \"retarget\": true, \"range\": [0, 1]";
  const std::string text =
      "{ \"characters\": [ { \"name\": \"a\", \"asset\": \"" + kBcn + "\", \"clips\": [ { \"file\": \"" + kWalk + "\", " +
      entry + " } ] }, { \"name\": \"b\", \"asset\": \"" + kBcn + "\", \"clips\": [ { \"file\": \"" + kWalk + "\", " +
      entry + " } ] }, { \"name\": \"c\", \"asset\": \"" + kBcn + "\", \"clips\": [ { \"file\": \"" + kWalk +
      "\", \"name\": \"w\", \"retarget\": true, \"range\": [0, 1.5] } ] } ] }";
  const SceneLoadResult r = load(text, scene);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  ASSERT_EQ(scene.characters().size(), 3u);
  EXPECT_EQ(&scene.characters()[0]->rig(), &scene.characters()[1]->rig());  // same entry: shared
  EXPECT_NE(&scene.characters()[0]->rig(), &scene.characters()[2]->rig());  // another range: its own
  EXPECT_NEAR(scene.characters()[2]->rig().findClip("w")->clip.duration, 1.5f, 0.01f);
}

// The demo's walk: retargeted from CMU 01_03's first seconds, best loop, on BCN.
TEST_F(SceneClipsTest, RetargetedWalkLoopsAndWalksAtAHumanSpeedOnBcn) {
  Scene scene;
  const SceneLoadResult r = loadSceneFile(sourceFile("assets/scenes/ar_demo_walk.json"), scene);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  EXPECT_TRUE(r.diagnostics.items.empty()) << r.diagnostics.format();
  ASSERT_EQ(r.clips.size(), 1u);
  const SceneClipInfo& info = r.clips[0];
  // One or two gait cycles within the range, whose end pose matches its start.
  EXPECT_GE(info.end - info.start, 0.8f);
  EXPECT_LE(info.end - info.start, 2.6f);
  EXPECT_GE(info.loopResidual, 0.0f);
  EXPECT_LT(glm::degrees(info.loopResidual), 6.0f) << "RMS joint rotation difference end to start";
  EXPECT_LT(glm::degrees(info.loopWorstJoint), 15.0f);
  ASSERT_EQ(scene.characters().size(), 1u);
  const Rig& rig = scene.characters()[0]->rig();
  EXPECT_EQ(rig.profile().walk, "walk_cmu_01_03");  // the profile names the scene's clip
  const auto clip = rig.findClip("walk_cmu_01_03");
  ASSERT_TRUE(clip);
  // After closeLoop the last key matches the first for every joint.
  for (const JointTrack& t : clip->clip.tracks) {
    if (t.rotation.keyCount() < 2 || t.joint == rig.joints().hips) continue;
    const float d = std::fabs(glm::dot(t.rotation.values.front(), t.rotation.values.back()));
    EXPECT_GT(d, std::cos(glm::radians(0.5f) / 2.0f)) << rig.skeleton().names[static_cast<std::size_t>(t.joint)];
  }
  const LocomotionSet set = makeLocomotionSet(rig);
  std::string notes;
  for (const auto& n : set.notes) notes += n + "\n";
  ASSERT_TRUE(set.usable()) << notes;
  EXPECT_TRUE(set.walk.hasRootMotion) << notes;
  std::printf("%s", notes.c_str());  // the figures docs/retargeting.md quotes
  EXPECT_GE(set.walk.groundSpeed, 0.6f) << notes;
  EXPECT_LE(set.walk.groundSpeed, 1.5f) << notes;
  // Its feet come down to the rest ground (not floating, not sinking), each foot once a cycle.
  const std::vector<glm::mat4> rest = rig.skeleton().restModelMatrices();
  for (int f = 0; f < 2; ++f) {
    const int joint = f == 0 ? rig.joints().leftLeg.end : rig.joints().rightLeg.end;
    ASSERT_GE(joint, 0);
    EXPECT_NEAR(set.walk.floor[f], rest[static_cast<std::size_t>(joint)][3].y, 0.05f) << "foot " << f;
  }
}

TEST_F(SceneClipsTest, LoadingIsDeterministic) {
  Scene a, b;
  const SceneLoadResult ra = loadSceneFile(sourceFile("assets/scenes/ar_demo_walk.json"), a);
  const SceneLoadResult rb = loadSceneFile(sourceFile("assets/scenes/ar_demo_walk.json"), b);
  ASSERT_TRUE(ra.ok() && rb.ok()) << ra.diagnostics.format();
  EXPECT_EQ(ra.notes, rb.notes);
  const Clip& ca = a.characters()[0]->rig().findClip("walk_cmu_01_03")->clip;
  const Clip& cb = b.characters()[0]->rig().findClip("walk_cmu_01_03")->clip;
  ASSERT_EQ(ca.tracks.size(), cb.tracks.size());
  for (std::size_t t = 0; t < ca.tracks.size(); ++t) {
    ASSERT_EQ(ca.tracks[t].rotation.values.size(), cb.tracks[t].rotation.values.size());
    for (std::size_t k = 0; k < ca.tracks[t].rotation.values.size(); ++k)
      ASSERT_EQ(ca.tracks[t].rotation.values[k], cb.tracks[t].rotation.values[k]) << "track " << t << " key " << k;
    ASSERT_EQ(ca.tracks[t].translation.values, cb.tracks[t].translation.values) << "track " << t;
  }
}

TEST_F(SceneClipsTest, LoopSearchFindsAShiftedCopyOfItsStart) {
  // On the retargeted clip: the best loop's residual is far below a cut at arbitrary times.
  Scene scene;
  const SceneLoadResult r = load(sceneWithClip("\"name\": \"w\", \"retarget\": true, \"range\": [0, 3]"), scene);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  const Rig& rig = scene.characters()[0]->rig();
  const Clip& clip = rig.findClip("w")->clip;
  const LoopMatch best = findBestLoop(clip, rig.skeleton(), 0.0f, 3.0f);
  ASSERT_TRUE(best.found);
  LoopSearchOptions one;
  one.minDuration = 0.999f;
  one.maxDuration = 1.001f;
  const LoopMatch arbitrary = findBestLoop(clip, rig.skeleton(), 0.5f, 1.505f, one);  // 0.5 to 1.5 s
  ASSERT_TRUE(arbitrary.found);
  EXPECT_LT(best.residual, 0.5f * arbitrary.residual)
      << glm::degrees(best.residual) << " against " << glm::degrees(arbitrary.residual) << " deg";
}

#ifdef MARIONETTE_HAS_BML
struct DemoListener : SceneListener {
  int warnings = 0, speeches = 0, visemes = 0;
  std::string log;
  void onLog(LogLevel level, std::string_view message) override {
    if (level != LogLevel::Info) ++warnings, log += std::string(message) + "\n";
  }
  void onSpeech(const Character&, std::string_view, const speech::Utterance&, std::string_view, double) override {
    ++speeches;
  }
  void onViseme(const Character&, std::string_view, float, double) override { ++visemes; }
};

glm::vec3 worldPosition(const Character& c, int joint) {
  const TransformBuffer& b = c.transformBuffer();
  return glm::vec3(b.worldMatrix() * b.modelMatrices()[static_cast<std::size_t>(joint)][3]);
}
glm::quat worldRotation(const Character& c, int joint) {
  const TransformBuffer& b = c.transformBuffer();
  return decompose(b.worldMatrix() * b.modelMatrices()[static_cast<std::size_t>(joint)]).rotation;
}

// The whole demo as `marionette run assets/scenes/ar_demo_walk.json --frames 600 --fps 60` runs it.
TEST_F(SceneClipsTest, ArDemoSceneWalksLooksNodsAndSpeaks) {
  Scene scene;
#ifdef MARIONETTE_HAS_TTS
  speech::useEspeak(scene.speech());  // as the marionette program does
#endif
  DemoListener listener;
  scene.addListener(&listener);
  const SceneLoadResult loaded = loadSceneFile(sourceFile("assets/scenes/ar_demo_walk.json"), scene);
  ASSERT_TRUE(loaded.ok()) << loaded.diagnostics.format();
  EXPECT_TRUE(loaded.diagnostics.items.empty()) << loaded.diagnostics.format();
  ASSERT_EQ(loaded.bml.size(), 1u);
  bml::Realizer realizer(scene);
  realizer.setSpeechSynthesis(bml::Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
  std::map<std::string, double> sync;  // "behavior:sync" -> scene time
  bool blockEnded = false;
  realizer.addFeedbackListener([&](const bml::Feedback& f) {
    if (f.kind == bml::Feedback::Kind::SyncPointProgress) sync[f.behaviorId + ":" + f.syncPoint] = f.sceneTime;
    if (f.kind == bml::Feedback::Kind::BlockProgress && f.syncPoint == "end") blockEnded = true;
  });
  const Character& c = *scene.characters()[0];
  const Skeleton& s = c.skeleton();
  const int head = s.findJoint("B_Neck"), jaw = s.findJoint("B_Jaw");
  const int feet[4] = {s.findJoint("B_Ankle_Left"), s.findJoint("B_Ankle_Right"), s.findJoint("B_Toe_Left"),
                       s.findJoint("B_Toe_Right")};
  ASSERT_TRUE(head >= 0 && jaw >= 0 && feet[0] >= 0 && feet[1] >= 0 && feet[2] >= 0 && feet[3] >= 0);
  const double dt = 1.0 / 60.0;
  bool sent = false;
  std::vector<double> times;
  std::vector<std::array<glm::vec3, 4>> footAt;
  std::vector<glm::quat> headAt, jawAt;
  for (int f = 0; f < 600; ++f) {
    const double now = scene.time() + (f == 0 ? 0.0 : dt);
    if (!sent && loaded.bml[0].time <= now + 1e-9) {
      const bml::Schedule sch = realizer.perform(test::readFile(loaded.bml[0].path), loaded.bml[0].character, {}, loaded.bml[0].time);
      EXPECT_TRUE(sch.warnings.empty()) << sch.warnings.front().message;
      sent = true;
    }
    scene.update(f == 0 ? 0.0 : dt);
    realizer.update();
    times.push_back(scene.time());
    footAt.push_back({worldPosition(c, feet[0]), worldPosition(c, feet[1]), worldPosition(c, feet[2]), worldPosition(c, feet[3])});
    headAt.push_back(worldRotation(c, head));
    jawAt.push_back(worldRotation(c, jaw) * glm::inverse(headAt.back()));
  }
  EXPECT_EQ(listener.warnings, 0) << listener.log;
  // The walk arrives at "0 1" (within 0.1 m), and its end fires.
  ASSERT_TRUE(sync.count("walk:end")) << "no end feedback for the locomotion";
  EXPECT_LT(glm::length(glm::vec2(c.position().x, c.position().z) - glm::vec2(0.0f, 1.0f)), 0.1f);
  EXPECT_TRUE(blockEnded) << "the block's end feedback never fired in 10 s";
  const double arrived = sync["walk:end"];
  EXPECT_GT(arrived, 2.0);
  EXPECT_LT(arrived, 6.0);
  // Feet: no ground penetration beyond 3 cm; while a foot is down (within 5 cm of its
  // lowest) and the character walks, it slides less than 0.5 m/s in 90 % of those frames.
  int contact = 0, skating = 0;
  for (int k = 0; k < 4; ++k) {
    float lowest = INFINITY;
    for (const auto& p : footAt) lowest = std::min(lowest, p[static_cast<std::size_t>(k)].y);
    EXPECT_GT(lowest, -0.03f) << "foot joint " << k << " goes into the ground";
    if (k >= 2) continue;  // ankles count for skating
    for (std::size_t i = 1; i < footAt.size(); ++i) {
      const glm::vec3 a = footAt[i - 1][static_cast<std::size_t>(k)], b = footAt[i][static_cast<std::size_t>(k)];
      if (b.y > lowest + 0.05f || times[i] > arrived + 0.5) continue;
      ++contact;
      if (glm::length(glm::vec2(b.x - a.x, b.z - a.z)) / dt > 0.5) ++skating;
    }
  }
  ASSERT_GT(contact, 100);
  EXPECT_LT(static_cast<double>(skating) / contact, 0.10) << skating << " of " << contact << " contact frames skate";
  // Gaze: the head's forward (+Z at rest, the character's facing) points at the camera
  // (0, 1.5, 4.5) within 5 degrees from the nod's end until the gaze relaxes, though the
  // body stopped facing 20 degrees away.
  ASSERT_TRUE(sync.count("say:end") && sync.count("nod:end") && sync.count("say:start") && sync.count("look:relax"));
  const glm::vec3 camera(0.0f, 1.5f, 4.5f);
  const float bodyHeading = c.heading();
  EXPECT_NEAR(glm::degrees(bodyHeading), -20.0f, 1.0f);
  const glm::quat headRest = headAt.back();  // the gaze is over: the head faces the body's way
  const glm::vec3 headPlace = worldPosition(c, head);
  double worstGaze = 0.0, worstAt = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (times[i] < sync["nod:end"] || times[i] > std::min(sync["say:end"], sync["look:relax"])) continue;
    const glm::vec3 forward = headAt[i] * glm::inverse(headRest) * glm::vec3(std::sin(bodyHeading), 0, std::cos(bodyHeading));
    const glm::vec3 to = glm::normalize(camera - headPlace);
    const double off = glm::degrees(std::acos(std::clamp(glm::dot(forward, to), -1.0f, 1.0f)));
    if (off > worstGaze) worstGaze = off, worstAt = times[i];
  }
  EXPECT_LT(worstGaze, 5.0) << "head off the camera by up to " << worstGaze << " deg at " << worstAt << " s (nod end "
                           << sync["nod:end"] << ", speech " << sync["say:start"] << " to " << sync["say:end"] << ")";
  // The nod: the head pitches down and back up twice, by more than 10 degrees.
  int dips = 0;
  bool down = false;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (times[i] < sync["nod:start"] || times[i] > sync["nod:end"]) continue;
    const glm::vec3 forward = headAt[i] * glm::inverse(headRest) * glm::vec3(std::sin(bodyHeading), 0, std::cos(bodyHeading));
    const float pitch = glm::degrees(std::asin(std::clamp(forward.y, -1.0f, 1.0f)));
    if (!down && pitch < -12.0f) down = true, ++dips;
    if (down && pitch > -6.0f) down = false;
  }
  EXPECT_EQ(dips, 2);
  // Speech: realized (audio, visemes), and the jaw joint moves with it (BCN has no mouth morphs).
  EXPECT_EQ(listener.speeches, 1);
  EXPECT_GT(listener.visemes, 5);
  EXPECT_GT(sync["say:end"] - sync["say:start"], 0.8);
  float jawMotion = 0.0f;
  for (std::size_t i = 0; i < times.size(); ++i)
    if (times[i] > sync["say:start"] && times[i] < sync["say:end"])
      jawMotion = std::max(jawMotion, glm::degrees(2.0f * std::acos(std::min(1.0f, std::fabs(glm::dot(jawAt[i], jawAt.back()))))));
  EXPECT_GT(jawMotion, 3.0f) << "the jaw does not open while speaking";
}
#endif

}  // namespace
}  // namespace marionette
