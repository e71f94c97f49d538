// The augmentation file (examples/ar/authoring/include/marionette_ar/authoring/augmentation.hpp):
// a round trip that keeps every float's bits, and bad files first: each is an error naming the
// file and the key, never a crash or a silent drop.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "marionette_ar/authoring/augmentation.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

Augmentation sample() {
  Augmentation a;
  a.tracker.kind = "markerless";
  a.tracker.camera = "/data/camera.yml";
  a.tracker.map = "/data/poster.map";
  a.tracker.mapCrc32 = "0a1b2c3d";
  a.exposureEv = -0.35f;
  a.environment = "/data/forest.exr";
  PlacedCharacter c;
  c.name = "bcn";
  c.asset = "/data/BCN.x";
  c.bml = "/data/wave.xml";
  c.placement.position = {0.1f, 0.0f, -0.25f};
  c.placement.rotation = ga::rotation(ga::kPlaneY<float>, 0.7f);
  c.placement.scale = 0.0123f;
  a.characters.push_back(c);
  return a;
}

// The first diagnostic, which must name the file and the key.
void expectError(const std::string& json, const std::string& key) {
  Diagnostics d;
  const auto a = parseAugmentation(json, "aug.json", d);
  EXPECT_FALSE(a) << json;
  EXPECT_FALSE(d.ok());
  EXPECT_EQ(d.format().rfind("aug.json", 0), 0u) << d.format();
  EXPECT_NE(d.format().find(key), std::string::npos) << "expected '" << key << "' in: " << d.format();
}

TEST(AugmentationFile, RoundTripKeepsEveryBit) {
  std::mt19937 rng(9);
  std::normal_distribution<float> n(0, 1);
  for (int i = 0; i < 2000; ++i) {
    Augmentation a = sample();
    PlacedCharacter& c = a.characters[0];
    c.placement.position = {n(rng) * 3, n(rng) * 1e-6f, n(rng)};
    c.placement.rotation = ga::Rotor{n(rng), n(rng), n(rng), n(rng)}.normalized();
    c.placement.scale = std::abs(n(rng)) + 1e-3f;
    a.exposureEv = n(rng);
    Diagnostics d;
    const auto back = parseAugmentation(formatAugmentation(a), "/data/aug.json", d);
    ASSERT_TRUE(back) << d.format();
    ASSERT_TRUE(d.ok()) << d.format();
    const Placement& p = back->characters[0].placement;
    ASSERT_EQ(std::memcmp(&p.position, &c.placement.position, sizeof p.position), 0) << i;
    ASSERT_EQ(std::memcmp(&p.rotation, &c.placement.rotation, sizeof p.rotation), 0) << i;
    ASSERT_EQ(std::memcmp(&p.scale, &c.placement.scale, sizeof p.scale), 0) << i;
    ASSERT_EQ(std::memcmp(&back->exposureEv, &a.exposureEv, sizeof a.exposureEv), 0) << i;
  }
  // Everything else comes back too.
  const Augmentation a = sample();
  Diagnostics d;
  const auto back = parseAugmentation(formatAugmentation(a), "/data/aug.json", d);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->tracker.kind, "markerless");
  EXPECT_EQ(back->tracker.camera, a.tracker.camera);
  EXPECT_EQ(back->tracker.map, a.tracker.map);
  EXPECT_EQ(back->tracker.mapCrc32, a.tracker.mapCrc32);
  EXPECT_EQ(back->environment, a.environment);
  EXPECT_EQ(back->characters[0].name, "bcn");
  EXPECT_EQ(back->characters[0].asset, a.characters[0].asset);
  EXPECT_EQ(back->characters[0].bml, a.characters[0].bml);
}

TEST(AugmentationFile, WrittenAndReadWithPathsBesideIt) {
  const std::string dir = ::testing::TempDir() + "marionette_augmentation/";
  std::filesystem::create_directories(dir);
  Augmentation a = sample();
  a.tracker.camera = "camera.yml";  // relative: beside the file
  a.characters[0].asset = "characters/BCN.x";
  Diagnostics d;
  ASSERT_TRUE(writeAugmentation(dir + "aug.json", a, d)) << d.format();
  const auto back = readAugmentation(dir + "aug.json", d);
  ASSERT_TRUE(back) << d.format();
  EXPECT_EQ(back->tracker.camera, (std::filesystem::path(dir) / "camera.yml").lexically_normal().string());
  EXPECT_EQ(back->characters[0].asset, (std::filesystem::path(dir) / "characters/BCN.x").lexically_normal().string());
  Diagnostics bad;
  EXPECT_FALSE(writeAugmentation(dir + "no/such/folder/aug.json", a, bad));
  EXPECT_NE(bad.format().find("no/such/folder/aug.json"), std::string::npos);
  Diagnostics missing;
  EXPECT_FALSE(readAugmentation(dir + "absent.json", missing));
  EXPECT_NE(missing.format().find("absent.json"), std::string::npos);
}

TEST(AugmentationFile, BadFilesNameTheKey) {
  const std::string good = formatAugmentation(sample());
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  expectError("", "not JSON");
  expectError("[1, 2]", "JSON object");
  expectError(good.substr(0, good.size() / 2), "not JSON");  // truncated
  expectError(with("\"marionette-augmentation\"", "\"marionette-scene\""), "format");
  expectError(with("\"version\": 1", "\"version\": 2"), "newer marionette");
  expectError(with("\"version\": 1", "\"version\": \"1\""), "version");
  expectError(with("\"kind\": \"markerless\"", "\"kind\": \"vuforia\""), "tracker.kind");
  expectError(with("\"map\": ", "\"mop\": "), "tracker.map");
  expectError(with("\"0a1b2c3d\"", "\"0A1B2C3D\""), "tracker.mapCrc32");
  expectError(with("\"exposure\": ", "\"exposure\": 99, \"x\": "), "exposure");
  expectError(with("\"characters\": [", "\"characters\": 5, \"c\": ["), "characters");
  expectError(with("\"name\": \"bcn\"", "\"name\": \"\""), "characters[0].name");
  expectError(with("\"asset\": ", "\"assets\": "), "characters[0].asset");
  expectError(with("\"scale\": ", "\"scale\": -1, \"s\": "), "characters[0].scale");
  // A rotor of 3 numbers, and one that is not unit (an edit by hand, or damage).
  const std::string rotorKey = "\"rotor\": [";
  const auto at = good.find(rotorKey);
  ASSERT_NE(at, std::string::npos);
  std::string three = good;
  three.replace(at, rotorKey.size(), "\"rotor\": [0.5, 0.5, 0.5], \"r\": [");
  expectError(three, "characters[0].rotor");
  std::string scaled = good;
  scaled.replace(at, rotorKey.size(), "\"rotor\": [2, 0, 0, 0], \"r\": [");
  expectError(scaled, "not a unit rotor");
  // Two characters of one name.
  Augmentation twice = sample();
  twice.characters.push_back(twice.characters[0]);
  expectError(formatAugmentation(twice), "characters[1].name");
  // Infinity is not a number JSON has; a huge one is out of range.
  expectError(with("\"scale\": ", "\"scale\": 1e999, \"s\": "), "");
  // An unknown key is a warning, and the file still reads.
  Diagnostics d;
  EXPECT_TRUE(parseAugmentation(with("\"exposure\": ", "\"exposur\": 1, \"exposure\": "), "aug.json", d));
  EXPECT_TRUE(d.hasWarnings());
  EXPECT_NE(d.format().find("'exposur'"), std::string::npos) << d.format();
}

}  // namespace
