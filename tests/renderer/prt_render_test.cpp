// marionette-ar with PRT lighting, on RobotExpressive in its rest pose under Blender's
// forest light: unshadowed PRT agrees with the per-fragment SH9 light, shadowed PRT only
// takes light away (and visibly so), exposure still scales it, the transfer comes from
// the cache on a relaunch, no environment means no precompute, bad settings are named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "marionette_ar/render/image.hpp"
#include "cli_run.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 240, kHeight = 320;

CliRun runAr(const std::string& args) { return runCommand(::marionette::test::programPath("marionette-ar") + " " + args); }

double luminance(const ar::Image8& im, std::size_t pixel) {
  const std::size_t i = pixel * std::size_t(im.channels);
  return (0.2126 * im.pixels[i] + 0.7152 * im.pixels[i + 1] + 0.0722 * im.pixels[i + 2]) / 255.0;
}

// A temporary folder with RobotExpressive standing in its rest pose (turned 30 degrees,
// so that the light is turned into its model frame) and an AR scene around it.
class PrtRender : public ::testing::Test {
 protected:
  void SetUp() override {
    robot_ = sharedAsset("characters/RobotExpressive.glb");
    forest_ = blenderStudiolight("forest.exr");
    MARIONETTE_REQUIRE_FILE(robot_);
    MARIONETTE_REQUIRE_FILE(forest_);
    dir_ = fs::temp_directory_path() /
           (std::string("marionette_prt_render_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "robot.json") << R"({"characters": [{"name": "robot", "asset": ")" << robot_
                                       << R"(", "heading": 30, "play": []}]})";
  }

  // An AR scene file; `environment` is the JSON of the "environment" object (empty: none).
  std::string writeScene(const std::string& name, const std::string& environment) const {
    const fs::path path = dir_ / name;
    std::ofstream out(path);
    out << R"({"scene": "robot.json", "camera": {"position": [0, 2.0, 7.5], "target": [0, 2.0, 0], "fovY": 40},
               "background": {"kind": "color", "color": [0.05, 0.05, 0.05]})";
    if (!environment.empty()) out << R"(, "environment": )" << environment;
    out << "}";
    return path.string();
  }
  std::string forestEnvironment(const std::string& prt = "") const {
    return R"({"file": ")" + forest_ + R"(", "rotation": 40)" + (prt.empty() ? "" : R"(, "prt": )" + prt) + "}";
  }

  // The transfer cache: the one ctest gives every GL test (MARIONETTE_PRT_CACHE, in the
  // build tree), so a transfer is computed once per build; the tests of the cache itself
  // (RelaunchReadsTheCache, NoEnvironment...) use a folder of their own.
  fs::path sharedCache() const {
    const char* shared = std::getenv("MARIONETTE_PRT_CACHE");
    return shared && *shared ? fs::path(shared) : dir_ / "cache";
  }

  // Renders one frame; returns it (and the program's output in `log`).
  ar::Image8 render(const std::string& scene, const std::string& options, const std::string& out,
                    std::string* log = nullptr, bool ownCache = false) const {
    const fs::path outDir = dir_ / out;
    const fs::path cache = ownCache ? dir_ / "cache" : sharedCache();
    const CliRun r = runAr(scene + " --headless --frames 1 --width " + std::to_string(kWidth) + " --height " +
                           std::to_string(kHeight) + " --prt-cache " + cache.string() + " " + options +
                           " --out " + outDir.string());
    EXPECT_EQ(r.status, 0) << r.out;
    if (log) *log = r.out;
    ar::Image8 image;
    Diagnostics error;
    EXPECT_TRUE(ar::readImage((outDir / "frame_0000.png").string(), image, error)) << error.format() << "\n" << r.out;
    if (const char* keep = std::getenv("MARIONETTE_TEST_IMAGES"))  // to look at them
      (void)ar::writeImage(std::string(keep) + "/prt_" + out + ".png", image, error);
    return image;
  }

  // Character pixels: where the frame differs from the same frame without characters.
  std::vector<std::size_t> characterPixels(const std::string& scene) const {
    const ar::Image8 with = render(scene, "--prt off", "mask_with"),
                     without = render(scene, "--prt off --hide-characters", "mask_without");
    std::vector<std::size_t> pixels;
    for (std::size_t p = 0; p < std::size_t(with.width * with.height); ++p) {
      bool differs = false;
      const std::size_t a = p * std::size_t(with.channels), b = p * std::size_t(without.channels);
      for (std::size_t c = 0; c < 3; ++c)
        differs = differs || std::abs(int(with.pixels[a + c]) - int(without.pixels[b + c])) > 6;
      if (differs) pixels.push_back(p);
    }
    return pixels;
  }

  std::string robot_, forest_;
  fs::path dir_;
};

double meanLuminance(const ar::Image8& image, const std::vector<std::size_t>& pixels) {
  double sum = 0.0;
  for (std::size_t p : pixels) sum += luminance(image, p);
  return pixels.empty() ? 0.0 : sum / double(pixels.size());
}

TEST_F(PrtRender, UnshadowedThreeBandsMatchesTheSh9Light) {
  // Unshadowed transfer in 3 bands is the SH9 irradiance exactly, evaluated per vertex (and
  // interpolated) instead of per fragment: the pictures differ only by that interpolation.
  // The robot is turned 30 degrees and the map 40: a wrong turn into the model frame shows.
  const std::string scene = writeScene("scene.json", forestEnvironment());
  const std::vector<std::size_t> character = characterPixels(scene);
  ASSERT_GT(character.size(), std::size_t(kWidth * kHeight / 20)) << "the robot covers too little of the frame";
  std::string log;
  const ar::Image8 prt = render(scene, "--prt unshadowed --prt-bands 3", "prt", &log);
  EXPECT_NE(log.find("3 bands, unshadowed"), std::string::npos) << log;
  const ar::Image8 sh9 = render(scene, "--prt off", "sh9");
  double sum = 0.0;
  std::vector<double> diffs;
  for (std::size_t p : character) diffs.push_back(std::abs(luminance(prt, p) - luminance(sh9, p)));
  for (double d : diffs) sum += d;
  std::sort(diffs.begin(), diffs.end());
  const double mean = sum / double(diffs.size()), p99 = diffs[diffs.size() * 99 / 100];
  std::printf("unshadowed n=3 PRT vs SH9 over %zu robot pixels: mean |dL| %.4f, 99th percentile %.4f, max %.4f\n",
              character.size(), mean, p99, diffs.back());
  // Measured (240x320): mean 0.0003, 99th percentile 0.0084, max 0.097 (a few silhouette pixels).
  EXPECT_LT(mean, 0.0008) << "per-vertex and per-fragment light disagree more than interpolation explains";
  EXPECT_LT(p99, 0.017);
  // And the comparison can fail: the light turned by 90 degrees more is another picture.
  const std::string turned = writeScene("turned.json", R"({"file": ")" + forest_ + R"(", "rotation": 130})");
  const ar::Image8 other = render(turned, "--prt unshadowed --prt-bands 3", "turned");
  double otherSum = 0.0;
  for (std::size_t p : character) otherSum += std::abs(luminance(other, p) - luminance(sh9, p));
  const double otherMean = otherSum / double(character.size());
  std::printf("the light turned 90 degrees more: mean |dL| %.4f\n", otherMean);
  EXPECT_GT(otherMean, 4.0 * mean) << "the test cannot tell the light's direction";
}

TEST_F(PrtRender, ShadowedOnlyTakesLightAway) {
  const std::string scene = writeScene("scene.json", forestEnvironment(R"({"rays": 256})"));
  const std::vector<std::size_t> character = characterPixels(scene);
  ASSERT_GT(character.size(), std::size_t(kWidth * kHeight / 20));
  std::string log;
  const ar::Image8 shadowed = render(scene, "", "shadowed", &log);
  EXPECT_NE(log.find("5 bands, shadowed"), std::string::npos) << log;
  const ar::Image8 unshadowed = render(scene, "--prt unshadowed", "unshadowed");
  std::size_t darker = 0, brighter = 0;
  double worstBrighter = 0.0;
  for (std::size_t p : character) {
    const double s = luminance(shadowed, p), u = luminance(unshadowed, p);
    darker += s < 0.75 * u;
    brighter += s > u + 0.02;
    worstBrighter = std::max(worstBrighter, s - u);
  }
  const double meanS = meanLuminance(shadowed, character), meanU = meanLuminance(unshadowed, character);
  std::printf("shadowed vs unshadowed over %zu robot pixels: mean luminance %.4f vs %.4f, %.2f %% at least 25 %% darker, "
              "%zu brighter by > 0.02 (most %.4f)\n",
              character.size(), meanS, meanU, 100.0 * double(darker) / double(character.size()), brighter, worstBrighter);
  // Measured: mean 0.221 vs 0.276, 27 % of the pixels at least 25 % darker, 2 pixels brighter
  // by more than 0.02 (at most 0.031: 256 rays' sampling noise on unoccluded vertices).
  EXPECT_LT(meanS, 0.9 * meanU) << "self-shadowing does not darken the robot";
  EXPECT_GT(double(darker), 0.12 * double(character.size())) << "too few pixels are in clear shadow";
  EXPECT_LT(double(brighter), 0.002 * double(character.size())) << "visibility added light";
  EXPECT_LT(worstBrighter, 0.06);
}

TEST_F(PrtRender, ExposureScalesThePrtLight) {
  const std::string scene = writeScene("scene.json", forestEnvironment(R"({"mode": "unshadowed"})"));
  const std::vector<std::size_t> character = characterPixels(scene);
  const ar::Image8 normal = render(scene, "", "normal"), bright = render(scene, "--exposure 2", "bright");
  const double n = meanLuminance(normal, character), b = meanLuminance(bright, character);
  std::printf("exposure 1: %.4f, exposure 2: %.4f\n", n, b);
  EXPECT_GT(b, 1.2 * n) << "exposure does not brighten the PRT-lit robot";
}

TEST_F(PrtRender, NoEnvironmentNoPrecomputeAndUnshadowedCastsNoRays) {
  std::string log;
  (void)render(writeScene("plain.json", ""), "", "plain", &log, /*ownCache=*/true);
  EXPECT_NE(log.find("prt off (no environment"), std::string::npos) << log;
  EXPECT_EQ(log.find("prt RobotExpressive"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir_ / "cache")) << "a scene without environment wrote a transfer";

  (void)render(writeScene("unshadowed.json", forestEnvironment(R"({"mode": "unshadowed"})")), "", "unshadowed", &log,
               /*ownCache=*/true);
  EXPECT_NE(log.find("prt RobotExpressive.glb: "), std::string::npos) << log;
  EXPECT_NE(log.find("unshadowed, "), std::string::npos) << log;
  EXPECT_NE(log.find(" s, 0 rays"), std::string::npos) << "an unshadowed transfer cast rays: " << log;
}

TEST_F(PrtRender, RelaunchReadsTheCache) {
  const std::string scene = writeScene("scene.json", forestEnvironment(R"({"rays": 64})"));
  std::string first, second;
  const ar::Image8 a = render(scene, "", "first", &first, true), b = render(scene, "", "second", &second, true);
  EXPECT_EQ(first.find("from cache"), std::string::npos) << first;
  EXPECT_NE(first.find("shadowed, "), std::string::npos) << first;
  EXPECT_EQ(first.find(" 0 rays"), std::string::npos) << "a shadowed precompute cast no rays: " << first;
  EXPECT_NE(second.find("from cache " + (dir_ / "cache").string()), std::string::npos) << second;
  EXPECT_EQ(a.pixels, b.pixels) << "the cached transfer lights differently";
  // Other settings are another cache entry: computed again.
  std::string third;
  (void)render(scene, "--prt-rays 16", "third", &third, true);
  EXPECT_EQ(third.find("from cache"), std::string::npos) << third;
}

TEST_F(PrtRender, BadPrtSettingsAreNamed) {
  struct Case {
    std::string prt, key;
  };
  for (const Case& c : {Case{R"({"bands": 9})", "environment.prt.bands"}, Case{R"({"bands": 1})", "environment.prt.bands"},
                        Case{R"({"rays": 0})", "environment.prt.rays"}, Case{R"({"rays": 70000})", "environment.prt.rays"},
                        Case{R"({"mode": "soft"})", "environment.prt.mode"}, Case{R"("yes")", "environment.prt"},
                        Case{R"({"pose": {"time": 1}})", "environment.prt.pose.clip"},
                        Case{R"({"pose": {"clip": "Moonwalk"}})", "environment.prt.pose.clip"}}) {
    const std::string scene = writeScene("bad.json", forestEnvironment(c.prt));
    const CliRun r = runAr(scene + " --headless --frames 1 --prt-cache " + (dir_ / "cache").string() + " --out " +
                           (dir_ / "bad").string());
    SCOPED_TRACE(c.prt);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("bad.json"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("'" + c.key + "'"), std::string::npos) << r.out;
  }
  const std::string scene = writeScene("good.json", forestEnvironment());
  for (const std::string option : {"--prt soft", "--prt-bands 9", "--prt-rays 0", "--prt-bands 2.5"}) {
    const CliRun r = runAr(scene + " --headless --frames 1 --out " + (dir_ / "bad").string() + " " + option);
    EXPECT_EQ(r.status, 2) << option << ": " << r.out;
    EXPECT_NE(r.out.find(option.substr(0, option.find(' '))), std::string::npos) << r.out;
  }
}

}  // namespace
}  // namespace marionette::test
