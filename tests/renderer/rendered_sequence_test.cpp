// The tracking evaluation on a sequence the project's own renderer made, with the character as
// the occluder (docs/tracking.md, "Evaluation on sequences with exact poses"): the synthetic
// orbit (tests/support/tracking) written as PNG frames with its exact poses (truth.csv), then
// rendered by marionette-ar headless with those poses replayed ("camera": {"poses"}) over the
// frames, BCN standing on the target; then `marionette-ar track` on the rendered frames, from
// the target image alone, compared with the truth by the trajectory metrics. One test: the
// sequence, both renders (with the character and --hide-characters, which measures how much
// of the target it covers) and the tracking are its shared setup.
//
// MARIONETTE_RENDERED_SEQUENCE_FRAMES (default 90: 3 s of the orbit) sets the length;
// docs/tracking.md gives the figures at 90 and 150.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <glm/gtc/quaternion.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_run.hpp"
#include "marionette_ar/pose_track.hpp"
#include "test_data.hpp"
#include "tracking/scenario_run.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

// BCN_Epileptic's root (its pelvis) is 0.99 m above its feet at scale 1; at 0.4 it is 0.68 m
// tall, standing on the centre of the 0.30 m target, and covers about a third of it.
constexpr double kScale = 0.6;
constexpr double kPelvis = 0.99 * kScale;  // its root's height

int framesWanted() {
  const char* env = std::getenv("MARIONETTE_RENDERED_SEQUENCE_FRAMES");
  return env ? std::clamp(std::atoi(env), 10, 3000) : 90;
}

void writeSequence(const ar::synthetic::RenderedScenario& orbit, const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream csv(dir / "truth.csv");
  csv << "frame,time,state,px,py,pz,qx,qy,qz,qw\n";
  char line[256];
  for (std::size_t i = 0; i < orbit.frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    cv::Mat bgr;
    cv::cvtColor(orbit.frames[i], bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite((dir / name).string(), bgr));
    const glm::dmat4& m = orbit.scenario.cameraToWorld[i];
    const glm::dquat q = glm::quat_cast(glm::dmat3(m));
    std::snprintf(line, sizeof line, "%zu,%.9g,TRACKING,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", i,
                  double(i) / orbit.scenario.fps, m[3].x, m[3].y, m[3].z, q.x, q.y, q.z, q.w);
    csv << line;
  }
}

bool differs(const ar::Image8& a, const ar::Image8& b, int x, int y) {
  const std::size_t p = (std::size_t(y) * std::size_t(a.width) + std::size_t(x)) * std::size_t(a.channels);
  int d = 0;
  for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.pixels[p + c]) - int(b.pixels[p + c])));
  return d > 12;
}

// The target's quad through the exact pose (the camera has no distortion: straight edges).
cv::Mat targetMask(const ar::synthetic::SequenceRenderer& renderer, const glm::dmat4& pose) {
  cv::Mat mask = cv::Mat::zeros(renderer.camera().height, renderer.camera().width, CV_8U);
  const double hw = renderer.targetWidth() / 2, hd = renderer.targetDepth() / 2;
  std::vector<cv::Point> quad;
  for (const glm::dvec3 corner : {glm::dvec3(-hw, 0, -hd), glm::dvec3(hw, 0, -hd), glm::dvec3(hw, 0, hd),
                                  glm::dvec3(-hw, 0, hd)}) {
    const glm::dvec2 p = ar::synthetic::projectWorldPoint(renderer.camera(), pose, corner);
    quad.emplace_back(int(std::lround(p.x * 16)), int(std::lround(p.y * 16)));
  }
  cv::fillConvexPoly(mask, quad, cv::Scalar(255), cv::LINE_8, 4);
  return mask;
}

std::vector<ar::TrackedPose> readEstimates(const std::string& path) {
  Diagnostics d;
  const auto track = ar::readPoseTrack(path, d);
  EXPECT_TRUE(track) << d.format();
  std::vector<ar::TrackedPose> poses;
  if (!track) return poses;
  for (const ar::RecordedPose& r : track->rows()) {
    ar::TrackedPose p;
    p.state = r.state;
    p.cameraToWorld = r.cameraToWorld;
    poses.push_back(p);
  }
  return poses;
}

TEST(RenderedSequence, TrackingThroughTheCharacterMeetsTheGoal) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const std::string forest = "/usr/share/blender/datafiles/studiolights/world/forest.exr";  // blender-data
  MARIONETTE_REQUIRE_FILE(forest);
  const int frames = framesWanted();
  const fs::path dir = fs::temp_directory_path() / "marionette_rendered_sequence_test";
  fs::remove_all(dir);
  const auto renderer = ar::synthetic::standardRenderer();
  const auto scenarios = ar::synthetic::renderScenarios(renderer, frames, {"orbit"});
  ASSERT_EQ(scenarios.size(), 1u);
  const auto& orbit = scenarios[0];
  writeSequence(orbit, dir / "sequence");
  if (HasFatalFailure()) return;

  const std::string camera = sourceFile("assets/cameras/synthetic_640x480.yml");
  std::ofstream(dir / "middleware.json") << R"({ "characters": [ { "name": "bcn",
      "asset": "/usr/share/assimp/models/X/BCN_Epileptic.X", "position": [0, )" << kPelvis
                                         << R"(, 0], "scale": )" << kScale << R"(, "play": [] } ] })";
  std::ofstream(dir / "replayed.json") << R"({ "scene": "middleware.json",
      "camera": { "poses": "sequence/truth.csv", "camera": ")" << camera << R"(", "near": 0.02, "far": 50 },
      "background": { "kind": "sequence", "file": "sequence", "fps": 30 },
      "environment": { "file": ")" << forest << R"(", "prt": { "mode": "off" } },
      "render": { "width": 640, "height": 480, "fps": 30, "contactShadows": false } })";
  // (No contact shadow: the character's pixels are where a frame differs from the empty plate,
  // and the published figures are for the character alone over the target.)
  const std::string common = (dir / "replayed.json").string() + " --headless --frames " + std::to_string(frames);
  const CliRun with = runAr(common + " --out " + (dir / "with").string());
  ASSERT_EQ(with.status, 0) << with.out;
  const std::string all = std::to_string(frames) + " of " + std::to_string(frames) + " frames with a pose";
  EXPECT_NE(with.out.find("replayed poses: " + all), std::string::npos) << with.out;
  const CliRun without = runAr(common + " --hide-characters --out " + (dir / "without").string());
  ASSERT_EQ(without.status, 0) << without.out;

  // How much of the target the character covers.
  std::vector<double> covered;
  double backgroundDiff = 0;
  for (int i = 0; i < frames; ++i) {
    const ar::Image8 a = frame(dir / "with", i), b = frame(dir / "without", i);
    ASSERT_EQ(a.width, 640);
    ASSERT_EQ(b.width, 640);
    const glm::dmat4& pose = orbit.scenario.cameraToWorld[std::size_t(i)];
    const cv::Mat mask = targetMask(renderer, pose);
    long target = 0, hidden = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        if (mask.at<std::uint8_t>(y, x)) {
          ++target;
          hidden += differs(a, b, x, y) ? 1 : 0;
        }
    ASSERT_GT(target, 1000) << "frame " << i;
    covered.push_back(double(hidden) / double(target));
    if (i % 15 == 0) {  // the background is the sequence's frame, as it is
      const cv::Mat& source = orbit.frames[std::size_t(i)];
      double sum = 0;
      for (int k = 0; k < a.width * a.height; ++k)
        for (int c = 0; c < 3; ++c) sum += std::abs(int(b.pixels[std::size_t(k) * b.channels + c]) - int(source.data[k * 3 + c]));
      backgroundDiff = std::max(backgroundDiff, sum / (3.0 * a.width * a.height));
    }
  }
  std::vector<double> sorted = covered;
  std::sort(sorted.begin(), sorted.end());
  std::printf("the character covers %.1f %% .. %.1f %% of the target (median %.1f %%); the background differs from "
              "the sequence by %.2f / 255 at most (mean per frame)\n",
              100 * sorted.front(), 100 * sorted.back(), 100 * sorted[sorted.size() / 2], backgroundDiff);
  EXPECT_GE(sorted.front(), 0.20);
  EXPECT_LE(sorted.back(), 0.60);
  EXPECT_LT(backgroundDiff, 2.0);

  // The replayed view is the exact pose: frame k drawn by a static camera placed at the true
  // pose k (the calibration's principal point is the image centre, so a symmetric frustum of
  // fovY = 2 atan(240 / 600) is the same projection) over that frame gives the same picture.
  const int k = frames / 2;
  const glm::dmat4& truthK = orbit.scenario.cameraToWorld[std::size_t(k)];
  const glm::dvec3 eye(truthK[3]), look = eye - glm::dvec3(truthK[2]), up(truthK[1]);
  char still[1024], name[32];
  std::snprintf(name, sizeof name, "frame_%04d.png", k);
  std::snprintf(still, sizeof still,
                R"({ "scene": "middleware.json",
      "camera": { "position": [%.9g, %.9g, %.9g], "target": [%.9g, %.9g, %.9g], "up": [%.9g, %.9g, %.9g],
                  "fovY": %.9g, "near": 0.02, "far": 50 },
      "background": { "kind": "image", "file": "sequence/%s" },
      "environment": { "file": "%s", "prt": { "mode": "off" } },
      "render": { "width": 640, "height": 480, "fps": 30 } })",
                eye.x, eye.y, eye.z, look.x, look.y, look.z, up.x, up.y, up.z,
                2 * std::atan(240.0 / 600.0) * 180 / 3.14159265358979323846, name, forest.c_str());
  std::ofstream(dir / "still.json") << still;
  const CliRun stillRun = runAr((dir / "still.json").string() + " --headless --frames 1 --out " + (dir / "still").string());
  ASSERT_EQ(stillRun.status, 0) << stillRun.out;
  const ar::Image8 replayed = frame(dir / "with", k), placed = frame(dir / "still", 0);
  long mismatched = 0, character = 0;
  const ar::Image8 plate = frame(dir / "without", k);
  for (int y = 0; y < replayed.height; ++y)
    for (int x = 0; x < replayed.width; ++x) {
      mismatched += differs(replayed, placed, x, y) ? 1 : 0;
      character += differs(replayed, plate, x, y) ? 1 : 0;
    }
  std::printf("frame %d replayed against a static camera at its true pose: %ld of %ld character pixels differ\n", k,
              mismatched, character);
  EXPECT_GT(character, 10000);
  EXPECT_LT(mismatched, character / 100) << "the replayed pose does not draw the character where the exact pose does";

  // Track the rendered frames from the target image, as a user would.
  const CliRun track = runAr("track --camera " + camera + " --images " + (dir / "with").string() + " --target " +
                             ar::synthetic::standardTargetImage() + " --target-width 0.3 --poses " +
                             (dir / "estimated.csv").string() + " --json");
  ASSERT_EQ(track.status, 0) << track.out;
  const std::vector<ar::TrackedPose> estimated = readEstimates((dir / "estimated.csv").string());
  ASSERT_EQ(estimated.size(), std::size_t(frames));
  const ar::synthetic::TrajectoryReport r = ar::synthetic::compareTrajectory(
      estimated, orbit.scenario.cameraToWorld, orbit.scenario.visibleFraction, renderer.camera());
  std::printf("%s\n%s", ar::synthetic::formatReport(r).c_str(), track.out.c_str());
  std::printf("| rendered orbit, BCN occluding %.0f-%.0f %% | %d | %d | %d | %.0f %% | %.2f | %.2f | %.2f | %d |\n",
              100 * sorted.front(), 100 * sorted.back(), r.frames, r.visibleFrames, r.verifiedFrames,
              100.0 * r.within2cm / std::max(1, r.visibleFrames), 100 * r.ateRmsM, 100 * r.ateMaxM, r.rotationMeanDeg,
              r.falsePoses);
  EXPECT_GE(r.within2cm, 0.95 * r.visibleFrames) << "the goal: 95 % of the visible frames within 2 cm";
  EXPECT_EQ(r.falsePoses, 0) << "TRACKING more than 5 cm off";
  EXPECT_LT(r.ateRmsM, 0.01);
  // Regression bounds (issue 41): about 1.5x docs/tracking.md's 90-frame row (0.16 cm rms,
  // 0.26 cm max, 0.10 deg mean), which session 26 reproduced to the digit.
  EXPECT_LT(r.ateRmsM, 0.0024);
  EXPECT_LT(r.ateMaxM, 0.0039);
  EXPECT_LT(r.rotationMeanDeg, 0.15);
  EXPECT_GE(r.verifiedFrames, frames / 2) << "the character must not reduce the tracker to LIMITED";
}

}  // namespace
}  // namespace marionette::test
