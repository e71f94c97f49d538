// marionette-ar's contact shadows (docs/ar-renderer.md, "Contact shadows"), rendered: BCN
// standing on a grey floor under Poly Haven's quarry probe (a sun), seen from above and in
// front. With shadows the floor is darker under and beside the feet and unchanged far away;
// the shadow turns with the light; a hidden character casts none.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ar_run.hpp"
#include "marionette_ar/render/image.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 400, kHeight = 300;

double luminance(const ar::Image8& im, std::size_t pixel) {
  const std::size_t i = pixel * std::size_t(im.channels);
  return (0.2126 * im.pixels[i] + 0.7152 * im.pixels[i + 1] + 0.0722 * im.pixels[i + 2]) / 255.0;
}

class ContactShadowRender : public ::testing::Test {
 protected:
  void SetUp() override {
    bcn_ = assimpModel("X/BCN_Epileptic.X");
    quarry_ = sharedAsset("envmaps/quarry_01_1k.hdr");
    MARIONETTE_REQUIRE_FILE(bcn_);
    MARIONETTE_REQUIRE_FILE(quarry_);
    dir_ = fs::temp_directory_path() /
           (std::string("marionette_contact_shadow_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // BCN's origin is its pelvis, 0.99 m above its feet: placed there it stands on y = 0.
    std::ofstream(dir_ / "bcn.json") << R"({"characters": [{"name": "bcn", "asset": ")" << bcn_
                                     << R"(", "position": [0, 0.99, 0], "play": []}]})";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A static camera 9 m in front and 4 m up, the light probe turned by `rotation` degrees (at 0
  // the quarry's sun, 13 degrees up, is behind BCN: its shadow falls toward the camera).
  std::string writeScene(const std::string& name, int rotation, const std::string& shadows) const {
    const fs::path path = dir_ / name;
    std::ofstream(path) << R"({"scene": "bcn.json",
        "camera": {"position": [0, 4.0, 9.0], "target": [0, 0.6, 0], "fovY": 45},
        "background": {"kind": "color", "color": [0.55, 0.55, 0.55]},
        "environment": {"file": ")" << quarry_ << R"(", "rotation": )" << rotation << R"(, "prt": {"mode": "off"}},
        "render": {"contactShadows": )" << shadows << "}}";
    return path.string();
  }

  ar::Image8 render(const std::string& scene, const std::string& options, const std::string& out,
                    std::string* log = nullptr) const {
    const fs::path outDir = dir_ / out;
    const CliRun r = runAr(scene + " --headless --frames 1 --width " + std::to_string(kWidth) + " --height " +
                           std::to_string(kHeight) + " " + options + " --out " + outDir.string());
    EXPECT_EQ(r.status, 0) << r.out;
    if (log) *log = r.out;
    const ar::Image8 image = frame(outDir, 0);
    if (const char* keep = std::getenv("MARIONETTE_TEST_IMAGES")) {  // to look at them
      Diagnostics ignored;
      (void)ar::writeImage(std::string(keep) + "/contact_shadow_" + out + ".png", image, ignored);
    }
    return image;
  }

  std::string bcn_, quarry_;
  fs::path dir_;
};

// What the shadow did to the floor: per pixel, luminance without minus with; character pixels
// (where the frame differs from the empty floor) are left out.
struct ShadowImage {
  std::vector<double> darkening;  // 0 on the character
  std::vector<char> character;
  int feetX = 0, feetY = 0;       // the silhouette's lowest rows, their mean column
  int characterHeight = 0;        // in pixels
  int left = kWidth, right = 0, top = kHeight, bottom = 0;
};

ShadowImage compare(const ar::Image8& off, const ar::Image8& on, const ar::Image8& floor) {
  ShadowImage s;
  const std::size_t n = std::size_t(kWidth) * kHeight;
  s.darkening.assign(n, 0.0);
  s.character.assign(n, 0);
  for (std::size_t p = 0; p < n; ++p) {
    if (std::abs(luminance(off, p) - luminance(floor, p)) > 2.0 / 255.0) {
      s.character[p] = 1;
      const int x = int(p % kWidth), y = int(p / kWidth);
      s.left = std::min(s.left, x), s.right = std::max(s.right, x);
      s.top = std::min(s.top, y), s.bottom = std::max(s.bottom, y);
      continue;
    }
    s.darkening[p] = luminance(off, p) - luminance(on, p);
  }
  s.characterHeight = s.bottom - s.top + 1;
  long sum = 0, count = 0;
  for (int y = s.bottom - s.characterHeight / 20; y <= s.bottom; ++y)
    for (int x = 0; x < kWidth; ++x)
      if (s.character[std::size_t(y) * kWidth + x]) sum += x, ++count;
  s.feetX = count ? int(sum / count) : 0;
  s.feetY = s.bottom;
  return s;
}

// The darkening's centroid relative to the feet, in pixels.
std::pair<double, double> shadowCentroid(const ShadowImage& s) {
  double w = 0, x = 0, y = 0;
  for (std::size_t p = 0; p < s.darkening.size(); ++p) {
    const double d = std::max(s.darkening[p], 0.0);
    w += d, x += d * double(p % kWidth), y += d * double(p / kWidth);
  }
  return w > 0 ? std::make_pair(x / w - s.feetX, y / w - s.feetY) : std::make_pair(0.0, 0.0);
}

TEST_F(ContactShadowRender, TheFloorIsDarkerUnderAndBesideTheFeetAndUnchangedFarAway) {
  // The sun behind the camera: the shadow falls away from it, foreshortened.
  const std::string on = writeScene("on.json", 180, "true"), off = writeScene("off.json", 180, "false");
  std::string log;
  const ar::Image8 with = render(on, "", "on", &log), without = render(off, "", "off"),
                   floor = render(off, "--hide-characters", "floor");
  EXPECT_NE(log.find("contact shadows: light from"), std::string::npos) << log;
  const ShadowImage s = compare(without, with, floor);
  ASSERT_GT(s.characterHeight, kHeight / 6) << "BCN is not in view";
  // Under and beside the feet: the floor within a quarter of the character's height of them.
  const int reach = s.characterHeight / 4;
  double nearSum = 0, nearMax = 0;
  long nearCount = 0;
  double farMax = 0;
  long farCount = 0;
  for (std::size_t p = 0; p < s.darkening.size(); ++p) {
    if (s.character[p]) continue;
    const int x = int(p % kWidth), y = int(p / kWidth);
    const int dx = std::abs(x - s.feetX), dy = std::abs(y - s.feetY);
    if (dx <= reach && dy <= reach / 2) {
      nearSum += s.darkening[p];
      nearMax = std::max(nearMax, s.darkening[p]);
      ++nearCount;
    }
    // Far: more than 2.5 times the character's height from its box (a low light's shadow reaches
    // up to about twice the height: contact_shadow.hpp's catcher).
    const int away = std::max({s.left - x, x - s.right, s.top - y, y - s.bottom});
    if (away > 5 * s.characterHeight / 2) {
      farMax = std::max(farMax, std::abs(s.darkening[p]));
      ++farCount;
    }
  }
  ASSERT_GT(nearCount, 100);
  const double nearMean = nearSum / double(nearCount);
  std::printf("contact shadow: floor near the feet darker by %.3f mean, %.3f at most (of 1); far away (%ld px) at most %.4f\n",
              nearMean, nearMax, farCount, farMax);
  // Measured: 0.012 mean over the box, 0.255 at most (the shadow leaving the feet).
  EXPECT_GT(nearMean, 0.006) << "no shadow under the feet";
  EXPECT_GT(nearMax, 0.1);
  ASSERT_GT(farCount, 1000);
  EXPECT_LE(farMax, 1.5 / 255.0) << "the shadow reaches far from the character";
  // Nowhere is the floor brighter with the shadow than without.
  EXPECT_GE(*std::min_element(s.darkening.begin(), s.darkening.end()), -1.5 / 255.0);
}

TEST_F(ContactShadowRender, TheShadowTurnsWithTheLight) {
  const ar::Image8 floor = render(writeScene("floor.json", 0, "false"), "--hide-characters", "floor");
  const ar::Image8 off = render(writeScene("off.json", 0, "false"), "", "off");
  const auto centroidAt = [&](int rotation) {
    const std::string name = "on_" + std::to_string(rotation);
    return shadowCentroid(compare(off, render(writeScene(name + ".json", rotation, "true"), "", name), floor));
  };
  const auto a = centroidAt(0), b = centroidAt(180);
  std::printf("shadow centroid from the feet: (%.1f, %.1f) px with the probe at 0 degrees, (%.1f, %.1f) at 180\n", a.first,
              a.second, b.first, b.second);
  // The probe turned half a turn moves the sun to the other side: the shadow falls the other way.
  EXPECT_GT(std::hypot(a.first - b.first, a.second - b.second), 8.0);
  EXPECT_LT(a.first * b.first + a.second * b.second, 0.0);
}

TEST_F(ContactShadowRender, AHiddenCharacterCastsNoShadow) {
  const std::string on = writeScene("on.json", 0, "true"), off = writeScene("off.json", 0, "false");
  const ar::Image8 hiddenOn = render(on, "--hide-characters", "hidden_on"),
                   hiddenOff = render(off, "--hide-characters", "hidden_off");
  ASSERT_EQ(hiddenOn.pixels.size(), hiddenOff.pixels.size());
  EXPECT_TRUE(hiddenOn.pixels == hiddenOff.pixels);
}

TEST_F(ContactShadowRender, BadSettingsAreNamed) {
  for (const char* bad : {R"("yes")", R"({"strength": 2})", R"({"softness": -1})", R"({"blur": 1})"}) {
    const std::string scene = writeScene("bad.json", 0, bad);
    const CliRun r = runAr(scene + " --headless --frames 1 --out " + (dir_ / "bad").string());
    if (std::string(bad) == R"({"blur": 1})") {  // an unknown key is a warning
      EXPECT_EQ(r.status, 0) << r.out;
      EXPECT_NE(r.out.find("render.contactShadows"), std::string::npos) << r.out;
      continue;
    }
    EXPECT_EQ(r.status, 2) << bad << "\n" << r.out;
    EXPECT_NE(r.out.find("bad.json"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("render.contactShadows"), std::string::npos) << bad << "\n" << r.out;
  }
}

}  // namespace
}  // namespace marionette::test
