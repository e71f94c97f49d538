// Occlusion over the target, end to end (docs/ar-renderer.md, "Occlusion over the target"): a
// synthetic hand-held sequence with hands reaching over the poster a character stands on
// (tests/support/tracking, exact truth), `marionette-ar` drawing the character with the tracker's
// occlusion mask, and again with the true mask (the renderer's truth of which frame pixels show
// the target hidden, given as "masks"). The character's pixels hidden in the two renders must
// agree.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_run.hpp"
#include "marionette_ar/render/image.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "test_data.hpp"
#include "tracking/occlusion_metrics.hpp"
#include "tracking/scenario_run.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 30;

int pixelDifference(const ar::Image8& a, const ar::Image8& b, std::size_t p) {
  int d = 0;
  for (std::size_t c = 0; c < 3; ++c) {
    const std::size_t i = p * std::size_t(a.channels) + c;
    d = std::max(d, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
  }
  return d;
}

TEST(OcclusionRender, AHandOverThePosterHidesTheCharacterAsTheTrueMaskDoes) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const fs::path dir = fs::temp_directory_path() / "marionette_occlusion_render_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  fs::create_directories(dir / "masks");
  const auto renderer = ar::synthetic::standardRenderer();
  // Hands (one or two, with forearms, 5-25 cm above the poster) reaching in while the camera moves.
  const ar::synthetic::OcclusionSequence seq =
      ar::synthetic::stressOcclusionSequence(renderer, ar::synthetic::StressClass::Hands, 3, kFrames, 1);
  ASSERT_EQ(seq.frames.size(), std::size_t(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", i);
    cv::Mat bgr, mask;
    cv::cvtColor(seq.frames[std::size_t(i)], bgr, cv::COLOR_RGB2BGR);
    ASSERT_TRUE(cv::imwrite((dir / "frames" / name).string(), bgr));
    seq.truth[std::size_t(i)].hidden.convertTo(mask, CV_8U, 255.0);  // the share of each pixel hidden
    ASSERT_TRUE(cv::imwrite((dir / "masks" / name).string(), mask));
  }
  const std::string map = (dir / "target.map").string();
  {
    Diagnostics d;
    auto tracker = ar::MarkerlessTracker::fromTarget(renderer.camera(), ar::synthetic::standardTargetImage(), 0.3, {}, d);
    ASSERT_TRUE(tracker) << d.format();
    Diagnostics error;
    ASSERT_TRUE(ar::writePlanarMap(map, tracker->map(), error)) << error.format();
  }
  // BCN, 0.5 m tall, on the 30 cm poster; no contact shadow (the pixels compared are the character's).
  std::ofstream(dir / "middleware.json") << R"({ "characters": [ { "name": "bcn",
      "asset": ")" << assimpModel("X/BCN_Epileptic.X") << R"(", "position": [0, 0.2475, 0], "scale": 0.25, "play": [] } ] })";
  auto scene = [&](const std::string& name, const std::string& occlusion) {
    std::ofstream(dir / name) << R"({ "scene": "middleware.json",
        "camera": { "tracker": { "kind": "markerless", "camera": ")"
                              << sourceFile("assets/cameras/synthetic_640x480.yml") << R"(", "map": ")" << map
                              << R"(" } },
        "background": { "kind": "sequence", "file": ")" << (dir / "frames").string() << R"(", "fps": 30 },
        "render": { "width": 640, "height": 480, "fps": 30, "contactShadows": false)"
                              << (occlusion.empty() ? "" : R"(, "occlusion": )" + occlusion) << " } }";
    return (dir / name).string() + " --headless --frames " + std::to_string(kFrames);
  };
  // The tracker's mask: on by default with a markerless tracker.
  const CliRun tracked = runAr(scene("tracked.json", "") + " --out " + (dir / "tracked").string());
  ASSERT_EQ(tracked.status, 0) << tracked.out;
  EXPECT_NE(tracked.out.find("occlusion over the target: on (the tracker's mask)"), std::string::npos) << tracked.out;
  const CliRun truth = runAr(scene("truth.json", R"({"masks": ")" + (dir / "masks").string() + R"("})") + " --out " +
                             (dir / "truth").string());
  ASSERT_EQ(truth.status, 0) << truth.out;
  const CliRun off = runAr(scene("off.json", "false") + " --out " + (dir / "off").string());
  ASSERT_EQ(off.status, 0) << off.out;
  EXPECT_EQ(off.out.find("occlusion over the target"), std::string::npos) << off.out;
  ASSERT_EQ(runAr(scene("off.json", "false") + " --hide-characters --out " + (dir / "plate").string()).status, 0);

  // Per pixel of the character (where it changes the plate), hidden when the plate shows through
  // (closer to the plate than to the unoccluded character).
  long character = 0, hiddenTruth = 0, hiddenTracked = 0, both = 0, either = 0;
  double absDiff = 0.0;
  for (int i = 2; i < kFrames; ++i) {  // from the first frames the tracker confirms
    const ar::Image8 plate = frame(dir / "plate", i), drawn = frame(dir / "off", i);
    const ar::Image8 byTruth = frame(dir / "truth", i), byTracker = frame(dir / "tracked", i);
    long frameTruth = 0, frameBoth = 0, frameEither = 0;
    for (std::size_t p = 0; p < std::size_t(plate.width) * std::size_t(plate.height); ++p) {
      const int full = pixelDifference(drawn, plate, p);
      if (full <= 24) continue;
      ++character;
      const bool t = 2 * pixelDifference(byTruth, plate, p) < full;
      const bool e = 2 * pixelDifference(byTracker, plate, p) < full;
      hiddenTruth += t;
      hiddenTracked += e;
      both += t && e;
      either += t || e;
      frameTruth += t;
      frameBoth += t && e;
      frameEither += t || e;
      absDiff += pixelDifference(byTruth, byTracker, p);
    }
    std::printf("frame %d: %ld character pixels hidden by the true mask, IoU with the tracker's %.2f\n", i, frameTruth,
                frameEither ? double(frameBoth) / double(frameEither) : 1.0);
  }
  const double iou = either ? double(both) / double(either) : 0.0;
  std::printf("%ld character pixels: %ld hidden by the true mask, %ld by the tracker's, IoU %.3f, mean |difference| %.2f\n",
              character, hiddenTruth, hiddenTracked, iou, absDiff / double(std::max(1L, character)));
  ASSERT_GT(character, 20000);
  // The hands do pass in front of the character, and do not hide all of it.
  ASSERT_GT(hiddenTruth, 2000);
  EXPECT_LT(hiddenTruth, character / 2);
  EXPECT_GT(iou, 0.7);
  EXPECT_LT(double(hiddenTracked), 1.3 * double(hiddenTruth));
}

// Bad "occlusion" values name the file and key; a camera that gives no mask (a static one, the
// AprilTag tracker) turns occlusion off with a warning when the file asked for it.
TEST(OcclusionRender, BadSettingsAndCamerasWithoutAMaskAreNamed) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const fs::path dir = fs::temp_directory_path() / "marionette_occlusion_settings_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  fs::create_directories(dir / "empty");
  cv::Mat grey(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
  ASSERT_TRUE(cv::imwrite((dir / "frames" / "frame_0000.png").string(), grey));
  std::ofstream(dir / "middleware.json") << R"({ "characters": [ { "name": "bcn",
      "asset": ")" << assimpModel("X/BCN_Epileptic.X") << R"(", "position": [0, 0.99, 0], "play": [] } ] })";
  auto run = [&](const std::string& camera, const std::string& background, const std::string& occlusion) {
    std::ofstream(dir / "scene.json") << R"({ "scene": "middleware.json", "camera": )" << camera
                                      << R"(, "background": )" << background
                                      << R"(, "render": { "width": 160, "height": 120, "occlusion": )" << occlusion << " } }";
    return runAr((dir / "scene.json").string() + " --headless --frames 1 --out " + (dir / "out").string());
  };
  const std::string still = R"({"position": [0, 1.5, 4], "target": [0, 1, 0]})";
  const std::string color = R"({"kind": "color", "color": [0.5, 0.5, 0.5]})";
  for (const char* bad : {R"("yes")", R"({"height": -1})", R"({"height": "high"})", R"({"enabled": 1})",
                          R"({"masks": 3})"}) {
    const CliRun r = run(still, color, bad);
    EXPECT_EQ(r.status, 2) << bad << "\n" << r.out;
    EXPECT_NE(r.out.find("scene.json"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("render.occlusion"), std::string::npos) << bad << "\n" << r.out;
  }
  for (const std::string& folder : {(dir / "missing").string(), (dir / "empty").string()}) {
    const CliRun r = run(still, color, R"({"masks": ")" + folder + R"("})");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("render.occlusion.masks: '" + folder + "'"), std::string::npos) << r.out;
  }
  const CliRun unknown = run(still, color, R"({"depth": 1})");  // an unknown key: a warning
  EXPECT_EQ(unknown.status, 0) << unknown.out;
  EXPECT_NE(unknown.out.find("render.occlusion"), std::string::npos) << unknown.out;

  const CliRun staticCamera = run(still, color, "true");
  EXPECT_EQ(staticCamera.status, 0) << staticCamera.out;
  EXPECT_NE(staticCamera.out.find("only a markerless tracker"), std::string::npos) << staticCamera.out;
  const std::string frames = R"({"kind": "sequence", "file": ")" + (dir / "frames").string() + R"(", "fps": 30})";
  const CliRun tag = run(R"({"tracker": {"kind": "apriltag", "camera": ")" +
                             sourceFile("assets/cameras/synthetic_640x480.yml") + R"(", "tagSize": 0.1}})",
                         frames, "true");
  EXPECT_EQ(tag.status, 0) << tag.out;
  EXPECT_NE(tag.out.find("the AprilTag tracker has no image of its target"), std::string::npos) << tag.out;
  EXPECT_EQ(tag.out.find("occlusion over the target: on"), std::string::npos) << tag.out;
}

}  // namespace
}  // namespace marionette::test
