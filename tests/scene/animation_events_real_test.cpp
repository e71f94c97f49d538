// Animation events on real data: RobotExpressive's Walking sends each foot's touchdown and
// lift-off at the clip's contact frames (±1 frame, against the contact analysis at its
// full rate); markers written into a glTF's animation extras (and a profile's "events")
// come back through the importer and are crossed once per loop, also in one-second steps;
// bad event data is a warning naming the file and the place. Missing data fails, never skips.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "marionette/animation/foot_contacts.hpp"
#include "marionette/behavior/two_bone_ik.hpp"
#include "marionette/io/gltf_writer.hpp"
#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;
namespace fs = std::filesystem;

namespace {

struct Heard {
  std::string name;
  AnimationEventKind kind;
  FootSide side;
  float clipTime;
  double sceneTime;
  std::string clip;
};

struct Recorder : SceneListener {
  std::vector<Heard> heard;
  void onAnimationEvent(const Character&, const AnimationEvent& e) override {
    heard.push_back({std::string(e.name), e.kind, e.side, e.clipTime, e.sceneTime, std::string(e.clip)});
  }
};

// Hip to ankle in the rest pose (through the lower joint), as foot_contacts_real_test measures it.
float legLength(const Rig& rig) {
  const Skeleton& s = rig.skeleton();
  const LimbIk leg = makeLimbIk(s, rig.joints().leftLeg);
  std::vector<glm::mat4> model = s.restModelMatrices();
  const glm::vec3 hip(model[static_cast<std::size_t>(leg.upper)][3]), knee(model[static_cast<std::size_t>(leg.lower)][3]);
  return glm::distance(hip, knee) + glm::distance(knee, limbEndModel(s, s.restPose, leg));
}

// The clip's frame: the shortest key interval of its tracks.
float frameOf(const Clip& clip) {
  float frame = INFINITY;
  for (const JointTrack& t : clip.tracks)
    for (const auto* times : {&t.translation.times, &t.rotation.times})
      for (std::size_t k = 1; k < times->size(); ++k) frame = std::min(frame, (*times)[k] - (*times)[k - 1]);
  return frame;
}

// Cyclic distance between two clip times.
double cyclicGap(double a, double b, double duration) {
  const double d = std::fmod(std::fabs(a - b), duration);
  return std::min(d, duration - d);
}

fs::path scratchDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "marionette_animation_events" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string warningsAbout(const Diagnostics& d, const std::string& needle) {
  std::string out;
  for (const Diagnostic& item : d.items)
    if (item.format().find(needle) != std::string::npos) out += item.format() + "\n";
  return out;
}

}  // namespace

TEST(AnimationEventsOnRealClips, RobotExpressiveFootstepsAtItsContactFrames) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  const auto start = std::chrono::steady_clock::now();
  auto rig = loadRigWithProfile(path, "RobotExpressive.json");
  const double loadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(rig);
  std::printf("RobotExpressive: import, rig, profile and events of %zu clips: %.1f ms\n", rig->clips().size(), loadMs);
  auto clip = rig->findClip("Walking");
  ASSERT_TRUE(clip);
  const double duration = clip->clip.duration;
  const float frame = frameOf(clip->clip);
  ASSERT_TRUE(std::isfinite(frame) && frame > 0.0f);

  // The contact analysis at its full rate, with the feet and leg length the foot IK uses.
  const FootContactOptions options = footContactOptionsForLeg(legLength(*rig));
  const int feet[2] = {rig->joints().leftLeg.end, rig->joints().rightLeg.end};
  std::vector<ContactInterval> contacts[2];
  for (int f = 0; f < 2; ++f) {
    ASSERT_GE(feet[f], 0);
    contacts[f] = detectFootContacts(*clip, rig->skeleton(), feet[f], options);
    ASSERT_EQ(contacts[f].size(), 1u) << "foot " << f;
  }

  Scene scene;
  Recorder recorder;
  scene.addListener(&recorder);
  Character* robot = scene.addCharacter("robot", rig);
  ASSERT_TRUE(robot->play(0, "Walking"));
  const int loops = 3;
  const int frames = static_cast<int>(std::ceil(duration * loops * 60.0));
  for (int k = 0; k < frames; ++k) scene.update(1.0 / 60.0);

  int counted[2][2] = {};  // [foot][down, up]
  for (const Heard& h : recorder.heard) {
    if (h.kind == AnimationEventKind::Marker) continue;
    const int f = h.side == FootSide::Left ? 0 : 1;
    const bool down = h.kind == AnimationEventKind::FootDown;
    ++counted[f][down ? 0 : 1];
    const double truth = (down ? contacts[f][0].begin : contacts[f][0].end) * duration;
    EXPECT_LE(cyclicGap(h.clipTime, truth, duration), frame) << h.name << " at " << h.clipTime << " s, contact at " << truth;
    // Sent at the scene time the playhead crossed it (speed 1 from 0: its time plus the loops before).
    const double loopsBefore = std::floor((h.sceneTime - h.clipTime) / duration + 0.5);
    EXPECT_NEAR(h.sceneTime, loopsBefore * duration + h.clipTime, 1e-6) << h.name;
    std::printf("%-16s clip %.4f s (analysis %.4f s, frame %.4f s), scene %.4f s\n", h.name.c_str(),
                static_cast<double>(h.clipTime), truth, static_cast<double>(frame), h.sceneTime);
  }
  for (int f = 0; f < 2; ++f)
    for (int e = 0; e < 2; ++e) EXPECT_EQ(counted[f][e], loops) << "foot " << f << (e ? " up" : " down");
}

TEST(AnimationEventsOnRealClips, GltfExtrasMarkersCrossedOncePerLoop) {
  const std::string source = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(source);
  ImportOptions motionOnly;
  motionOnly.loadMeshes = false;
  ImportResult robot = importAsset(source, motionOnly);
  ASSERT_TRUE(robot.ok()) << robot.diagnostics.format();
  auto walking = std::find_if(robot.asset->clips.begin(), robot.asset->clips.end(),
                              [](const Clip& c) { return c.name == "Walking"; });
  ASSERT_NE(walking, robot.asset->clips.end());
  Clip marked = *walking;
  const float d = marked.duration;
  marked.events = {{0.0f, "begin"}, {0.5f * d, "half"}, {d, "end"}};
  const fs::path dir = scratchDir("extras");
  const std::string file = (dir / "walking.gltf").string();
  const Diagnostics written = writeGltf(file, *robot.asset, std::span<const Clip>(&marked, 1));
  ASSERT_TRUE(written.ok()) << written.format();

  ImportResult back = importAsset(file, motionOnly);
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  ASSERT_EQ(back.asset->clips.size(), 1u);
  const Clip& read = back.asset->clips[0];
  ASSERT_EQ(read.events.size(), 3u);
  EXPECT_EQ(read.events[1].name, "half");
  EXPECT_FLOAT_EQ(read.events[1].time, 0.5f * d);

  auto rig = std::make_shared<Rig>(*back.asset);
  for (const double step : {1.0 / 60.0, 1.0 / 7.0, 1.0}) {
    Scene scene;
    Recorder recorder;
    scene.addListener(&recorder);
    Character* c = scene.addCharacter("robot", rig);
    ASSERT_TRUE(c->play(0, "Walking"));
    const int loops = 4;
    const double total = loops * static_cast<double>(d) - 1e-3;  // short of the next loop point
    while (scene.time() < total - 1e-9) scene.update(std::min(step, total - scene.time()));
    std::string order;
    for (const Heard& h : recorder.heard)
      if (h.kind == AnimationEventKind::Marker) order += h.name + " ";
    // The loop point ("end" and "begin" are one instant of a loop, the end first) then "half",
    // once per loop: the start of play leaves the loop point too.
    std::string expected;
    for (int k = 0; k < loops; ++k) expected += "end begin half ";
    EXPECT_EQ(order, expected) << "step " << step;
  }
}

TEST(AnimationEventsOnRealClips, BadEventDataIsNamedWhereItIs) {
  const std::string source = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(source);
  ImportOptions motionOnly;
  motionOnly.loadMeshes = false;
  ImportResult robot = importAsset(source, motionOnly);
  ASSERT_TRUE(robot.ok()) << robot.diagnostics.format();
  const fs::path dir = scratchDir("bad");
  const std::string file = (dir / "robot.gltf").string();
  ASSERT_TRUE(writeGltf(file, *robot.asset, robot.asset->clips).ok());

  // Animation 0 with bad events in extras.events; animation 1 with the list as extras itself.
  nlohmann::json doc = nlohmann::json::parse(readFile(file));
  ASSERT_GE(doc["animations"].size(), 2u);
  doc["animations"][0]["extras"] = {
      {"events",
       {{{"time", -1.0}, {"name", "before"}}, {{"time", 1e6}, {"name", "after"}}, {{"name", "no time"}},
        {{"time", 0.1}}, {{"time", 0.1}, {"name", ""}}, 7, {{"time", "0.1"}, {"name", "text time"}},
        {{"time", 0.1}, {"name", "fine"}}}}};
  doc["animations"][1]["extras"] = nlohmann::json::array({{{"time", 0.2}, {"name", "listed"}}});
  doc["animations"][2]["extras"] = {{"events", "not a list"}};
  doc["animations"][3]["extras"] = {{"author", "someone else's extras"}};
  std::ofstream(file) << doc.dump(1);

  ImportResult r = importAsset(file, motionOnly);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  const std::string first = "animations/0/extras/events/";
  for (int i : {0, 1, 2, 3, 4, 5, 6})
    EXPECT_NE(warningsAbout(r.diagnostics, first + std::to_string(i) + ")"), "") << i << "\n" << r.diagnostics.format();
  EXPECT_EQ(warningsAbout(r.diagnostics, first + "7)"), "");
  EXPECT_NE(warningsAbout(r.diagnostics, "animations/2/extras/events)"), "");
  EXPECT_EQ(warningsAbout(r.diagnostics, "animations/3/"), "");
  EXPECT_EQ(warningsAbout(r.diagnostics, "extras").find(file) == std::string::npos, false);  // the file is named
  ASSERT_EQ(r.asset->clips[0].events.size(), 1u);
  EXPECT_EQ(r.asset->clips[0].events[0].name, "fine");
  ASSERT_EQ(r.asset->clips[1].events.size(), 1u);
  EXPECT_EQ(r.asset->clips[1].events[0].name, "listed");

  // A profile's "events": a clip the asset lacks, a time past the clip, a missing name.
  const std::string profile = (dir / "robot.json").string();
  const std::string walking = "Walking";
  std::ofstream(profile) << R"({
  "events": {
    "Walking": [{"time": 0.1, "name": "scuff"}, {"time": 99, "name": "late"}, {"time": 0.2}],
    "Moonwalk": [{"time": 0.1, "name": "glide"}]
  }
})";
  CharacterProfileResult p = loadCharacterProfile(profile, *r.asset);
  EXPECT_NE(warningsAbout(p.diagnostics, "events/Walking/1/time"), "") << p.diagnostics.format();
  EXPECT_NE(warningsAbout(p.diagnostics, "events/Walking/2"), "") << p.diagnostics.format();
  EXPECT_NE(warningsAbout(p.diagnostics, "events/Moonwalk"), "") << p.diagnostics.format();
  EXPECT_NE(warningsAbout(p.diagnostics, profile + ":3:"), "") << p.diagnostics.format();  // file:line
  ASSERT_EQ(p.profile.events.count(walking), 1u);
  ASSERT_EQ(p.profile.events[walking].size(), 1u);
  EXPECT_EQ(p.profile.events[walking][0].name, "scuff");
  EXPECT_EQ(p.profile.events.count("Moonwalk"), 0u);
  // The rig sends it on the clip of that name.
  auto rig = std::make_shared<Rig>(*r.asset);
  rig->setProfile(p.profile);
  auto track = rig->events(*rig->findClip(walking));
  ASSERT_TRUE(track);
  bool scuff = false;
  for (const auto& e : track->events()) scuff = scuff || track->name(e) == "scuff";
  EXPECT_TRUE(scuff);
}

// A blend-space layer sends its heaviest clip's events: RobotExpressive's profile space
// "locomotion" (Walking at 3.56, Running at 4.31) between the two, nearer the walk, over 4
// cycles at 60 Hz: each foot lands once a cycle, left and right alternate, every event names
// the walk. Past the middle the run leads and its events come instead.
TEST(AnimationEventsOnRealClips, BlendSpaceLayerSendsItsHeaviestClipsFootsteps) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  auto rig = loadRigWithProfile(path, "RobotExpressive.json");
  ASSERT_TRUE(rig);
  const auto space = rig->findBlendSpace("locomotion");
  ASSERT_TRUE(space) << "the robot's profile names a 'locomotion' blend space";
  for (const auto& [x, lead] : {std::pair{3.7f, std::string("Walking")}, std::pair{4.2f, std::string("Running")}}) {
    Scene scene;
    Recorder recorder;
    scene.addListener(&recorder);
    Character* robot = scene.addCharacter("robot", rig);
    ASSERT_TRUE(robot->playBlend(0, space, {}, x, 0.0f));
    std::vector<float> weights(space->samples().size());
    space->weights(x, 0.0f, weights);
    const double cycle = space->cycleDuration(weights);
    const int frames = static_cast<int>(std::ceil(cycle * 4 * 60.0));
    for (int k = 0; k < frames; ++k) scene.update(1.0 / 60.0);
    int downs[2] = {};
    FootSide last = FootSide::None;
    for (const Heard& h : recorder.heard) {
      if (h.kind != AnimationEventKind::FootDown) continue;
      const int f = h.side == FootSide::Left ? 0 : 1;
      ++downs[f];
      EXPECT_EQ(h.clip, lead) << "at x = " << x;
      EXPECT_NE(h.side, last) << "two touchdowns of one foot in a row at " << h.sceneTime << " s";
      last = h.side;
    }
    std::printf("x = %.2f (%s leads): %d left and %d right touchdowns over 4 cycles of %.3f s\n", static_cast<double>(x),
                lead.c_str(), downs[0], downs[1], cycle);
    for (int f = 0; f < 2; ++f) EXPECT_NEAR(downs[f], 4, 1) << "foot " << f << " at x = " << x;
    ASSERT_TRUE(robot);
  }
}
