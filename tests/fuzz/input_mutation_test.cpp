// Deterministic mutation fuzzing of everything that parses input: the
// importers (GLB, glTF, FBX, BVH, X), scene files, BML blocks and the AR
// tracking's planar maps, camera calibrations and recorded pose CSVs. Each seed file
// is corrupted many times (bit flips, byte runs, truncation, splices, number
// edits) with a fixed seed, so a failure reproduces. The assertion is the
// contract: no crash, no hang, and either an error or finite data.
// MARIONETTE_FUZZ_ITERATIONS scales the work (CI keeps the default small).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette_ar/authoring/augmentation.hpp"
#include "marionette_ar/authoring/authoring_actions.hpp"
#include "marionette_ar/pose_track.hpp"
#include "pose_track_seed.hpp"  // tests/fuzz: the fuzz target's seed
#include "marionette/scene_file/scene_file.hpp"
#include "test_data.hpp"
#ifdef MARIONETTE_HAS_BML
#include "marionette/bml/document.hpp"
#endif
#ifdef MARIONETTE_HAS_TRACKING
#include "marionette_ar/tracking/camera_model.hpp"
#include "marionette_ar/tracking/planar_map.hpp"
#include "tracking_seeds.hpp"  // tests/fuzz: the fuzz targets' seeds
#endif

using namespace marionette;
using namespace marionette::test;

namespace {
int iterations(int fallback) {
  const char* env = std::getenv("MARIONETTE_FUZZ_ITERATIONS");
  return env ? std::max(1, std::atoi(env)) : fallback;
}


std::string mutate(const std::string& seed, std::mt19937& rng) {
  std::string s = seed;
  if (s.empty()) return s;
  std::uniform_int_distribution<int> kind(0, 5);
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !s.empty(); ++e) {
    const std::size_t at = rng() % s.size();
    switch (kind(rng)) {
      case 0: s[at] = static_cast<char>(s[at] ^ (1 << (rng() % 8))); break;  // bit flip
      case 1: s[at] = static_cast<char>(rng() % 256); break;                  // random byte
      case 2: s.resize(at); break;                                             // truncation
      case 3: {                                                                // splice a run elsewhere
        const std::size_t len = std::min<std::size_t>(s.size() - at, 1 + rng() % 64);
        s.insert(rng() % s.size(), s.substr(at, len));
        break;
      }
      case 4: {  // overwrite with an extreme number, where text allows it
        static const char* numbers[] = {"nan", "-inf", "1e39", "-1", "4294967295", "0", "1e-45", "99999999999"};
        const std::string n = numbers[rng() % 8];
        s.replace(at, std::min(n.size(), s.size() - at), n);
        break;
      }
      default: s.erase(at, std::min<std::size_t>(s.size() - at, 1 + rng() % 16)); break;  // deletion
    }
  }
  return s;
}

bool finiteAsset(const Asset& a) {
  auto f = [](float v) { return std::isfinite(v); };
  for (const Transform& t : a.skeleton.restPose)
    if (!f(t.translation.x) || !f(t.translation.y) || !f(t.translation.z) || !f(t.rotation.w) || !f(t.scale.x))
      return false;
  for (const Clip& c : a.clips) {
    if (!f(c.duration)) return false;
    for (const JointTrack& jt : c.tracks) {
      for (const glm::vec3& v : jt.translation.values)
        if (!f(v.x) || !f(v.y) || !f(v.z)) return false;
      for (const glm::quat& q : jt.rotation.values)
        if (!f(q.w) || !f(q.x) || !f(q.y) || !f(q.z)) return false;
    }
  }
  for (const Mesh& m : a.meshes)
    for (const MeshPrimitive& p : m.primitives)
      for (const glm::vec3& v : p.positions)
        if (!f(v.x) || !f(v.y) || !f(v.z)) return false;
  return true;
}

void fuzzImporter(const std::string& seedPath, const std::string& extension, int count, std::uint32_t seed) {
  MARIONETTE_REQUIRE_FILE(seedPath);
  const std::string original = readFile(seedPath);
  std::mt19937 rng(seed);
  const std::string dir = ::testing::TempDir() + "marionette_fuzz/";
  std::filesystem::create_directories(dir);
  // A .gltf names its buffers by relative path: bring them along, unmutated.
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(seedPath).parent_path()))
    if (e.path().extension() == ".bin")
      std::filesystem::copy_file(e.path(), dir + e.path().filename().string(),
                                 std::filesystem::copy_options::overwrite_existing);
  int rejected = 0;
  // Case 0 is the seed itself (it must load, whatever the count). Assimp's own crashes
  // are caught by reading in a forked child first (ImportOptions); every 10th case goes
  // that way, so the round trip is fuzzed too, and the rest parse once, in process: the
  // code under test here is ours, and the fixed seeds keep Assimp's inputs the same.
  for (int i = 0; i < count; ++i) {
    const std::string path = dir + "case" + extension;
    std::ofstream(path, std::ios::binary) << (i == 0 ? original : mutate(original, rng));
    ImportOptions options;
    options.isolateThirdPartyParsers = i % 10 == 0;
    ImportResult r = importAsset(path, options);
    if (!r.ok()) {
      ++rejected;
      ASSERT_FALSE(r.diagnostics.items.empty()) << "case " << i << ": rejected without a diagnostic";
      ASSERT_NE(r.diagnostics.format().find(path), std::string::npos) << "case " << i << ": diagnostic lacks the file";
    } else {
      ASSERT_TRUE(finiteAsset(*r.asset)) << "case " << i << " of " << seedPath << " gave non-finite data";
      ASSERT_EQ(r.asset->skeleton.validate(), "") << "case " << i;
    }
    if (i == 0) {
      ASSERT_TRUE(r.ok()) << "the seed " << seedPath << " does not load: " << r.diagnostics.format();
    }
  }
  std::printf("%s: %d mutations, %d rejected\n", seedPath.c_str(), count - 1, rejected);
  EXPECT_LT(rejected, count - 1) << "every mutation was rejected";
}
}  // namespace

TEST(Fuzz, GlbImporter) { fuzzImporter(sharedAsset("characters/CesiumMan.glb"), ".glb", iterations(150), 1); }
TEST(Fuzz, VrmaImporter) { fuzzImporter(sharedAsset("motions/gltf/three-vrm_test.vrma"), ".vrma", iterations(150), 2); }
TEST(Fuzz, GltfTextImporter) {
  fuzzImporter(assimpModel("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"), ".gltf",
               iterations(150), 3);
}
#ifdef MARIONETTE_HAS_ASSIMP
TEST(Fuzz, BvhImporter) { fuzzImporter(assimpModel("BVH/Boxing_Toes.bvh"), ".bvh", iterations(60), 4); }
TEST(Fuzz, FbxImporter) { fuzzImporter(sharedAsset("motions/fbx/pab_jog.fbx"), ".fbx", iterations(40), 5); }
TEST(Fuzz, XImporter) { fuzzImporter(assimpModel("X/test.x"), ".x", iterations(60), 6); }
#endif

TEST(Fuzz, SceneFiles) {
  const std::string seed = R"({"characters": [{"name": "r", "asset": ")" + sharedAsset("characters/RobotExpressive.glb") +
                           R"(", "position": [1, 0, 2], "heading": 45, "scale": 1.0,
      "play": [{"clip": "Walking", "weight": 0.5, "speed": 1.5, "loop": true, "fadeIn": 0.2}]}]})";
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  std::mt19937 rng(7);
  int rejected = 0;
  const int count = iterations(200);
  for (int i = 0; i < count; ++i) {
    Scene scene;
    SceneLoadResult r = loadSceneText(mutate(seed, rng), "fuzz.json", "", scene);
    if (!r.ok()) {
      ++rejected;
      ASSERT_FALSE(r.diagnostics.items.empty());
      ASSERT_TRUE(scene.characters().empty());
      continue;
    }
    scene.update(1.0 / 30.0);
    for (const auto& c : scene.characters())
      for (float v : c->transformBuffer().skinning()) ASSERT_TRUE(std::isfinite(v)) << "case " << i;
  }
  EXPECT_GT(rejected, 0);
}

// The "speech" section: recorded lines read at load (WAV and alignment paths mutated too).
TEST(Fuzz, SceneFilesWithSpeech) {
  const std::string wav = sharedAsset("speech/arctic_a0009.wav"), phones = sharedAsset("speech/arctic_a0009.phones.txt");
  MARIONETTE_REQUIRE_FILE(wav);
  const std::string seed = R"({"characters": [], "speech": {"synthesizer": false, "lines": [{"text": "He turned sharply.", "audio": ")" +
                           wav + R"(", "alignment": ")" + phones + R"("}]}})";
  std::mt19937 rng(9);
  int rejected = 0, accepted = 0;
  for (int i = 0; i < iterations(200); ++i) {  // case 0: the seed itself, which loads and speaks
    Scene scene;
    SceneLoadResult r = loadSceneText(i == 0 ? seed : mutate(seed, rng), "fuzz.json", "", scene);
    if (!r.ok()) {
      ASSERT_NE(i, 0) << "the seed does not load: " << r.diagnostics.format();
      ++rejected;
      ASSERT_FALSE(r.diagnostics.items.empty());
      continue;
    }
    ++accepted;
    speech::SpeechRequest say;
    say.text = "He turned sharply.";
    const auto said = scene.speech().speak(say);  // a line that loaded plays; otherwise a clear error
    if (said.line)
      for (float v : said.line->curves.values) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << "case " << i;
    else
      ASSERT_FALSE(said.error.empty());
    if (i == 0) {
      ASSERT_TRUE(said.line) << "the seed's recorded line does not play: " << said.error;
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 0);
}

#ifdef MARIONETTE_HAS_BML
TEST(Fuzz, BmlBlocks) {
  const std::string dir = ::marionette::test::sharedDir() + "/bml-corpus/openbmlparser";
  MARIONETTE_REQUIRE_FILE(dir);
  std::mt19937 rng(8);
  int cases = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    const std::string original = readFile(e.path().string());
    for (int i = 0; i < iterations(20); ++i, ++cases) {
      bml::ParseResult r = bml::parseBlock(mutate(original, rng));
      if (!r.block) {
        ASSERT_FALSE(r.warnings.empty());
        EXPECT_GE(r.warnings[0].line, 0);
      }
    }
  }
  EXPECT_GT(cases, 500);
}
#endif

#ifdef MARIONETTE_HAS_TRACKING
// Each mutation is parsed twice: as it is, and with its trailing CRC-32 made right again,
// since the reader checks the checksum first and would refuse nearly every mutation there.
// A map that parses writes back to the same bytes.
TEST(Fuzz, PlanarMaps) {
  const std::string dir = ::testing::TempDir() + "marionette_fuzz/";
  std::filesystem::create_directories(dir);
  Diagnostics error;
  ASSERT_TRUE(ar::writePlanarMap(dir + "seed.map", fuzz::seedPlanarMap(1), error)) << error.format();
  const std::string original = readFile(dir + "seed.map");
  std::mt19937 rng(10);
  int rejected = 0, accepted = 0;
  const int count = iterations(200);
  for (int i = 0; i < count; ++i) {
    std::string bytes = i == 0 ? original : mutate(original, rng);
    for (int patched = 0; patched < 2; ++patched) {
      if (patched) {
        if (bytes.size() < 4) break;
        fuzz::patchMapChecksum(reinterpret_cast<std::uint8_t*>(bytes.data()), bytes.size());
      }
      Diagnostics d;
      const auto map = ar::parsePlanarMap(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "fuzz.map", d);
      if (!map) {
        ++rejected;
        ASSERT_FALSE(d.ok()) << "case " << i << ": rejected without an error";
        ASSERT_NE(d.format().find("fuzz.map"), std::string::npos) << "case " << i << ": the error lacks the name";
        ASSERT_NE(i, 0) << "the seed map does not parse: " << d.format();
        continue;
      }
      ++accepted;
      ASSERT_EQ(map->camera.problem(), "") << "case " << i;
      ASSERT_TRUE(ar::writePlanarMap(dir + "copy.map", *map, error)) << error.format();
      ASSERT_EQ(readFile(dir + "copy.map"), bytes) << "case " << i << ": the map does not write back the same";
    }
  }
  std::printf("planar maps: %d mutations, %d parses rejected, %d accepted\n", count - 1, rejected, accepted);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 2) << "no mutation got past the checks";  // the seed twice, then mutated ones
}

TEST(Fuzz, CameraModels) {
  // The fuzz targets' YAML and XML seeds (the JSON one is the third).
  const std::string yaml = fuzz::kSeedCalibrations[0][1], xml = fuzz::kSeedCalibrations[1][1];
  const std::string path = ::testing::TempDir() + "marionette_fuzz_camera.yml";
  std::mt19937 rng(11);
  int rejected = 0, accepted = 0;
  for (const std::string* seed : {&yaml, &xml}) {
    for (int i = 0; i < iterations(150); ++i) {  // case 0: the seed itself, which reads
      std::ofstream(path, std::ios::binary | std::ios::trunc) << (i == 0 ? *seed : mutate(*seed, rng));
      Diagnostics d;
      const auto camera = ar::readCameraModel(path, d);
      if (!camera) {
        ASSERT_NE(i, 0) << "the seed does not read: " << d.format();
        ++rejected;
        ASSERT_FALSE(d.ok()) << "case " << i << ": rejected without an error";
        ASSERT_NE(d.format().find(path), std::string::npos) << "case " << i << ": the error lacks the file";
        continue;
      }
      ++accepted;
      ASSERT_EQ(camera->problem(), "") << "case " << i;
    }
  }
  std::printf("camera models: %d mutations, %d rejected, %d accepted\n", 2 * (iterations(150) - 1), rejected, accepted);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 2);
}
#endif

// Case 0: the text itself; odd cases: bytes mutated (mostly no JSON any more); even ones: one
// digit changed, which keeps the JSON and reaches the value checks (a rotor off unit, version 7...).
std::string mutateBytesOrDigit(const std::string& original, int i, std::mt19937& rng) {
  if (i == 0) return original;
  if (i % 2 == 1) return mutate(original, rng);
  std::vector<std::size_t> digits;
  for (std::size_t k = 0; k < original.size(); ++k)
    if (original[k] >= '0' && original[k] <= '9') digits.push_back(k);
  std::string text = original;
  text[digits[rng() % digits.size()]] = static_cast<char>('0' + rng() % 10);
  return text;
}

// Mutates a JSON file's text `iterations(300)` times (mutateBytesOrDigit) and parses each with
// `parse(text, diagnostics)`: a refusal must be an error naming the file, what reads must pass
// `check(result, case)`; some of both must happen.
template <class Parse, class Check>
void mutateAndParse(const char* what, const std::string& original, unsigned seed, Parse parse, Check check) {
  std::mt19937 rng(seed);
  int rejected = 0, accepted = 0;
  const int count = iterations(300);
  for (int i = 0; i < count; ++i) {  // case 0: the seed itself, which reads
    const std::string text = mutateBytesOrDigit(original, i, rng);
    Diagnostics d;
    const auto result = parse(text, d);
    if (!result) {
      ASSERT_NE(i, 0) << "the seed does not read: " << d.format();
      ++rejected;
      ASSERT_FALSE(d.ok()) << "case " << i << ": rejected without an error";
      ASSERT_EQ(d.format().rfind("fuzz.json", 0), 0u) << "case " << i << ": the error lacks the file: " << d.format();
      continue;
    }
    ++accepted;
    check(*result, i);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::printf("%s: %d mutations, %d rejected, %d accepted\n", what, count - 1, rejected, accepted);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 2) << "no mutation got past the checks";
}

// The authoring's augmentation files (marionette_ar/authoring/augmentation.hpp).
TEST(Fuzz, Augmentations) {
  ar::Augmentation seed;
  seed.tracker.camera = "camera.yml";
  seed.tracker.map = "poster.map";
  seed.tracker.mapCrc32 = "0a1b2c3d";
  seed.environment = "forest.exr";
  for (int i = 0; i < 2; ++i) {
    ar::PlacedCharacter c;
    c.name = "c" + std::to_string(i);
    c.asset = "BCN.x";
    c.bml = "wave.xml";
    const float k = static_cast<float>(i);
    c.placement.position = {0.1f * k, 0.0f, -0.2f};
    c.placement.rotation = ar::ga::rotation(ar::ga::kPlaneY<float>, 0.3f + k);
    c.placement.scale = 0.5f;
    seed.characters.push_back(c);
  }
  mutateAndParse("augmentations", ar::formatAugmentation(seed), 13,
                 [](const std::string& text, Diagnostics& d) { return ar::parseAugmentation(text, "fuzz.json", d); },
                 [](const ar::Augmentation& a, int i) {
                   for (const ar::PlacedCharacter& c : a.characters) {
                     const ar::Placement& p = c.placement;
                     ASSERT_TRUE(std::isfinite(p.position.x) && std::isfinite(p.position.y) &&
                                 std::isfinite(p.position.z)) << i;
                     ASSERT_NEAR(p.rotation.norm(), 1.0f, 1e-4f) << "case " << i;
                     ASSERT_TRUE(p.scale > 0 && std::isfinite(p.scale)) << "case " << i;
                     ASSERT_FALSE(c.name.empty());
                     ASSERT_FALSE(c.asset.empty());
                   }
                 });
}

// The authoring's action files (marionette_ar/authoring/authoring_actions.hpp).
TEST(Fuzz, ActionFiles) {
  const std::string original = R"({"format": "marionette-actions", "version": 1, "actions": [
    {"do": "pick-character", "name": "bcn"}, {"do": "pick-bml", "file": "wave.xml"},
    {"do": "place", "pixel": [330, 410]}, {"do": "drag", "from": [330, 410], "to": [300, 380], "frame": 90},
    {"do": "rotate", "axes": "local", "plane": "e31", "degrees": 30}, {"do": "height", "metres": 1.75},
    {"do": "exposure", "ev": -0.5}, {"do": "undo"}, {"do": "save"}]})";
  mutateAndParse("action files", original, 14,
                 [](const std::string& text, Diagnostics& d) { return ar::parseActions(text, "fuzz.json", d); },
                 [](const std::vector<ar::Action>& actions, int i) {
                   for (const ar::Action& a : actions) {
                     ASSERT_TRUE(std::isfinite(a.value) && std::isfinite(a.pixel.x) && std::isfinite(a.to.y)) << "case " << i;
                     ASSERT_TRUE(std::isfinite(ar::modelledSeconds(a, nullptr)) && ar::modelledSeconds(a, nullptr) > 0) << i;
                     // What reads writes back to the same actions.
                     Diagnostics again;
                     const auto back = ar::parseActions(ar::formatActions({a}), "fuzz.json", again);
                     ASSERT_TRUE(back && back->size() == 1) << "case " << i << ": " << again.format();
                     ASSERT_EQ((*back)[0].value, a.value);
                     ASSERT_EQ((*back)[0].pixel, a.pixel);
                   }
                 });
}

TEST(Fuzz, PoseTracks) {
  std::mt19937 rng(12);
  int rejected = 0, accepted = 0;
  const int count = iterations(300);
  // Both formats track has written: without and with the standard deviations.
  for (const char* seed : {fuzz::kSeedPoseTrack, fuzz::kSeedPoseTrackWithSigmas})
  for (int i = 0; i < count; ++i) {  // case 0: the seed itself, which reads
    const std::string original = seed;
    const std::string text = i == 0 ? original : mutate(original, rng);
    Diagnostics d;
    const auto track = ar::parsePoseTrack(text, "fuzz.csv", d);
    if (!track) {
      ASSERT_NE(i, 0) << "the seed does not read: " << d.format();
      ++rejected;
      ASSERT_FALSE(d.ok()) << "case " << i << ": rejected without an error";
      ASSERT_EQ(d.format().rfind("fuzz.csv", 0), 0u) << "case " << i << ": the error lacks the file: " << d.format();
      continue;
    }
    ++accepted;
    ASSERT_FALSE(track->rows().empty());
    for (std::size_t r = 0; r < track->rows().size(); ++r) {
      const ar::RecordedPose& row = track->rows()[r];
      ASSERT_TRUE(std::isfinite(row.time) && row.time >= 0) << "case " << i;
      ASSERT_TRUE(std::isfinite(row.positionSigmaM) && row.positionSigmaM >= 0) << "case " << i;
      ASSERT_TRUE(std::isfinite(row.rotationSigmaDeg) && row.rotationSigmaDeg >= 0) << "case " << i;
      if (r > 0) {
        ASSERT_GT(row.frame, track->rows()[r - 1].frame) << "case " << i;
      }
      for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(row.cameraToWorld[c][k])) << "case " << i;
      const glm::dmat3 rot(row.cameraToWorld);  // a rotation: orthonormal
      ASSERT_NEAR(glm::determinant(rot), 1.0, 1e-9) << "case " << i;
      ASSERT_EQ(track->atFrame(row.frame), &row) << "case " << i;
    }
  }
  std::printf("pose tracks: %d mutations, %d rejected, %d accepted\n", 2 * (count - 1), rejected, accepted);
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 2) << "no mutation got past the checks";  // the two seeds and more
}
