// AR authoring end to end (docs/authoring.md), as a user runs it: the demo's recorded sweep
// (marionette_write_sequence --scenario authoring_sweep, exactly as scripts/demo makes it) and
// its map; `marionette-ar author` with the shipped action file; `marionette-ar --restore` of the
// saved augmentation, measured against the frames' exact poses; ten relaunches from around the
// authoring spot; bad augmentations and maps; and the authoring window driven by synthetic input,
// whose recorded actions replayed headless must give the same file bit for bit.
//
// The sweep is rendered once into this build's folder (MARIONETTE_AUTHORING_TEST_DIR) and
// reused by the tests after it while the programs and data that made it are the same.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_run.hpp"
#include "marionette_ar/authoring/augmentation.hpp"
#include "marionette_ar/authoring/authoring_actions.hpp"
#include "marionette_ar/pose_track.hpp"
#include "marionette_ar/tracking/planar_map.hpp"
#include "test_data.hpp"
#include "tracking/scenarios.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kMatWidth = 2.0;   // metres: graf1.png printed as a floor mat (scripts/demo)
constexpr double kFloorMpp = 0.008;
constexpr int kSweepFrames = 150;

// This build's folder (MARIONETTE_AUTHORING_TEST_DIR, which ctest sets to a folder in the
// build tree), else one made afresh for this process: never a folder another build wrote.
fs::path root() {
  static const fs::path dir = [] {
    if (const char* d = std::getenv("MARIONETTE_AUTHORING_TEST_DIR"); d && *d) return fs::path(d);
    std::string pattern = (fs::temp_directory_path() / "marionette_authoring_test.XXXXXX").string();
    if (!::mkdtemp(pattern.data())) ADD_FAILURE() << "cannot make a temporary folder " << pattern;
    return fs::path(pattern);
  }();
  return dir;
}
std::string camera() { return sourceFile("assets/cameras/synthetic_640x480.yml"); }

// FNV-1a, continued from h over the bytes.
std::uint64_t fnv1a(std::uint64_t h, const std::string& bytes) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

// The demo's sweep and its map, as scripts/demo makes them; rendered once, then reused.
// ctest runs this file's tests in parallel processes: the first renders while the others
// wait on a lock file (else one would remove the folder another is writing). A sweep is
// reused only if its key matches: the commands, and the bytes of the two programs that made
// it and of their inputs. A rebuilt program or other data renders the sweep again.
struct Sweep {
  fs::path frames, map;
};
struct FileLock {
  int fd;
  explicit FileLock(const fs::path& path) : fd(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd >= 0) ::flock(fd, LOCK_EX);
  }
  ~FileLock() {
    if (fd >= 0) ::close(fd);  // releases the lock
  }
};
const Sweep& sweep() {
  static const Sweep s = [] {
    fs::create_directories(root().parent_path());
    const FileLock lock(root().string() + ".lock");
    Sweep out{root() / "sweep", root() / "sweep.map"};
    const std::string writeCommand = ::marionette::test::programPath("marionette_write_sequence") + " --target " +
                                     opencvData("graf1.png") + " --target-width 2.0 --camera " + camera() +
                                     " --scenario authoring_sweep --frames " + std::to_string(kSweepFrames) +
                                     " --floor " + opencvData("baboon.jpg") + " --floor-mpp 0.008 --out " +
                                     out.frames.string();
    const std::string trackArgs = "track --camera " + camera() + " --images " + out.frames.string() + " --target " +
                                  opencvData("graf1.png") + " --target-width 2.0 --poses " +
                                  (root() / "sweep_poses.csv").string() + " --save-map " + out.map.string();
    std::uint64_t key = fnv1a(14695981039346656037ull, writeCommand + "\n" + trackArgs);
    for (const std::string& file : {::marionette::test::programPath("marionette_write_sequence"),
                                    ::marionette::test::programPath("marionette-ar"), opencvData("graf1.png"),
                                    opencvData("baboon.jpg"), camera()})  // a missing file: its name alone
      key = fnv1a(fnv1a(key, file), fs::exists(file) ? readFile(file) : std::string());
    const fs::path keyFile = root() / "sweep.key";
    const std::string keyText = std::to_string(key);
    const bool have = fs::exists(out.map) && fs::exists(out.frames / "truth.csv") &&
                      fs::exists(out.frames / "frame_0149.png") && fs::exists(keyFile) &&
                      readFile(keyFile.string()) == keyText;
    if (!have) {
      fs::remove_all(root());
      fs::create_directories(root());
      const CliRun write = runCommand(writeCommand);
      EXPECT_EQ(write.status, 0) << write.out;
      const CliRun track = runAr(trackArgs);
      EXPECT_EQ(track.status, 0) << track.out;
      // Written last: a sweep cut short is not taken for a finished one.
      if (write.status == 0 && track.status == 0) std::ofstream(keyFile) << keyText;
    }
    return out;
  }();
  return s;
}

// The shipped AR scene (assets/scenes/ar_tracked_demo.json) with its relative paths made
// absolute and the frames and map swapped for `frames` and `map`.
fs::path writeScene(const fs::path& file, const fs::path& frames, const fs::path& map) {
  const fs::path shipped = sourceFile("assets/scenes/ar_tracked_demo.json");
  Json j = Json::parse(readFile(shipped.string()));
  const fs::path dir = shipped.parent_path();
  auto absolute = [&](const std::string& p) { return (dir / p).lexically_normal().string(); };
  j["scene"] = absolute(j["scene"].get<std::string>());
  j["camera"]["tracker"]["camera"] = absolute(j["camera"]["tracker"]["camera"].get<std::string>());
  j["camera"]["tracker"]["map"] = map.string();
  j["background"]["file"] = frames.string();
  for (auto& b : j["authoring"]["bml"]) b = absolute(b.get<std::string>());
  fs::create_directories(file.parent_path());
  std::ofstream(file) << j.dump(2);
  return file;
}

// marionette-ar ARGS with stdout (the JSON report) apart from stderr.
struct JsonRun {
  int status = -1;
  Json json;
  std::string err;
};
JsonRun runArJson(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "report.json", err = dir / "stderr.txt";
  JsonRun r;
  r.status = runCommand("( " + ::marionette::test::programPath("marionette-ar") + " " + args + " > " + out.string() + " 2> " + err.string() +
                        " )").status;
  r.err = readFile(err.string());
  const std::string text = readFile(out.string());
  r.json = Json::parse(text, nullptr, false);
  EXPECT_FALSE(r.json.is_discarded()) << "not JSON: " << text << "\n" << r.err;
  return r;
}

std::string hex8(std::uint32_t v) {
  char s[9];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

TEST(AuthoringDemo, ShippedActionsPlaceALifeSizeCharacterThatRestoresWhereItWasAuthored) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  MARIONETTE_REQUIRE_FILE(opencvData("graf1.png"));
  const Sweep& s = sweep();
  const fs::path dir = root() / "demo";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene(dir / "scene.json", s.frames, s.map);
  const fs::path augmentation = dir / "augmentation.json";

  // The authoring session, replayed.
  const JsonRun author = runArJson("author " + scene.string() + " --actions " +
                                   sourceFile("assets/scenes/ar_tracked_demo.actions.json") + " -o " +
                                   augmentation.string() + " --json", dir);
  ASSERT_EQ(author.status, 0) << author.err;
  const Json& a = author.json;
  std::printf("author: %d actions, %.2f s modelled, %d frames\n", a["actions"].get<int>(),
              a["authoring_seconds"].get<double>(), a["frames"].get<int>());
  EXPECT_LE(a["actions"].get<int>(), 12);                 // the issue's budget
  EXPECT_LE(a["authoring_seconds"].get<double>(), 60.0);  // the paper's minute
  for (const Json& step : a["steps"]) EXPECT_EQ(step["state"], "TRACKING") << step.dump();
  ASSERT_EQ(a["characters"].size(), 1u);
  const Json& c = a["characters"][0];
  EXPECT_EQ(c["name"], "bcn");
  EXPECT_NEAR(c["height_m"].get<double>(), 1.75, 1e-4);  // life size, as the slider set it
  // On the floor behind the mat where the clicks aimed (computed from the exact poses): the
  // tracked pose the clicks went through is a few millimetres off.
  EXPECT_EQ(c["position"][1].get<double>(), 0.0);
  EXPECT_NEAR(c["position"][0].get<double>(), 0.30, 0.05);
  EXPECT_NEAR(c["position"][2].get<double>(), -1.30, 0.05);
  // Turned about the vertical only (the roll was undone): no e23 or e12 part.
  EXPECT_NEAR(c["rotor"][1].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(c["rotor"][3].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(a["exposure_ev"].get<double>(), -0.33, 1e-6);

  // The file names the map by its checksum and reads back.
  Diagnostics d;
  const auto saved = ar::readAugmentation(augmentation.string(), d);
  ASSERT_TRUE(saved.has_value()) << d.format();
  const auto map = ar::readPlanarMap(s.map.string(), d);
  ASSERT_TRUE(map.has_value()) << d.format();
  EXPECT_EQ(saved->tracker.mapCrc32, hex8(map->checksum));
  ASSERT_EQ(saved->characters.size(), 1u);
  EXPECT_EQ(fs::path(saved->characters[0].bml).filename(), "ar_authored.xml");

  // Restored from the start of the sweep: registered at once, where it was authored.
  const JsonRun restore = runArJson(scene.string() + " --restore " + augmentation.string() +
                                    " --headless --frames 20 --json --out " + (dir / "with").string(), dir);
  ASSERT_EQ(restore.status, 0) << restore.err;
  const Json& r = restore.json;
  std::printf("restore: %s\n", r.dump().c_str());
  EXPECT_TRUE(r["restored"].get<bool>());
  EXPECT_TRUE(r["truth"].get<bool>());
  ASSERT_GE(r["first_registered_frame"].get<int>(), 0);
  // The first frame relocalizes; the second confirms it (a relocalization is given once confirmed).
  EXPECT_EQ(r["first_registered_frame"].get<int>(), 1);
  EXPECT_LE(r["placement_error_m"].get<double>(), 0.01);
  EXPECT_LE(r["placement_error_deg"].get<double>(), 0.5);
  EXPECT_LE(r["placement_error_max_m"].get<double>(), 0.01);
  EXPECT_LE(r["placement_error_max_deg"].get<double>(), 0.5);
  EXPECT_GT(r["launch_to_registered_seconds"].get<double>(), 0.0);
  // The launch's phases are durations (docs/authoring.md's table): each >= 0, and together the
  // launch to the first registered frame.
  const Json& phases = r["launch_phases_seconds"];
  double sum = 0;
  for (const char* name : {"main_and_augmentation", "environment_and_background", "gl_context", "scene_and_characters",
                           "gpu_models_and_prt", "shaders_and_targets", "frame0_bml_and_scene",
                           "frame0_background_and_tracking", "first_registered_frame"}) {
    ASSERT_TRUE(phases.contains(name)) << name << ": " << phases.dump();
    EXPECT_GE(phases[name].get<double>(), 0.0) << name;
    sum += phases[name].get<double>();
  }
  EXPECT_EQ(phases.size(), 9u) << phases.dump();
  EXPECT_NEAR(sum, r["launch_to_registered_seconds"].get<double>(), 1e-6) << phases.dump();
  // The restored character is drawn: the frame differs from one without it.
  ASSERT_EQ(runAr(scene.string() + " --restore " + augmentation.string() + " --headless --frames 20 --hide-characters --out " +
                  (dir / "without").string()).status, 0);
  const ar::Image8 with = frame(dir / "with", 10), without = frame(dir / "without", 10);
  ASSERT_EQ(with.pixels.size(), without.pixels.size());
  int differing = 0;
  for (std::size_t i = 0; i + 3 < with.pixels.size(); i += static_cast<std::size_t>(with.channels))
    differing += std::abs(int(with.pixels[i]) - int(without.pixels[i])) > 24 ? 1 : 0;
  std::printf("the restored character covers %d pixels of frame 10\n", differing);
  EXPECT_GT(differing, 4000);  // a 1.75 m figure 3.5 m away
}

TEST(AuthoringRestore, TenRelaunchesAroundTheAuthoringSpotRestoreWithinACentimetre) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const Sweep& s = sweep();
  const fs::path dir = root() / "relaunch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // An augmentation as the demo authors it: BCN life size behind the mat, turned 30 deg.
  Diagnostics d;
  const auto map = ar::readPlanarMap(s.map.string(), d);
  ASSERT_TRUE(map.has_value()) << d.format();
  ar::Augmentation aug;
  aug.tracker.camera = camera();
  aug.tracker.map = s.map.string();
  aug.tracker.mapCrc32 = hex8(map->checksum);
  ar::PlacedCharacter bcn;
  bcn.name = "bcn";
  bcn.asset = assimpModel("X/BCN_Epileptic.X");
  bcn.placement.position = {0.3f, 0.0f, -1.3f};
  bcn.placement.rotation = ar::ga::rotation(ar::ga::kPlaneY<float>, 0.66f);
  bcn.placement.pivot = {0.0f, -1.02f, -0.1f};
  aug.characters.push_back(bcn);
  ASSERT_TRUE(ar::writeAugmentation((dir / "augmentation.json").string(), aug, d)) << d.format();

  // The renderer of the sweep (the same mat and floor), the authoring spot its frame 98's camera
  // (where the demo's session saves), and ten poses around it.
  ar::synthetic::PlanarScene world;
  world.targetWidth = kMatWidth;
  world.floorMetresPerPixel = kFloorMpp;
  cv::cvtColor(cv::imread(opencvData("graf1.png")), world.target, cv::COLOR_BGR2RGB);
  cv::cvtColor(cv::imread(opencvData("baboon.jpg")), world.floor, cv::COLOR_BGR2RGB);
  Diagnostics cd;
  const auto model = ar::readCameraModel(camera(), cd);
  ASSERT_TRUE(model.has_value()) << cd.format();
  const ar::synthetic::SequenceRenderer renderer(world, *model);
  const glm::dmat4 spot = ar::synthetic::authoringSweep(renderer, kSweepFrames).cameraToWorld[98];
  const auto starts = ar::synthetic::relaunchPoses(renderer, spot, 10);
  ASSERT_EQ(starts.size(), 10u);

  int restored = 0;
  double worstM = 0, worstDeg = 0;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const fs::path frames = dir / ("start_" + std::to_string(k));
    fs::create_directories(frames);
    std::ofstream csv(frames / "truth.csv");
    csv << "frame,time,state,px,py,pz,qx,qy,qz,qw\n";
    constexpr int kFrames = 8;  // a still phone for a quarter of a second
    for (int i = 0; i < kFrames; ++i) {
      ar::synthetic::FrameEffects fx;
      fx.noiseSigma = 2.0;
      fx.noiseSeed = static_cast<std::uint32_t>(1000 * k + i + 1);
      cv::Mat rgb, bgr;
      renderer.render(starts[k].cameraToWorld, fx, rgb);
      cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.png", i);
      ASSERT_TRUE(cv::imwrite((frames / name).string(), bgr));
      const glm::dmat4& m = starts[k].cameraToWorld;
      const glm::dquat q = glm::quat_cast(glm::dmat3(m));
      char line[256];
      std::snprintf(line, sizeof line, "%d,%.9g,TRACKING,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", i, i / 30.0, m[3].x,
                    m[3].y, m[3].z, q.x, q.y, q.z, q.w);
      csv << line;
    }
    csv.close();
    const fs::path scene = writeScene(frames / "scene.json", frames, s.map);
    const JsonRun run = runArJson(scene.string() + " --restore " + (dir / "augmentation.json").string() +
                                      " --headless --frames " + std::to_string(kFrames) + " --json --out " +
                                      (frames / "out").string(),
                                  frames);
    EXPECT_EQ(run.status, 0) << run.err;
    const Json& r = run.json;
    const bool registered = r.value("first_registered_frame", -1) >= 0;
    const double m = registered ? r["placement_error_max_m"].get<double>() : -1;
    const double deg = registered ? r["placement_error_max_deg"].get<double>() : -1;
    const bool ok = registered && m <= 0.01 && deg <= 0.5;
    restored += ok ? 1 : 0;
    if (registered) {
      worstM = std::max(worstM, m);
      worstDeg = std::max(worstDeg, deg);
    }
    std::printf("start %zu: moved %.2f m, turned %.1f deg: %s at frame %d, %.1f mm, %.3f deg, launch to registered %.3f s\n",
                k, starts[k].moved, starts[k].turnedDeg, ok ? "restored" : "NOT restored",
                r.value("first_registered_frame", -1), m * 1000, deg,
                registered ? r["launch_to_registered_seconds"].get<double>() : -1.0);
  }
  std::printf("%d of 10 relaunches restored within 1 cm and 0.5 deg (worst %.1f mm, %.3f deg)\n", restored,
              worstM * 1000, worstDeg);
  EXPECT_GE(restored, 9);  // the goal
  // Regression bounds (issue 41): docs/authoring.md publishes 10 of 10, 5.3 mm and 0.018 deg at worst.
  EXPECT_EQ(restored, 10);
  EXPECT_LE(worstM, 0.008);
  EXPECT_LE(worstDeg, 0.027);
}

TEST(AuthoringRestore, BadAugmentationsAndMapsAreNamedAndTheSceneStillRuns) {
  const Sweep& s = sweep();
  const fs::path dir = root() / "bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene(dir / "scene.json", s.frames, s.map);
  Diagnostics d;
  const auto map = ar::readPlanarMap(s.map.string(), d);
  ASSERT_TRUE(map.has_value()) << d.format();
  ar::Augmentation good;
  good.tracker.camera = camera();
  good.tracker.map = s.map.string();
  good.tracker.mapCrc32 = hex8(map->checksum);
  ar::PlacedCharacter bcn;
  bcn.name = "bcn";
  bcn.asset = assimpModel("X/BCN_Epileptic.X");
  good.characters.push_back(bcn);
  const std::string text = ar::formatAugmentation(good);

  // A map with one byte changed, and a good augmentation pointing at it.
  std::string mapBytes = readFile(s.map.string());
  mapBytes[mapBytes.size() / 2] = static_cast<char>(mapBytes[mapBytes.size() / 2] ^ 0x5a);
  std::ofstream(dir / "corrupt.map", std::ios::binary) << mapBytes;
  ar::Augmentation onCorrupt = good;
  onCorrupt.tracker.map = (dir / "corrupt.map").string();
  ar::Augmentation otherMap = good;
  otherMap.tracker.mapCrc32 = "0badc0de";
  ar::PlacedCharacter stranger = bcn;
  stranger.name = "robot";
  ar::Augmentation unknownCharacter = good;
  unknownCharacter.characters.push_back(stranger);

  const struct {
    const char* name;
    std::string contents;  // empty: no file
    const char* says;
  } cases[] = {
      {"missing.json", "", "missing.json"},
      {"truncated.json", text.substr(0, text.size() / 2), "not JSON"},
      {"foreign.json", readFile(scene.string()), "'format': missing"},
      {"newer.json", std::string(text).replace(text.find("\"version\": 1"), 12, "\"version\": 9"), "newer marionette"},
      {"corrupt_map.json", ar::formatAugmentation(onCorrupt), "checksum mismatch"},
      {"other_map.json", ar::formatAugmentation(otherMap), "not the map this augmentation was authored on"},
      {"unknown_character.json", ar::formatAugmentation(unknownCharacter), "'robot' is not a character of the scene"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path file = dir / c.name;
    if (!c.contents.empty()) std::ofstream(file) << c.contents;
    const fs::path out = dir / (std::string(c.name) + ".frames");
    const JsonRun run = runArJson(scene.string() + " --restore " + file.string() + " --headless --frames 3 --json --out " +
                                      out.string(), dir);
    EXPECT_EQ(run.status, 1) << run.err;                                  // said, not hidden
    EXPECT_NE(run.err.find(c.says), std::string::npos) << run.err;       // the problem
    const std::string error = run.json["error"].is_string() ? run.json["error"].get<std::string>() : "";
    EXPECT_NE(error.find(c.says), std::string::npos) << run.json.dump();
    EXPECT_TRUE(fs::exists(out / "frame_0002.png"));                      // and the renderer ran on
    const bool partial = std::string(c.name) == "unknown_character.json";  // bcn is still restored
    EXPECT_EQ(run.json.value("restored", !partial), partial) << run.json.dump();
    if (!partial) {
      EXPECT_NE(run.err.find("the scene runs without it"), std::string::npos) << run.err;
    }
  }
}

TEST(AuthoringReplay, BadScenesAndActionsAreNamed) {
  const Sweep& s = sweep();
  const fs::path dir = root() / "bad_replay";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene(dir / "scene.json", s.frames, s.map);
  auto actions = [&](const char* name, const std::string& list) {
    std::ofstream(dir / name) << R"({"format": "marionette-actions", "version": 1, "actions": [)" << list << "]}";
    return (dir / name).string();
  };
  const std::string out = " -o " + (dir / "out.json").string();
  // A click in the sky: the action, its frame and the tracking state are named; exit 2.
  CliRun r = runAr("author " + scene.string() + " --actions " +
                   actions("sky.json", R"({"do": "pick-character", "name": "bcn"}, {"do": "place", "pixel": [320, 5]})") + out);
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("sky.json: actions[1] (place) at frame"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the click does not meet the tracked floor"), std::string::npos) << r.out;
  // A character the scene does not have; a frame before the one reached.
  r = runAr("author " + scene.string() + " --actions " + actions("who.json", R"({"do": "pick-character", "name": "robot"})") + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("no character \"robot\" in the scene (it has: bcn)"), std::string::npos) << r.out;
  r = runAr("author " + scene.string() + " --actions " +
            actions("back.json", R"({"do": "exposure", "ev": 1, "frame": 40}, {"do": "save", "frame": 10})") + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("back.json: actions[1] (save): frame 10 is before frame 40"), std::string::npos) << r.out;
  // A bad action file is named before anything runs.
  r = runAr("author " + scene.string() + " --actions " + actions("typo.json", R"({"do": "plaec"})") + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("typo.json: error: 'actions[0].do': \"plaec\" is not an action"), std::string::npos) << r.out;
  // Scenes it cannot author in: no tracker, no saved map, no recorded frames.
  Json j = Json::parse(readFile(scene.string()));
  Json noTracker = j, noMap = j, still = j;
  noTracker["camera"].erase("tracker");
  noMap["camera"]["tracker"].erase("map");
  noMap["camera"]["tracker"]["target"] = opencvData("graf1.png");
  noMap["camera"]["tracker"]["width"] = 2.0;
  still["background"] = {{"kind", "image"}, {"file", (s.frames / "frame_0000.png").string()}};
  const std::string ok = actions("ok.json", R"({"do": "save"})");
  for (const auto& [name, scene2, says] : {std::tuple{"no_tracker.json", noTracker, "'camera.tracker' is needed"},
                                            std::tuple{"no_map.json", noMap, "'camera.tracker.map' is needed"},
                                            std::tuple{"still.json", still, "a tracker needs camera frames"}}) {
    SCOPED_TRACE(name);
    std::ofstream(dir / name) << scene2.dump();
    r = runAr("author " + (dir / name).string() + " --actions " + ok + out);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find(says), std::string::npos) << r.out;
  }
  // Usage: the three arguments are needed.
  r = runAr("author " + scene.string() + " --actions " + ok);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("usage: marionette-ar author"), std::string::npos) << r.out;
}

TEST(AuthoringWindow, BadInputScriptsAreNamed) {
  const Sweep& s = sweep();
  const fs::path dir = root() / "bad_window";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene(dir / "scene.json", s.frames, s.map);
  const struct {
    const char* name;
    const char* text;
    const char* says;
  } cases[] = {
      {"notjson.json", "{", "notjson.json: not JSON"},
      {"noevents.json", "{}", "'events': expected an array"},
      {"noframe.json", R"({"events": [{"quit": true}]})", "'events[0]': expected an object with a whole \"frame\""},
      {"badclick.json", R"({"events": [{"frame": 1, "clickImage": [1]}]})", "expected \"clickImage\": [x, y]"},
      {"badkey.json", R"({"events": [{"frame": 1, "key": "!"}]})", "\"key\" must be a letter or a digit"},
      {"nothing.json", R"({"events": [{"frame": 1, "dance": true}]})", "expected one of clickImage"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    std::ofstream(dir / c.name) << c.text;
    const CliRun r = runAr(scene.string() + " --author " + (dir / "out.json").string() + " --input-script " +
                           (dir / c.name).string() + " --frames 5");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << r.out;
  }
  // --author opens a window: not with --headless.
  const CliRun r = runAr(scene.string() + " --author " + (dir / "out.json").string() + " --headless --out " + dir.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--author opens the authoring window"), std::string::npos) << r.out;
}

TEST(AuthoringWindow, SyntheticInputPlacesTurnsAndSavesWhatTheReplayMakesBitForBit) {
  MARIONETTE_REQUIRE_FILE(assimpModel("X/BCN_Epileptic.X"));
  const Sweep& s = sweep();
  const fs::path dir = root() / "window";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scene = writeScene(dir / "scene.json", s.frames, s.map);
  // Pick BCN and its BML with the panel's buttons, click the floor behind the mat, turn 30 deg
  // about the world's vertical with the button, switch to local axes, tip it forward and undo
  // that, turn back 15 deg about its own vertical by key, drag it, save, quit.
  std::ofstream(dir / "events.json") << R"({ "events": [
    { "frame": 5, "clickButton": "bcn" }, { "frame": 12, "clickButton": "ar_authored.xml" },
    { "frame": 20, "clickImage": [330, 261] },
    { "frame": 30, "clickButton": "Y+" }, { "frame": 36, "clickButton": "Y+" },
    { "frame": 42, "key": "L" }, { "frame": 46, "clickButton": "X+" }, { "frame": 52, "key": "Z", "ctrl": true },
    { "frame": 58, "key": "Y", "shift": true },
    { "frame": 64, "dragImage": [[330, 261], [345, 255]] },
    { "frame": 72, "clickButton": "Save" }, { "frame": 80, "quit": true } ] })";
  const fs::path saved = dir / "ui.json";
  const CliRun window = runAr(scene.string() + " --author " + saved.string() + " --input-script " +
                              (dir / "events.json").string() + " --frames 120 --screenshot " + (dir / "ui.png").string());
  ASSERT_EQ(window.status, 0) << window.out;
  ASSERT_TRUE(fs::exists(saved)) << window.out;
  ASSERT_TRUE(fs::exists(dir / "ui.actions.json")) << window.out;
  ASSERT_TRUE(fs::exists(dir / "ui.png")) << window.out;

  Diagnostics d;
  const auto actions = ar::readActions((dir / "ui.actions.json").string(), d);
  ASSERT_TRUE(actions.has_value()) << d.format();
  std::vector<std::string> kinds;
  for (const ar::Action& a : *actions) kinds.push_back(ar::actionName(a.kind));
  EXPECT_EQ(kinds, (std::vector<std::string>{"pick-character", "pick-bml", "place", "rotate", "rotate", "rotate", "undo",
                                             "rotate", "drag", "save"}));
  const auto aug = ar::readAugmentation(saved.string(), d);
  ASSERT_TRUE(aug.has_value()) << d.format();
  ASSERT_EQ(aug->characters.size(), 1u);
  const ar::Placement& p = aug->characters[0].placement;
  EXPECT_EQ(aug->characters[0].name, "bcn");
  EXPECT_EQ(fs::path(aug->characters[0].bml).filename(), "ar_authored.xml");
  EXPECT_EQ(p.scale, 1.0f);
  EXPECT_NEAR(p.rotation.b23, 0.0f, 1e-6f);  // the tip forward was undone; only turns about the vertical remain
  EXPECT_NEAR(p.rotation.b12, 0.0f, 1e-6f);
  // Where the click met the floor at frame 22 (the sweep's start): behind the mat (z < -0.8).
  EXPECT_LT(p.position.z, -0.8f);
  EXPECT_GT(p.position.z, -2.5f);
  EXPECT_LT(std::abs(p.position.x), 1.5f);

  // The same actions from the file, headless: the same augmentation, bit for bit.
  const fs::path replayed = dir / "replayed.json";
  const CliRun replay = runAr("author " + scene.string() + " --actions " + (dir / "ui.actions.json").string() + " -o " +
                              replayed.string());
  ASSERT_EQ(replay.status, 0) << replay.out;
  EXPECT_EQ(readFile(replayed.string()), readFile(saved.string()));
}

}  // namespace
}  // namespace marionette::test
