// marionette-ar with a tracked camera, end to end: a synthetic sequence with exact poses
// (tests/support/tracking), `marionette-ar track` saving the map, then an AR scene that
// restores the map and draws a character on the target. The character's feet must land where
// the exact pose projects the world origin; when the camera frames show no target, the
// characters are hidden once the hold time has passed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_run.hpp"
#include "marionette_ar/render/image.hpp"
#include "test_data.hpp"
#include "tracking/scenario_run.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

// The lowest row where `with` differs from `without` (the character's feet), and the mean
// column of the differing pixels in the 6 rows above it; -1 when nothing differs.
bool feet(const ar::Image8& with, const ar::Image8& without, double& u, double& v, int& pixels) {
  int lowest = -1;
  pixels = 0;
  auto differs = [&](int x, int y) {
    const std::size_t p = (std::size_t(y) * std::size_t(with.width) + std::size_t(x)) * std::size_t(with.channels);
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(with.pixels[p + c]) - int(without.pixels[p + c])));
    return d > 12;
  };
  for (int y = 0; y < with.height; ++y)
    for (int x = 30; x < with.width; ++x)  // the tracking badge sits in the top-left corner
      if (differs(x, y)) {
        lowest = y;
        ++pixels;
      }
  if (lowest < 0) return false;
  double sum = 0;
  int n = 0;
  for (int y = std::max(0, lowest - 6); y <= lowest; ++y)
    for (int x = 30; x < with.width; ++x)
      if (differs(x, y)) {
        sum += x;
        ++n;
      }
  u = sum / n;
  v = lowest;
  return true;
}

// `contactShadows`: the "render" key's value, or nothing (a tracked scene's default: on).
void writeScene(const fs::path& dir, const std::string& frames, const std::string& map,
                const std::string& contactShadows = "") {
  std::ofstream(dir / "middleware.json") << R"({ "characters": [ { "name": "bcn",
      "asset": "/usr/share/assimp/models/X/BCN_Epileptic.X", "position": [0, 0.2475, 0], "scale": 0.25, "play": [] } ] })";
  std::ofstream(dir / "tracked.json") << R"({ "scene": "middleware.json",
      "camera": { "tracker": { "kind": "markerless", "camera": ")" << sourceFile("assets/cameras/synthetic_640x480.yml")
                                      << R"(", "map": ")" << map << R"(", "holdSeconds": 0.5 } },
      "background": { "kind": "sequence", "file": ")" << frames << R"(", "fps": 30 },
      "render": { "width": 640, "height": 480, "fps": 30)"
                                      << (contactShadows.empty() ? "" : R"(, "contactShadows": )" + contactShadows) << " } }";
}

TEST(TrackedScene, CharacterStandsWhereTheExactPosePutsTheOrigin) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const fs::path dir = fs::temp_directory_path() / "marionette_tracked_scene_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  const auto renderer = ar::synthetic::standardRenderer();
  const auto scenarios = ar::synthetic::renderScenarios(renderer, 40, {"orbit"});
  ASSERT_EQ(scenarios.size(), 1u);
  const auto& orbit = scenarios[0];
  for (std::size_t i = 0; i < orbit.frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    cv::Mat bgr;
    cv::cvtColor(orbit.frames[i], bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite((dir / "frames" / name).string(), bgr));
  }
  const std::string map = (dir / "target.map").string();
  const CliRun track = runAr("track --camera " + sourceFile("assets/cameras/synthetic_640x480.yml") + " --images " +
                             (dir / "frames").string() + " --target " + ar::synthetic::standardTargetImage() +
                             " --target-width 0.3 --poses " + (dir / "poses.csv").string() + " --save-map " + map +
                             " --json");
  ASSERT_EQ(track.status, 0) << track.out;
  // Every frame but the first TRACKING: the relocalization at frame 0 is given once frame 1 confirms it.
  EXPECT_NE(track.out.find("\"tracked\": 39"), std::string::npos) << track.out;
  EXPECT_NE(track.out.find("\"sigma_position_m_median\": "), std::string::npos) << track.out;
  {  // Every pose with its standard deviations: positive, and a few millimetres at this range.
    std::ifstream csv(dir / "poses.csv");
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg");
    int withSigma = 0;
    while (std::getline(csv, line)) {
      if (line.find("TRACKING") == std::string::npos) continue;
      const std::size_t last = line.rfind(','), before = line.rfind(',', last - 1);
      const double sigmaM = std::atof(line.substr(before + 1, last - before - 1).c_str());
      const double sigmaDeg = std::atof(line.substr(last + 1).c_str());
      EXPECT_GT(sigmaM, 0.0) << line;
      EXPECT_LT(sigmaM, 0.01) << line;
      EXPECT_GT(sigmaDeg, 0.0) << line;
      EXPECT_LT(sigmaDeg, 1.0) << line;
      ++withSigma;
    }
    EXPECT_EQ(withSigma, 39);
  }
  ASSERT_TRUE(fs::exists(map));

  // The character's pixels are where the frame differs from the empty plate: no shadow on it.
  writeScene(dir, (dir / "frames").string(), map, "false");
  const std::string common = (dir / "tracked.json").string() + " --headless --frames 40";
  const CliRun with = runAr(common + " --out " + (dir / "with").string());
  ASSERT_EQ(with.status, 0) << with.out;
  // The map relocalized at launch, confirmed by the second frame.
  EXPECT_NE(with.out.find("tracking TRACKING at 0.033 s (frame 1)"), std::string::npos) << with.out;
  EXPECT_NE(with.out.find("39 of 40 camera frames with a pose"), std::string::npos) << with.out;
  ASSERT_EQ(runAr(common + " --hide-characters --out " + (dir / "without").string()).status, 0);
  // The feet (the lowest character pixels) cast back onto the floor through the exact pose:
  // the same world point in every frame (the character stays put on the target while the
  // camera circles), near the origin where it stands.
  const ar::CameraModel& camera = renderer.camera();
  std::vector<glm::dvec3> onFloor;
  for (int i : {5, 12, 20, 28, 35}) {
    SCOPED_TRACE(i);
    double u = 0, v = 0;
    int pixels = 0;
    ASSERT_TRUE(feet(frame(dir / "with", i), frame(dir / "without", i), u, v, pixels));
    EXPECT_GT(pixels, 300);
    const glm::dmat4& pose = orbit.scenario.cameraToWorld[std::size_t(i)];
    // The ray through pixel (u, v) in OpenGL camera axes (looking along -Z, +Y up).
    const glm::dvec3 ray = glm::dmat3(pose) * glm::dvec3((u - camera.cx) / camera.fx, -(v - camera.cy) / camera.fy, -1.0);
    const glm::dvec3 eye(pose[3]);
    ASSERT_LT(ray.y, 0);
    onFloor.push_back(eye + ray * (-eye.y / ray.y));
    std::printf("frame %d: feet at pixel (%.1f, %.1f), on the floor at (%.3f, %.3f) m; %d character pixels\n", i, u, v,
                onFloor.back().x, onFloor.back().z, pixels);
  }
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : onFloor) mean += p / double(onFloor.size());
  for (const glm::dvec3& p : onFloor) EXPECT_LT(glm::length(p - mean), 0.015);  // the feet do not slide
  EXPECT_LT(glm::length(mean), 0.06);  // and stand at the origin (BCN's toes are 3-4 cm from its root here)
}

TEST(TrackedScene, CharactersHideWhenTheTargetIsGone) {
  const fs::path dir = fs::temp_directory_path() / "marionette_tracked_lost_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  // The map of a real target, then frames of noise: no pose ever, so nothing is drawn.
  cv::RNG rng(3);
  for (int i = 0; i < 12; ++i) {
    cv::Mat noise(480, 640, CV_8UC3);
    rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", i);
    ASSERT_TRUE(cv::imwrite((dir / "frames" / name).string(), noise));
  }
  const std::string map = (dir / "target.map").string();
  {
    Diagnostics d;
    auto tracker = ar::MarkerlessTracker::fromTarget(ar::synthetic::standardRenderer().camera(),
                                                     ar::synthetic::standardTargetImage(), 0.3, {}, d);
    ASSERT_TRUE(tracker) << d.format();
    Diagnostics error;
    ASSERT_TRUE(ar::writePlanarMap(map, tracker->map(), error)) << error.format();
  }
  writeScene(dir, (dir / "frames").string(), map);
  const std::string common = (dir / "tracked.json").string() + " --headless --frames 12";
  const CliRun with = runAr(common + " --out " + (dir / "with").string());
  ASSERT_EQ(with.status, 0) << with.out;
  EXPECT_NE(with.out.find("tracking LOST at 0.000 s"), std::string::npos) << with.out;
  EXPECT_NE(with.out.find("0 of 12 camera frames with a pose"), std::string::npos) << with.out;
  // Contact shadows are on by default in a tracked scene, and a hidden character casts none
  // (the frames below are the same with and without characters).
  EXPECT_NE(with.out.find("contact shadows: light from"), std::string::npos) << with.out;
  ASSERT_EQ(runAr(common + " --hide-characters --out " + (dir / "without").string()).status, 0);
  double u = 0, v = 0;
  int pixels = 0;
  EXPECT_FALSE(feet(frame(dir / "with", 11), frame(dir / "without", 11), u, v, pixels)) << pixels << " pixels differ";
  // A scene with a tracker but an image background is refused, naming the key.
  std::ofstream(dir / "still.json") << R"({ "scene": "middleware.json",
      "camera": { "tracker": { "kind": "markerless", "camera": "c.yml", "map": "m.map" } },
      "background": { "kind": "image", "file": "x.png" } })";
  const CliRun still = runAr((dir / "still.json").string() + " --headless --out " + (dir / "s").string());
  EXPECT_EQ(still.status, 2);
  EXPECT_NE(still.out.find("camera.tracker"), std::string::npos) << still.out;
}

// A replayed trajectory ("camera": {"poses"}) over a colour background (rows by scene time):
// LOST rows act as the tracker's LOST (held for holdSeconds, then hidden, or kept with
// "hideWhenLost": false), and a bad CSV or a tracker beside the poses is named.
TEST(TrackedScene, ReplayedPosesHoldHideAndNameBadRows) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const fs::path dir = fs::temp_directory_path() / "marionette_replayed_poses_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream csv(dir / "poses.csv");  // 1.2 m in front of the character, looking along -Z
    csv << "frame,time,state,px,py,pz,qx,qy,qz,qw\n";
    for (int k = 0; k < 12; ++k)
      csv << k << "," << k / 30.0 << (k < 5 ? ",TRACKING,0,0.2,1.2,0,0,0,1\n" : ",LOST,,,,,,,\n");
  }
  std::ofstream(dir / "middleware.json") << R"({ "characters": [ { "name": "bcn",
      "asset": "/usr/share/assimp/models/X/BCN_Epileptic.X", "position": [0, 0.2475, 0], "scale": 0.25, "play": [] } ] })";
  auto scene = [&](const std::string& name, const std::string& camera) {
    std::ofstream(dir / name) << R"({ "scene": "middleware.json", "camera": { "poses": "poses.csv", "camera": ")"
                              << sourceFile("assets/cameras/synthetic_640x480.yml") << "\", " << camera
                              << R"( }, "background": { "kind": "color", "color": [0.2, 0.3, 0.4] },
        "render": { "width": 320, "height": 240, "fps": 30 } })";
    return (dir / name).string() + " --headless --frames 12";
  };
  const std::string hide = scene("hide.json", R"("holdSeconds": 0.1)");
  const CliRun with = runAr(hide + " --out " + (dir / "with").string());
  ASSERT_EQ(with.status, 0) << with.out;
  EXPECT_NE(with.out.find("replayed pose LOST at 0.167 s (frame 5)"), std::string::npos) << with.out;
  EXPECT_NE(with.out.find("replayed poses: 5 of 12 frames with a pose"), std::string::npos) << with.out;
  ASSERT_EQ(runAr(hide + " --hide-characters --out " + (dir / "without").string()).status, 0);
  const CliRun keep = runAr(scene("keep.json", R"("holdSeconds": 0.1, "hideWhenLost": false)") + " --out " +
                            (dir / "keep").string());
  ASSERT_EQ(keep.status, 0) << keep.out;
  auto drawn = [&](const std::string& run, int i) {
    double u = 0, v = 0;
    int pixels = 0;
    return feet(frame(dir / run, i), frame(dir / "without", i), u, v, pixels) && pixels > 200;
  };
  EXPECT_TRUE(drawn("with", 2));    // TRACKING
  EXPECT_TRUE(drawn("with", 6));    // LOST, within the 0.1 s hold
  EXPECT_FALSE(drawn("with", 11));  // LOST for 0.23 s: hidden
  EXPECT_TRUE(drawn("keep", 11));   // ... unless hideWhenLost is false
  // The held pose is the last one (the feet where they were), faded out over the hold time
  // (marionette_ar/pose_hold.hpp): fainter against the background than while TRACKING.
  double u2 = 0, v2 = 0, u6 = 0, v6 = 0;
  int n2 = 0, n6 = 0;
  ASSERT_TRUE(feet(frame(dir / "with", 2), frame(dir / "without", 2), u2, v2, n2));
  ASSERT_TRUE(feet(frame(dir / "with", 6), frame(dir / "without", 6), u6, v6, n6));
  EXPECT_NEAR(u6, u2, 1.0);
  EXPECT_NEAR(v6, v2, 1.0);
  auto contrast = [&](int i) {
    const ar::Image8 a = frame(dir / "with", i), b = frame(dir / "without", i);
    double sum = 0;
    for (std::size_t p = 0; p < a.pixels.size(); ++p) sum += std::abs(int(a.pixels[p]) - int(b.pixels[p]));
    return sum;
  };
  EXPECT_LT(contrast(6), 0.8 * contrast(2));

  std::ofstream(dir / "poses.csv", std::ios::app) << "12,0.4,TRACKING,0,0.2,1.2,0,0,nan,1\n";
  const CliRun bad = runAr(hide + " --out " + (dir / "bad").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find((dir / "poses.csv").string() + ":14: error: 'qz': not a finite number"), std::string::npos)
      << bad.out;
  const CliRun both = runAr(scene("both.json", R"("tracker": { "kind": "apriltag", "camera": "c.yml", "tagSize": 0.1 })") +
                            " --out " + (dir / "both").string());
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.out.find("'camera.poses': a camera either tracks or replays poses, not both"), std::string::npos)
      << both.out;
}

}  // namespace
}  // namespace marionette::test
