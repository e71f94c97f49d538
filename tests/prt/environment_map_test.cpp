// Loading lat-long HDR maps: formats, channels, clamping, errors, the direction convention.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <fstream>

#include "marionette/prt/environment_map.hpp"
#include "image_test_util.hpp"
#include "test_data.hpp"

using namespace marionette::prt;
namespace mt = marionette::test;
namespace fs = std::filesystem;

using marionette::prt::test::mentions;
using marionette::prt::test::tempDir;
using marionette::prt::test::writeFloatImage;

namespace {
constexpr double kPi = std::numbers::pi;

}  // namespace

TEST(EnvironmentMap, DirectionConventionAndInverse) {
  auto near = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-12; };
  EXPECT_TRUE(near(EnvironmentMap::direction(0.5, 0.5), {0, 0, -1}));   // image centre: -Z
  EXPECT_TRUE(near(EnvironmentMap::direction(0.75, 0.5), {1, 0, 0}));   // right of it: +X
  EXPECT_TRUE(near(EnvironmentMap::direction(0.25, 0.5), {-1, 0, 0}));
  EXPECT_TRUE(near(EnvironmentMap::direction(0.0, 0.5), {0, 0, 1}));    // the seam: +Z
  EXPECT_TRUE(near(EnvironmentMap::direction(0.3, 0.0), {0, 1, 0}));    // top row: +Y
  EXPECT_TRUE(near(EnvironmentMap::direction(0.3, 1.0), {0, -1, 0}));
  for (double u : {0.01, 0.3, 0.5, 0.77, 0.99})
    for (double v : {0.02, 0.4, 0.5, 0.93}) {
      const glm::dvec2 back = EnvironmentMap::uv(EnvironmentMap::direction(u, v) * 3.0);
      EXPECT_NEAR(back.x, u, 1e-12);
      EXPECT_NEAR(back.y, v, 1e-12);
    }
}

TEST(EnvironmentMap, TexelSolidAnglesAreExactAndSumToFourPi) {
  const EnvironmentMap map(64, 32, std::vector<float>(64 * 32 * 3));
  double total = 0.0;
  for (int row = 0; row < 32; ++row) total += 64 * map.texelSolidAngle(row);
  EXPECT_NEAR(total, 4.0 * kPi, 1e-12);
  // Row 0: the cap theta in [0, pi/32] split into 64: 2 pi (1 - cos(pi/32)) / 64.
  EXPECT_NEAR(map.texelSolidAngle(0), 2.0 * kPi * (1.0 - std::cos(kPi / 32)) / 64, 1e-16);
  EXPECT_NEAR(map.texelSolidAngle(5), map.texelSolidAngle(26), 1e-15);  // symmetric about the equator
}

TEST(EnvironmentMap, BilinearSampleHitsTexelCentresAndWraps) {
  std::vector<float> px(8 * 4 * 3);
  for (int i = 0; i < 8 * 4; ++i) px[i * 3] = static_cast<float>(i), px[i * 3 + 1] = 1.0f, px[i * 3 + 2] = 2.0f;
  const EnvironmentMap map(8, 4, px);
  EXPECT_NEAR(map.sample(map.texelDirection(3, 2)).r, map.texel(3, 2).r, 1e-5);
  // Halfway between the last and the first column of row 1 (the seam): their mean.
  const glm::vec3 seam = map.sample(EnvironmentMap::direction(0.0, 1.5 / 4));
  EXPECT_NEAR(seam.r, 0.5 * (map.texel(7, 1).r + map.texel(0, 1).r), 1e-5);
  EXPECT_NEAR(seam.g, 1.0f, 1e-6);
}

TEST(EnvironmentMap, LoadsTheSharedHdrAndDwabExrMaps) {
  for (const char* name : {"quarry_01_1k.hdr", "royal_esplanade_1k.hdr", "blender_studiolight_forest.exr"}) {
    const std::string path = mt::sharedAsset(std::string("envmaps/") + name);
    MARIONETTE_REQUIRE_FILE(path);
    auto load = loadEnvironmentMap(path);
    ASSERT_TRUE(load.map) << load.diagnostics.format();
    if (std::string(name) == "blender_studiolight_forest.exr") {
      // DWAB is lossy: its ringing leaves 784 slightly negative values, clamped with a warning.
      EXPECT_TRUE(mentions(load.diagnostics, "784 pixel values clamped to 0 (784 negative")) << load.diagnostics.format();
    } else {
      EXPECT_FALSE(load.diagnostics.hasWarnings()) << load.diagnostics.format();
    }
    EXPECT_EQ(load.map->width(), 1024);
    EXPECT_EQ(load.map->height(), 512);
    double maxValue = 0.0, sum = 0.0;
    for (float v : load.map->pixels()) {
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << name;
      maxValue = std::max(maxValue, static_cast<double>(v));
      sum += v;
    }
    EXPECT_GT(sum, 0.0) << name;
    if (std::string(name) == "royal_esplanade_1k.hdr") {  // the sun, per ASSETS.md about 3.9e4
      EXPECT_GT(maxValue, 2e4);
      EXPECT_LT(maxValue, 6e4);
    }
  }
}

TEST(EnvironmentMap, LoadsEveryBlenderStudiolightDwabExr) {
  for (const char* name : {"city.exr", "courtyard.exr", "forest.exr", "interior.exr", "night.exr", "studio.exr",
                           "sunrise.exr", "sunset.exr"}) {
    const std::string path = mt::blenderStudiolight(name);
    MARIONETTE_REQUIRE_FILE(path);
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("compression"), "dwab") << path;
    auto load = loadEnvironmentMap(path);
    ASSERT_TRUE(load.map) << load.diagnostics.format();
    EXPECT_EQ(load.map->width(), 1024);
  }
}

TEST(EnvironmentMap, NanInfAndNegativeValuesAreClampedWithOneWarningNamingTheFile) {
  // A float EXR holds them all (Radiance RGBE cannot store NaN, Inf or negatives).
  const fs::path dir = tempDir("env_clamp");
  const std::string path = (dir / "bad.exr").string();
  std::vector<float> px(16 * 8 * 3, 0.5f);
  px[0] = std::numeric_limits<float>::quiet_NaN();
  px[4] = std::numeric_limits<float>::infinity();
  px[8] = -3.0f;
  px[9] = -std::numeric_limits<float>::infinity();
  writeFloatImage(path, 16, 8, 3, px);
  auto load = loadEnvironmentMap(path);
  ASSERT_TRUE(load.map) << load.diagnostics.format();
  for (float v : load.map->pixels()) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << path;
  EXPECT_EQ(load.map->pixels()[0], 0.0f);
  EXPECT_EQ(load.map->pixels()[4], 0.0f);  // +Inf -> 0 (documented choice)
  EXPECT_EQ(load.map->pixels()[8], 0.0f);
  EXPECT_EQ(load.map->pixels()[9], 0.0f);
  EXPECT_EQ(load.map->pixels()[1], 0.5f);
  EXPECT_EQ(load.map->pixels()[10], 0.5f);
  ASSERT_EQ(load.diagnostics.items.size(), 1u) << load.diagnostics.format();
  EXPECT_EQ(load.diagnostics.items[0].severity, marionette::Severity::Warning);
  EXPECT_EQ(load.diagnostics.items[0].file, path);
  EXPECT_TRUE(mentions(load.diagnostics, "4 pixel values clamped to 0 (1 negative, 1 NaN, 2 infinite)"))
      << load.diagnostics.format();
}

TEST(EnvironmentMap, OneAndFourChannelImagesBecomeRgb) {
  const fs::path dir = tempDir("env_channels");
  const std::string grey = (dir / "grey.exr").string(), rgba = (dir / "rgba.exr").string();
  writeFloatImage(grey, 4, 2, 1, {1, 2, 3, 4, 5, 6, 7, 8});
  std::vector<float> four(4 * 2 * 4);
  for (int i = 0; i < 8; ++i) four[i * 4] = 1.0f, four[i * 4 + 1] = 2.0f, four[i * 4 + 2] = 3.0f, four[i * 4 + 3] = 0.25f;
  writeFloatImage(rgba, 4, 2, 4, four);
  auto g = loadEnvironmentMap(grey);
  ASSERT_TRUE(g.map) << g.diagnostics.format();
  EXPECT_EQ(g.map->texel(2, 1), glm::vec3(7.0f));
  auto c = loadEnvironmentMap(rgba);
  ASSERT_TRUE(c.map) << c.diagnostics.format();
  EXPECT_EQ(c.map->pixels().size(), 4u * 2 * 3);
  EXPECT_EQ(c.map->texel(3, 1), glm::vec3(1.0f, 2.0f, 3.0f));
}

TEST(EnvironmentMap, OtherAspectRatiosLoadWithAWarning) {
  const fs::path dir = tempDir("env_aspect");
  const std::string path = (dir / "square.exr").string();
  writeFloatImage(path, 8, 8, 3, std::vector<float>(8 * 8 * 3, 1.0f));
  auto load = loadEnvironmentMap(path);
  ASSERT_TRUE(load.map);
  ASSERT_TRUE(load.diagnostics.hasWarnings());
  EXPECT_TRUE(mentions(load.diagnostics, "not 2:1")) << load.diagnostics.format();
  EXPECT_TRUE(mentions(load.diagnostics, path));
}

TEST(EnvironmentMap, ErrorsNameTheFile) {
  const fs::path dir = tempDir("env_errors");
  const std::string missing = (dir / "no_such_map.hdr").string();
  auto a = loadEnvironmentMap(missing);
  EXPECT_FALSE(a.map);
  EXPECT_FALSE(a.diagnostics.ok());
  EXPECT_TRUE(mentions(a.diagnostics, missing)) << a.diagnostics.format();
  EXPECT_TRUE(mentions(a.diagnostics, "not found"));

  const std::string garbage = (dir / "garbage.exr").string();
  { std::ofstream(garbage) << "this is not an EXR file at all"; }
  auto b = loadEnvironmentMap(garbage);
  EXPECT_FALSE(b.map);
  EXPECT_TRUE(mentions(b.diagnostics, garbage)) << b.diagnostics.format();

  // A truncated real file: header fine, pixels cut off.
  const std::string source = mt::sharedAsset("envmaps/blender_studiolight_forest.exr");
  MARIONETTE_REQUIRE_FILE(source);
  const std::string truncated = (dir / "truncated.exr").string();
  const std::string bytes = mt::readFile(source);
  { std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 3); }
  auto c = loadEnvironmentMap(truncated);
  EXPECT_FALSE(c.map);
  EXPECT_TRUE(mentions(c.diagnostics, truncated)) << c.diagnostics.format();
}

// Found by fuzz_environment_map: OpenEXR allocates a header attribute at its declared size
// before reading it, so 60 bytes asked for 1.7 GB; a name over 31 characters (without the
// long-names flag) is cut short and its rest read as the size; a channel list runs past its
// declared size (OpenEXR reads it to its end), putting the next size anywhere. The header is
// checked first.
TEST(EnvironmentMap, ExrAttributeLargerThanTheFileIsAnErrorBeforeDecoding) {
  const fs::path dir = tempDir("env_exr_attribute");
  const std::string path = (dir / "huge_attribute.exr").string();
  std::string bytes("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  bytes += std::string("capDate\0string\0", 15) + std::string("\x00\x00\xe3\x66", 4) + "2026:12:01 19:32:12";
  { std::ofstream(path, std::ios::binary) << bytes; }
  const auto r = loadEnvironmentMap(path);
  EXPECT_FALSE(r.map);
  EXPECT_TRUE(mentions(r.diagnostics, path)) << r.diagnostics.format();
  EXPECT_TRUE(mentions(r.diagnostics, "attribute 'capDate' (string) declares 1726152704 bytes")) << r.diagnostics.format();

  const std::string longName = (dir / "long_name.exr").string();
  bytes = std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + "cha" + std::string(60, 'x') + "nnels" +
          std::string("\0chlist\0\x13\0\0\0", 12) + std::string(19, '\0') + std::string(1, '\0');
  { std::ofstream(longName, std::ios::binary) << bytes; }
  const auto l = loadEnvironmentMap(longName);
  EXPECT_FALSE(l.map);
  EXPECT_TRUE(mentions(l.diagnostics, longName)) << l.diagnostics.format();
  EXPECT_TRUE(mentions(l.diagnostics, "longer than 31 characters")) << l.diagnostics.format();

  const std::string longList = (dir / "long_channel_list.exr").string();
  bytes = std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + std::string("channels\0chlist\0\x13\0\0\0", 20) +
          "Y" + std::string(18, '\x01') + std::string("\0\0\0\0", 4) + std::string(40, '\xe9');
  { std::ofstream(longList, std::ios::binary) << bytes; }
  const auto c = loadEnvironmentMap(longList);
  EXPECT_FALSE(c.map);
  EXPECT_TRUE(mentions(c.diagnostics, longList)) << c.diagnostics.format();
  EXPECT_TRUE(mentions(c.diagnostics, "attribute 'channels' (chlist) declares 19 bytes but holds")) << c.diagnostics.format();
}

// fuzz_environment_map, long run: a 900-byte EXR whose data window OpenEXR sized a 1.3 GB
// chunk table from when OpenImageIO opened it, before the size could be checked. The data
// window, and tiles too small to be real, are checked from the header first.
TEST(EnvironmentMap, ExrDataWindowOverTheLimitIsAnErrorBeforeDecoding) {
  const fs::path dir = tempDir("env_exr_window");
  auto le32 = [](std::int32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i) s[static_cast<std::size_t>(i)] = static_cast<char>((static_cast<std::uint32_t>(v) >> (8 * i)) & 0xFF);
    return s;
  };
  const std::string magic("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);
  const std::string window = (dir / "huge_window.exr").string();
  {
    std::ofstream(window, std::ios::binary) << magic << std::string("dataWindow\0box2i\0", 17) << le32(16) << le32(0)
                                            << le32(0) << le32(15) << le32(200000000) << std::string(1, '\0');
  }
  const auto w = loadEnvironmentMap(window);
  EXPECT_FALSE(w.map);
  EXPECT_TRUE(mentions(w.diagnostics, window)) << w.diagnostics.format();
  EXPECT_TRUE(mentions(w.diagnostics, "data window that is 16x200000001 pixels, more than the library reads"))
      << w.diagnostics.format();

  const std::string tiles = (dir / "tiny_tiles.exr").string();
  {
    std::ofstream(tiles, std::ios::binary) << magic << std::string("tiles\0tiledesc\0", 15) << le32(9) << le32(1)
                                           << le32(1) << std::string(1, '\0') << std::string(1, '\0');
  }
  const auto t = loadEnvironmentMap(tiles);
  EXPECT_FALSE(t.map);
  EXPECT_TRUE(mentions(t.diagnostics, "OpenEXR tiles of 1x1 pixels, fewer than 8 a side")) << t.diagnostics.format();
}
