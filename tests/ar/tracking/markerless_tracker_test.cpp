// The markerless tracker on real and synthetic data: the graffiti pair with its true
// homography (opencv-doc), bad and extreme input, determinism, maps saved and reloaded.
// Accuracy over the scenario catalogue is in tracking_accuracy_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "test_data.hpp"
#include "tracking/synthetic_sequence.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

const CameraModel kCamera{.width = 640, .height = 480, .fx = 600, .fy = 600, .cx = 319.5, .cy = 239.5};

std::string graf(int i) { return test::opencvData("graf" + std::to_string(i) + ".png"); }

ImageView view(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)};
}

std::unique_ptr<MarkerlessTracker> grafTracker(const CameraModel& camera, MarkerlessSettings settings = {}) {
  Diagnostics d;
  auto t = MarkerlessTracker::fromTarget(camera, graf(1), 0.3, settings, d);
  EXPECT_TRUE(t) << d.format();
  return t;
}

synthetic::SequenceRenderer grafRenderer(const CameraModel& camera) {
  synthetic::PlanarScene scene;
  scene.target = cv::imread(graf(1), cv::IMREAD_COLOR);
  cv::cvtColor(scene.target, scene.target, cv::COLOR_BGR2RGB);
  scene.targetWidth = 0.3;
  return synthetic::SequenceRenderer(scene, camera);
}

// The graffiti wall from two viewpoints with the true homography between them (real photos,
// other light, 40 degrees apart): relocalization then KLT against the warped reference must
// find graf1's pixels in graf3 where H1to3p puts them. graf1 is not fronto-parallel and the
// pair has no intrinsics, so the check is on the tracker's homography, not on a pose: the
// pose is accepted here whatever its residual (a long focal length, rms unlimited).
TEST(MarkerlessTracker, GraffitiHomographyMatchesTheTrueOne) {
  MARIONETTE_REQUIRE_FILE(graf(1));
  MARIONETTE_REQUIRE_FILE(graf(3));
  MARIONETTE_REQUIRE_FILE(test::opencvData("H1to3p.xml"));
  cv::Mat h13;
  cv::FileStorage(test::opencvData("H1to3p.xml"), cv::FileStorage::READ)["H13"] >> h13;
  ASSERT_EQ(h13.rows, 3);
  const cv::Mat image3 = cv::imread(graf(3), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image3.empty());
  const double w = 800, h = 640, s = 0.3 / w;  // graf1's size; the target is 0.3 m wide
  const CameraModel camera{.width = image3.cols, .height = image3.rows, .fx = 3000, .fy = 3000,
                           .cx = image3.cols / 2.0 - 0.5, .cy = image3.rows / 2.0 - 0.5};
  MarkerlessSettings settings;
  settings.maxTrackingRmsPx = 100;
  auto tracker = grafTracker(camera, settings);
  ASSERT_TRUE(tracker);
  // The relocalized pose is given once the next frame (the same photo) confirms it.
  EXPECT_EQ(tracker->update(view(image3), 0.0).state, TrackingState::Lost);
  EXPECT_TRUE(tracker->lastFrame().relocalized);
  const TrackedPose p = tracker->update(view(image3), 1.0 / 30);
  ASSERT_NE(p.state, TrackingState::Lost);
  const cv::Matx33d g(tracker->lastFrame().planeToImage.data());
  double sum = 0, worst = 0;
  int n = 0;
  for (double v = 40; v < h - 40; v += 40)
    for (double u = 40; u < w - 40; u += 40) {
      const cv::Vec3d t = cv::Matx33d(h13) * cv::Vec3d(u, v, 1);
      const double ut = t[0] / t[2], vt = t[1] / t[2];
      if (ut < 0 || vt < 0 || ut >= camera.width || vt >= camera.height) continue;
      const cv::Vec3d e = g * cv::Vec3d((u + 0.5 - w / 2) * s, (v + 0.5 - h / 2) * s, 1);
      const double err = std::hypot(e[0] / e[2] - ut, e[1] / e[2] - vt);
      sum += err;
      worst = std::max(worst, err);
      ++n;
    }
  ASSERT_GT(n, 100);
  std::printf("graf1 -> graf3: %d inliers, transfer error against H1to3p mean %.2f px, max %.2f px\n",
              tracker->lastFrame().inliers, sum / n, worst);
  EXPECT_LT(sum / n, 1.0);
  EXPECT_LT(worst, 3.0);
}

TEST(MarkerlessTracker, BadFramesAreLostNeverACrash) {
  auto tracker = grafTracker(kCamera);
  ASSERT_TRUE(tracker);
  const std::uint8_t one = 7;
  EXPECT_EQ(tracker->update({}, 0.0).state, TrackingState::Lost);
  EXPECT_EQ(tracker->update({&one, 1, 1, 1, 0}, 0.1).state, TrackingState::Lost);
  const cv::Mat small(240, 320, CV_8UC3, cv::Scalar(20, 30, 40));
  EXPECT_EQ(tracker->update(view(small), 0.2).state, TrackingState::Lost);  // another size
  for (int level : {0, 255}) {
    const cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(level));
    EXPECT_EQ(tracker->update(view(flat), 0.3).state, TrackingState::Lost) << level;
  }
  cv::Mat noise(480, 640, CV_8UC1);
  cv::randu(noise, 0, 256);
  EXPECT_EQ(tracker->update(view(noise), 0.4).state, TrackingState::Lost);
  const ImageView badStride{noise.data, 640, 480, 1, 100};
  EXPECT_EQ(tracker->update(badStride, 0.5).state, TrackingState::Lost);
  const ImageView twoChannels{noise.data, 320, 480, 2, 0};
  EXPECT_EQ(tracker->update(twoChannels, 0.6).state, TrackingState::Lost);
}

TEST(MarkerlessTracker, BadSetupIsAClearError) {
  Diagnostics d;
  EXPECT_FALSE(MarkerlessTracker::fromTarget(kCamera, "/nonexistent/target.png", 0.3, {}, d));
  EXPECT_NE(d.format().find("/nonexistent/target.png"), std::string::npos) << d.format();
  for (double width : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    Diagnostics e;
    EXPECT_FALSE(MarkerlessTracker::fromTarget(kCamera, graf(1), width, {}, e));
    EXPECT_NE(e.format().find("--target-width"), std::string::npos) << e.format();
  }
  CameraModel nanCamera = kCamera;
  nanCamera.fx = std::nan("");
  Diagnostics e;
  EXPECT_FALSE(MarkerlessTracker::fromTarget(nanCamera, graf(1), 0.3, {}, e));
  EXPECT_NE(e.format().find("NaN"), std::string::npos) << e.format();
  // A target without texture.
  const cv::Mat flat(200, 200, CV_8UC1, cv::Scalar(128));
  Diagnostics f;
  EXPECT_FALSE(MarkerlessTracker::fromTargetPixels(kCamera, view(flat), 0.3, {}, f));
  EXPECT_NE(f.format().find("too little texture"), std::string::npos) << f.format();
  const std::uint8_t px = 0;
  Diagnostics g;
  EXPECT_FALSE(MarkerlessTracker::fromTargetPixels(kCamera, {&px, 1, 1, 1, 0}, 0.3, {}, g));
  MarkerlessSettings bad;
  bad.trackedCorners = 0;
  Diagnostics h;
  EXPECT_FALSE(MarkerlessTracker::fromTarget(kCamera, graf(1), 0.3, bad, h));
  EXPECT_NE(h.format().find("trackedCorners"), std::string::npos) << h.format();
  // Session 25's settings: the by-parts gate and the carried poses.
  auto refused = [&](MarkerlessSettings s, const char* name) {
    Diagnostics refusal;
    EXPECT_FALSE(MarkerlessTracker::fromTarget(kCamera, graf(1), 0.3, s, refusal)) << name;
    EXPECT_NE(refusal.format().find(name), std::string::npos) << refusal.format();
  };
  MarkerlessSettings parts;
  parts.minDenseAgreeingParts = 0;
  refused(parts, "minDenseAgreeingParts");
  MarkerlessSettings carry;
  carry.carryRotationSigmaDeg = std::nan("");
  refused(carry, "carryRotationSigmaDeg");
  carry = {};
  carry.maxCarriedFrames = -1;
  refused(carry, "maxCarriedFrames");
}

std::vector<cv::Mat> orbitFrames(const synthetic::SequenceRenderer& r, int count, std::vector<glm::dmat4>& truth) {
  std::vector<cv::Mat> frames;
  for (int i = 0; i < count; ++i) {
    const double a = 0.02 * i;
    const glm::dvec3 eye(0.45 * std::sin(a), 0.5, 0.45 * std::cos(a));
    truth.push_back(synthetic::lookAtCameraToWorld(eye, glm::dvec3(0), glm::dvec3(0, 1, 0)));
    cv::Mat f;
    synthetic::FrameEffects fx;
    fx.noiseSigma = 2;
    fx.noiseSeed = static_cast<std::uint32_t>(i + 1);
    r.render(truth.back(), fx, f);
    frames.push_back(f);
  }
  return frames;
}

TEST(MarkerlessTracker, SameFramesGiveTheSamePoseBits) {
  const auto renderer = grafRenderer(kCamera);
  std::vector<glm::dmat4> truth;
  const auto frames = orbitFrames(renderer, 20, truth);
  std::vector<glm::dmat4> first;
  for (int run = 0; run < 2; ++run) {
    auto tracker = grafTracker(kCamera);
    ASSERT_TRUE(tracker);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const TrackedPose p = tracker->update(view(frames[i]), static_cast<double>(i) / 30.0);
      // Frame 0 relocalizes; its pose is given once frame 1 confirms it.
      ASSERT_EQ(p.state, i == 0 ? TrackingState::Lost : TrackingState::Tracking) << "frame " << i;
      if (run == 0) first.push_back(p.cameraToWorld);
      else EXPECT_EQ(std::memcmp(&first[i], &p.cameraToWorld, sizeof(glm::dmat4)), 0) << "frame " << i;
    }
  }
  // And the poses are right.
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_LT(glm::length(glm::dvec3(first[i][3]) - glm::dvec3(truth[i][3])), 0.01) << i;
}

// A camera with strong barrel distortion: the tracker undistorts each frame itself (its own
// fixed-point remap, since cv::remap allocates per call), so the poses stay right.
TEST(MarkerlessTracker, DistortedLensTracksAsThePinholeDoes) {
  CameraModel lens = kCamera;
  lens.distortion = {-0.28, 0.09, 0.001, -0.0005, 0.0};
  const auto renderer = grafRenderer(lens);
  std::vector<glm::dmat4> truth;
  const auto frames = orbitFrames(renderer, 20, truth);
  auto tracker = grafTracker(lens);
  ASSERT_TRUE(tracker);
  double worstWithLens = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const TrackedPose p = tracker->update(view(frames[i]), static_cast<double>(i) / 30.0);
    ASSERT_EQ(p.state, i == 0 ? TrackingState::Lost : TrackingState::Tracking) << "frame " << i;
    if (i == 0) continue;
    worstWithLens = std::max(worstWithLens, glm::length(glm::dvec3(p.cameraToWorld[3]) - glm::dvec3(truth[i][3])));
  }
  EXPECT_LT(worstWithLens, 0.01);
  // The same frames read as if the lens were a pinhole are clearly worse: the undistortion is
  // what makes the difference.
  auto pinhole = grafTracker(kCamera);
  double worst = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const TrackedPose p = pinhole->update(view(frames[i]), static_cast<double>(i) / 30.0);
    if (p.state != TrackingState::Lost)
      worst = std::max(worst, glm::length(glm::dvec3(p.cameraToWorld[3]) - glm::dvec3(truth[i][3])));
  }
  EXPECT_GT(worst, 2 * worstWithLens) << worstWithLens;
}

TEST(MarkerlessTracker, SavedMapRelocalizesAtLaunchAndCorruptMapsAreErrors) {
  const auto renderer = grafRenderer(kCamera);
  std::vector<glm::dmat4> truth;
  const auto frames = orbitFrames(renderer, 10, truth);
  auto tracker = grafTracker(kCamera);
  ASSERT_TRUE(tracker);
  for (std::size_t i = 0; i < frames.size(); ++i) (void)tracker->update(view(frames[i]), static_cast<double>(i) / 30.0);
  const auto file = (std::filesystem::temp_directory_path() / "marionette_graf.map").string();
  Diagnostics error;
  ASSERT_TRUE(writePlanarMap(file, tracker->map(), error)) << error.format();

  Diagnostics d;
  auto map = readPlanarMap(file, d);
  ASSERT_TRUE(map) << d.format();
  EXPECT_EQ(map->keyframes.size(), tracker->map().keyframes.size());
  EXPECT_EQ(map->keyframes[0].grey, tracker->map().keyframes[0].grey);
  auto relaunched = MarkerlessTracker::fromMap(kCamera, std::move(*map), file, {}, d);
  ASSERT_TRUE(relaunched) << d.format();
  EXPECT_EQ(relaunched->update(view(frames[5]), 0.0).state, TrackingState::Lost);  // relocalized, to be confirmed
  const TrackedPose p = relaunched->update(view(frames[5]), 1.0 / 30);
  ASSERT_EQ(p.state, TrackingState::Tracking);
  EXPECT_LT(glm::length(p.position() - glm::dvec3(truth[5][3])), 0.01);

  // Another camera: refused, naming the file.
  CameraModel other = kCamera.scaledTo(320, 240);
  auto again = readPlanarMap(file, d);
  ASSERT_TRUE(again);
  Diagnostics e;
  EXPECT_FALSE(MarkerlessTracker::fromMap(other, std::move(*again), file, {}, e));
  EXPECT_NE(e.format().find(file), std::string::npos);
  EXPECT_NE(e.format().find("320x240"), std::string::npos) << e.format();

  // Truncated at every length, and a flipped byte anywhere: an error, never a crash or a map.
  const std::string bytes = test::readFile(file);
  ASSERT_GT(bytes.size(), 1000u);
  for (std::size_t cut : {std::size_t(0), std::size_t(7), std::size_t(12), std::size_t(40), bytes.size() / 2, bytes.size() - 1}) {
    Diagnostics t;
    EXPECT_FALSE(parsePlanarMap(reinterpret_cast<const std::uint8_t*>(bytes.data()), cut, "cut.map", t)) << cut;
    EXPECT_NE(t.format().find("cut.map"), std::string::npos);
  }
  for (std::size_t at : {std::size_t(3), std::size_t(9), std::size_t(30), bytes.size() / 3, bytes.size() - 2}) {
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    Diagnostics t;
    EXPECT_FALSE(parsePlanarMap(reinterpret_cast<const std::uint8_t*>(damaged.data()), damaged.size(), "bad.map", t))
        << at;
    EXPECT_FALSE(t.ok());
  }
  Diagnostics t;
  EXPECT_FALSE(readPlanarMap("/nonexistent.map", t));
  EXPECT_NE(t.format().find("/nonexistent.map"), std::string::npos);
}

// Videos without the target: the tracker must report nothing.
TEST(MarkerlessTracker, NoPoseInVideosWithoutTheTarget) {
  for (const char* name : {"vtest.avi", "tree.avi", "Megamind.avi"}) {
    const std::string file = test::opencvData(name);
    MARIONETTE_REQUIRE_FILE(file);
    cv::VideoCapture video(file);
    ASSERT_TRUE(video.isOpened()) << file;
    const int w = static_cast<int>(video.get(cv::CAP_PROP_FRAME_WIDTH)), h = static_cast<int>(video.get(cv::CAP_PROP_FRAME_HEIGHT));
    const CameraModel camera{.width = w, .height = h, .fx = 0.9 * w, .fy = 0.9 * w, .cx = w / 2.0 - 0.5, .cy = h / 2.0 - 0.5};
    auto tracker = grafTracker(camera);
    ASSERT_TRUE(tracker);
    cv::Mat frame;
    int frames = 0, posed = 0;
    while (frames < 300 && video.read(frame)) {
      posed += tracker->update(view(frame), frames / 30.0).state != TrackingState::Lost;
      ++frames;
    }
    std::printf("%s: %d frames, %d with a pose\n", name, frames, posed);
    EXPECT_GT(frames, 50);
    EXPECT_EQ(posed, 0) << name;
  }
}

}  // namespace
