// marionette-ar on the default scene, looked at as a person would: the frames
// it writes headless show a lit character of plausible size that moves, over a
// background that shows elsewhere. Bad scene files get clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "marionette_ar/render/image.hpp"
#include "ar_run.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

double luminance(const ar::Image8& im, std::size_t pixel) {
  const std::size_t i = pixel * std::size_t(im.channels);
  return (0.2126 * im.pixels[i] + 0.7152 * im.pixels[i + 1] + 0.0722 * im.pixels[i + 2]) / 255.0;
}

// Character pixels: where the frame differs from the same frame drawn without characters.
std::vector<bool> characterMask(const ar::Image8& with, const ar::Image8& without) {
  std::vector<bool> mask(std::size_t(with.width * with.height), false);
  for (std::size_t p = 0; p < mask.size(); ++p)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(with.pixels[p * std::size_t(with.channels) + std::size_t(c)]) -
                   int(without.pixels[p * std::size_t(without.channels) + std::size_t(c)])) > 6)
        mask[p] = true;
  return mask;
}

TEST(ArScene, DefaultSceneLooksRight) {
  const std::string scene = sourceFile("assets/scenes/ar_demo.json");
  MARIONETTE_REQUIRE_FILE(scene);
  const fs::path dir = fs::temp_directory_path() / "marionette_ar_scene_test";
  fs::remove_all(dir);
  const int frames = 150;  // 5 s at 30 fps: the walk is under way
  const std::string common = scene + " --headless --frames " + std::to_string(frames) + " --width 480 --height 270";
  const CliRun with = runAr(common + " --out " + (dir / "with").string());
  ASSERT_EQ(with.status, 0) << with.out;
  // No runtime or BML warning. (Blender's forest.exr has 784 negative pixels; the
  // loader's warning about clamping them is expected and names the map.)
  std::istringstream lines(with.out);
  for (std::string line; std::getline(lines, line);)
    if (line.find("warning") != std::string::npos && line.find("forest.exr") == std::string::npos)
      ADD_FAILURE() << "unexpected warning: " << line;
  const CliRun without = runAr(common + " --hide-characters --out " + (dir / "without").string());
  ASSERT_EQ(without.status, 0) << without.out;
  ASSERT_TRUE(fs::exists(dir / "with" / "frame_0149.png"));

  std::vector<std::vector<bool>> masks;
  for (int f : {30, 90, 149}) {
    const ar::Image8 a = frame(dir / "with", f), b = frame(dir / "without", f);
    ASSERT_EQ(a.width, 480);
    ASSERT_EQ(a.height, 270);
    const std::vector<bool> mask = characterMask(a, b);
    std::size_t covered = 0, black = 0, saturated = 0;
    double lum = 0.0;
    std::vector<double> backgroundLum;
    for (std::size_t p = 0; p < mask.size(); ++p) {
      if (!mask[p]) {
        backgroundLum.push_back(luminance(a, p));
        continue;
      }
      ++covered;
      const double l = luminance(a, p);
      lum += l;
      black += l < 0.02;
      saturated += l > 0.98;
    }
    const double fraction = double(covered) / double(mask.size());
    SCOPED_TRACE("frame " + std::to_string(f));
    EXPECT_GT(fraction, 0.003) << "the character is too small to see";
    EXPECT_LT(fraction, 0.5) << "the character fills the frame";
    ASSERT_GT(covered, 0u);
    const double meanLum = lum / double(covered);
    EXPECT_GT(meanLum, 0.08) << "the character is unlit";
    EXPECT_LT(meanLum, 0.9) << "the character is blown out";
    EXPECT_LT(double(black) / double(covered), 0.1);
    EXPECT_LT(double(saturated) / double(covered), 0.05);
    // The background shows around the character, and it is an image, not a flat fill.
    double mean = 0.0, var = 0.0;
    for (double l : backgroundLum) mean += l;
    mean /= double(backgroundLum.size());
    for (double l : backgroundLum) var += (l - mean) * (l - mean);
    EXPECT_GT(std::sqrt(var / double(backgroundLum.size())), 0.02) << "the background is flat";
    EXPECT_GT(mean, 0.02) << "the background is black";
    masks.push_back(mask);
  }
  // The character moves: its silhouette changes between frames.
  for (std::size_t k = 1; k < masks.size(); ++k) {
    std::size_t changed = 0;
    for (std::size_t p = 0; p < masks[k].size(); ++p) changed += masks[k][p] != masks[k - 1][p];
    EXPECT_GT(double(changed) / double(masks[k].size()), 0.002) << "no motion between sampled frames " << k;
  }
}

// Mean luminance over the pixels a mask marks.
double meanLuminance(const ar::Image8& image, const std::vector<bool>& mask) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < mask.size(); ++p)
    if (mask[p]) sum += luminance(image, p), ++n;
  return n ? sum / double(n) : 0.0;
}

TEST(ArScene, ExposureScalesTheLight) {
  const std::string scene = sourceFile("assets/scenes/ar_demo.json");
  MARIONETTE_REQUIRE_FILE(scene);
  const fs::path dir = fs::temp_directory_path() / "marionette_ar_exposure_test";
  fs::remove_all(dir);
  const std::string common = scene + " --headless --frames 60 --width 320 --height 180";
  ASSERT_EQ(runAr(common + " --out " + (dir / "normal").string()).status, 0);
  ASSERT_EQ(runAr(common + " --exposure 0.25 --out " + (dir / "dark").string()).status, 0);
  ASSERT_EQ(runAr(common + " --hide-characters --out " + (dir / "plate").string()).status, 0);
  const ar::Image8 normal = frame(dir / "normal", 59), dark = frame(dir / "dark", 59), plate = frame(dir / "plate", 59);
  const std::vector<bool> mask = characterMask(normal, plate);
  EXPECT_LT(meanLuminance(dark, mask), 0.75 * meanLuminance(normal, mask)) << "exposure does not darken the character";
}

TEST(ArScene, PhotoBackgroundCoversTheFrame) {
  // A still photo (written here: a colour ramp) behind the scene, drawn without characters,
  // fills the frame: same aspect ratio, so the picture is the photo itself.
  const fs::path dir = fs::temp_directory_path() / "marionette_ar_photo_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ar::Image8 photo;
  photo.width = 320, photo.height = 180, photo.channels = 3;
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x)
      for (int c = 0; c < 3; ++c)
        photo.pixels.push_back(static_cast<std::uint8_t>(c == 0 ? x * 255 / 319 : c == 1 ? y * 255 / 179 : 128));
  Diagnostics error;
  ASSERT_TRUE(ar::writeImage((dir / "photo.png").string(), photo, error)) << error.format();
  std::ofstream(dir / "photo_scene.json") << R"({"scene": ")" << sourceFile("assets/scenes/ar_demo_walk.json")
                                          << R"(", "background": {"kind": "image", "file": "photo.png"}})";
  const CliRun r = runAr((dir / "photo_scene.json").string() +
                         " --headless --frames 1 --width 320 --height 180 --hide-characters --out " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.out;
  const ar::Image8 shown = frame(dir / "out", 0);
  ASSERT_EQ(shown.width * shown.height, photo.width * photo.height);
  double diff = 0.0;  // readImage gives RGBA, the photo is RGB
  for (std::size_t p = 0; p < std::size_t(photo.width * photo.height); ++p)
    for (std::size_t c = 0; c < 3; ++c)
      diff += std::abs(int(shown.pixels[p * std::size_t(shown.channels) + c]) - int(photo.pixels[p * 3 + c]));
  EXPECT_LT(diff / double(photo.pixels.size()), 2.0) << "the photo is not drawn as it is (flipped, stretched, tinted)";
}

TEST(ArScene, WindowAndScreenshot) {
  // Windowed mode (a real window on the X display) and --screenshot.
  const std::string scene = sourceFile("assets/scenes/ar_demo.json");
  MARIONETTE_REQUIRE_FILE(scene);
  const fs::path shot = fs::temp_directory_path() / "marionette_ar_screenshot.png";
  fs::remove(shot);
  const CliRun r = runAr(scene + " --frames 10 --width 320 --height 180 --screenshot " + shot.string());
  ASSERT_EQ(r.status, 0) << r.out;
  ar::Image8 image;
  Diagnostics error;
  ASSERT_TRUE(ar::readImage(shot.string(), image, error)) << error.format();
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 180);
}

TEST(ArScene, BadInputIsNamed) {
  const fs::path dir = fs::temp_directory_path() / "marionette_ar_bad_input";
  fs::create_directories(dir);
  CliRun r = runAr((dir / "missing.json").string() + " --headless --out " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("missing.json"), std::string::npos) << r.out;

  std::ofstream(dir / "bad.json") << R"({"scene": "nowhere.json", "camera": {"position": [0, 1, "x"], "fovY": 400},
                                         "background": {"kind": "hologram"}})";
  r = runAr((dir / "bad.json").string() + " --headless --out " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("camera.position"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("camera.fovY"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("hologram"), std::string::npos) << r.out;

  r = runAr("--frames -3");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--frames"), std::string::npos) << r.out;

  std::ofstream(dir / "noscene.json") << R"({"scene": "nowhere.json"})";
  r = runAr((dir / "noscene.json").string() + " --headless --out " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("nowhere.json"), std::string::npos) << r.out;
}

// A live camera background, end to end. No camera here: opencv-doc's tree.avi (68 frames)
// opened as a stream URL (file://, FFmpeg) stands in for one, so this covers the renderer's
// side (the source opened headless, its frames drawn, the stream's end reported once while the
// last frame stays) but not V4L2 capture. FFmpeg decodes the file faster than a camera gives
// frames, so which frames the 12 written ones show depends on timing: not asserted here
// (LiveCamera.* checks the hand-over). Missing devices are named.
TEST(ArScene, LiveCameraBackground) {
  const std::string video = "/usr/share/doc/opencv-doc/examples/data/tree.avi";  // Debian opencv-doc
  MARIONETTE_REQUIRE_FILE(video);
  const fs::path dir = fs::temp_directory_path() / "marionette_ar_live_camera_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "empty.json") << R"({ "characters": [] })";
  auto scene = [&](const std::string& name, const std::string& device) {
    std::ofstream(dir / name) << R"({ "scene": "empty.json", "background": { "kind": "camera", "device": )" << device
                              << R"(, "timeoutSeconds": 2 }, "render": { "width": 320, "height": 240, "fps": 30 } })";
    return (dir / name).string();
  };
  const CliRun live = runAr(scene("live.json", "\"file://" + video + "\"") + " --headless --frames 12 --out " +
                            (dir / "frames").string());
  ASSERT_EQ(live.status, 0) << live.out;
  for (int i : {0, 11}) {
    const ar::Image8 image = frame(dir / "frames", i);
    ASSERT_EQ(image.width, 320);
    double bright = 0;
    for (std::uint8_t v : image.pixels) bright += v;
    EXPECT_GT(bright / double(image.pixels.size()), 20.0) << "frame " << i << ": the camera frame is not drawn";
  }
  const std::string ended = "file://" + video + ": error: stopped delivering frames after 68 (grab failed); the last frame stays";
  const std::size_t at = live.out.find(ended);
  EXPECT_NE(at, std::string::npos) << live.out;
  EXPECT_EQ(live.out.find(ended, at + 1), std::string::npos) << "reported twice: " << live.out;

  const CliRun missing = runAr(scene("missing.json", "\"/dev/video99\"") + " --headless --frames 2 --out " +
                               (dir / "m").string());
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.out.find("/dev/video99: error: no such device"), std::string::npos) << missing.out;
  const CliRun index = runAr(scene("index.json", "7") + " --headless --frames 2 --out " + (dir / "i").string());
  EXPECT_EQ(index.status, 2);
  EXPECT_NE(index.out.find("camera 7 (/dev/video7): error: no such device"), std::string::npos) << index.out;
  const CliRun bad = runAr(scene("bad.json", "\"camera.mp4\"") + " --headless --frames 2 --out " + (dir / "b").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("'background.device': 'camera.mp4' is neither a /dev/ path nor a stream URL"),
            std::string::npos) << bad.out;
}

}  // namespace
}  // namespace marionette::test
