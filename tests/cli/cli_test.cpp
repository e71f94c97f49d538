// Runs the `marionette` tool as a user would and checks its output, trace and exit codes.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "test_data.hpp"

using namespace marionette::test;

namespace {
CliRun run(const std::string& args) { return runCli(args); }

std::string tempFile(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << content;
  return path;
}
}  // namespace

TEST(Cli, UsageAndUnknownCommandsExitWithTwo) {
  EXPECT_EQ(run("").status, 2);
  EXPECT_EQ(run("frobnicate").status, 2);
  EXPECT_EQ(run("run").status, 2);
  EXPECT_EQ(run("run x.json --frames zero").status, 2);
  EXPECT_EQ(run("inspect").status, 2);
  EXPECT_EQ(run("--help").status, 0);
}

TEST(Cli, InspectMissingFileIsAnErrorNamingIt) {
  CliRun r = run("inspect /nonexistent/robot.glb");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("/nonexistent/robot.glb: error: file does not exist"), std::string::npos) << r.out;
}

TEST(Cli, InspectJsonListsJointsClipsAndMorphs) {
  const std::string file = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(file);
  CliRun r = run("inspect " + file + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  auto j = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  EXPECT_EQ(j["joints"].size(), 43u);
  EXPECT_EQ(j["joints"][0], "Bone");
  ASSERT_EQ(j["clips"].size(), 14u);
  std::map<std::string, double> durations;
  for (auto& c : j["clips"]) durations[c["name"]] = c["duration"];
  EXPECT_NEAR(durations["Walking"], 0.958, 0.002);
  std::vector<std::string> morphs = j["morphTargets"];
  EXPECT_NE(std::find(morphs.begin(), morphs.end(), "Surprised"), morphs.end());
}

TEST(Cli, RunWritesTheTraceContract) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const std::string scene =
      tempFile("cli_scene.json", R"({"characters": [{"name": "robot", "asset": ")" + asset + R"("}]})");
  const std::string trace = ::testing::TempDir() + "cli_trace.csv";
  CliRun r = run("run " + scene + " --frames 10 --fps 30 --trace " + trace + " --stats");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("controllers"), std::string::npos) << r.out;
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,time,character,joint,px,py,pz,qx,qy,qz,qw");
  int rows = 0;
  double lastTime = -1;
  while (std::getline(in, line)) {
    ++rows;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 11u) << line;
    EXPECT_EQ(cells[2], "robot");
    double qx = std::stod(cells[7]), qy = std::stod(cells[8]), qz = std::stod(cells[9]), qw = std::stod(cells[10]);
    EXPECT_NEAR(qx * qx + qy * qy + qz * qz + qw * qw, 1.0, 1e-4) << line;
    lastTime = std::stod(cells[1]);
  }
  EXPECT_EQ(rows, 10 * 43);
  EXPECT_NEAR(lastTime, 9.0 / 30.0, 1e-6);
}

TEST(Cli, RunBadSceneGivesFileLineColumnAndExitTwo) {
  const std::string scene = tempFile("bad_scene.json", "{\n \"characters\": [ {\"name\": } ]\n}\n");
  CliRun r = run("run " + scene);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find(scene + ":2:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error:"), std::string::npos);
}

TEST(Cli, RunWithWarningsExitsWithOne) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const std::string scene = tempFile(
      "warn_scene.json", R"({"characters": [{"name": "robot", "asset": ")" + asset + R"(", "colour": "red"}]})");
  CliRun r = run("run " + scene + " --frames 2");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("unknown key 'colour'"), std::string::npos) << r.out;
}

#ifdef MARIONETTE_CLI_HAS_BML
namespace {
std::string corpusFile(const std::string& name) {
  return ::marionette::test::sharedDir() + "/bml-corpus/openbmlparser/" + name;
}
}  // namespace

TEST(CliBmlCheck, ExitCodesFollowTheWorstBlock) {
  MARIONETTE_REQUIRE_FILE(corpusFile("testnod.xml"));
  EXPECT_EQ(run("bml-check " + corpusFile("testnod.xml")).status, 0);
  CliRun warned = run("bml-check " + corpusFile("testnod.xml") + " " + corpusFile("testspeech_invalidtime.xml"));
  EXPECT_EQ(warned.status, 1);
  // file:line:col: warning: TYPE: message
  EXPECT_NE(warned.out.find(corpusFile("testspeech_invalidtime.xml") + ":17:2: warning: IMPOSSIBLE_TO_SCHEDULE: behavior 'speech1'"),
            std::string::npos)
      << warned.out;
  CliRun failed = run("bml-check " + corpusFile("testinvalidxml.xml"));
  EXPECT_EQ(failed.status, 2);
  EXPECT_NE(failed.out.find(":26:3: error: PARSING_FAILURE: malformed XML"), std::string::npos) << failed.out;
  EXPECT_EQ(run("bml-check /nonexistent.xml").status, 2);
  EXPECT_EQ(run("bml-check").status, 2);
}

TEST(CliBmlCheck, JsonHasTheDocumentedShape) {
  MARIONETTE_REQUIRE_FILE(corpusFile("testoffset.xml"));
  CliRun r = run("bml-check --json " + corpusFile("testoffset.xml") + " " + corpusFile("testspeech_invalidtime.xml"));
  ASSERT_EQ(r.status, 1) << r.out;
  auto j = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_TRUE(j.is_array()) << r.out;
  ASSERT_EQ(j.size(), 2u);
  const auto& block = j[0]["blocks"][0];
  EXPECT_EQ(block["id"], "bml1");
  EXPECT_EQ(block["status"], "ok");
  ASSERT_EQ(block["behaviors"].size(), 3u);
  bool sawG1 = false;
  for (const auto& b : block["behaviors"])
    if (b["id"] == "g1") {
      sawG1 = true;
      EXPECT_DOUBLE_EQ(b["syncPoints"]["start"].get<double>(), 4.0);
    }
  EXPECT_TRUE(sawG1);
  const auto& second = j[1]["blocks"][0];
  EXPECT_EQ(second["status"], "warnings");
  EXPECT_TRUE(second["behaviors"].empty());  // the dropped speech does not appear
  ASSERT_EQ(second["warnings"].size(), 1u);
  EXPECT_EQ(second["warnings"][0]["type"], "IMPOSSIBLE_TO_SCHEDULE");
  EXPECT_EQ(second["warnings"][0]["behavior"], "speech1");
  EXPECT_EQ(second["warnings"][0]["line"], 17);
}

// Against the default character (every controller, built-in durations) the BML
// alone is checked; against a real one, its clips set durations and what it
// cannot realize is a CANNOT_CREATE_BEHAVIOR warning.
TEST(CliBmlCheck, DefaultCharacterOrARealOne) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const std::string bml = tempFile("check_character.xml",
                                   "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b\">\n"
                                   "  <gesture id=\"g\" lexeme=\"WAVE\"/>\n"
                                   "  <faceLexeme id=\"f\" lexeme=\"SMILE\" start=\"g:end\"/>\n"
                                   "</bml>\n");
  auto gestureEnd = [](const CliRun& r) {
    auto j = nlohmann::json::parse(r.out, nullptr, false);
    if (j.is_discarded() || !j.is_array() || j.empty()) return -1.0;
    for (const auto& b : j[0]["blocks"][0]["behaviors"])
      if (b["id"] == "g") return b["syncPoints"]["end"].get<double>();
    return -1.0;
  };
  CliRun ideal = run("bml-check --json " + bml);
  EXPECT_EQ(ideal.status, 0) << ideal.out;
  EXPECT_DOUBLE_EQ(gestureEnd(ideal), 2.0);
  CliRun real = run("bml-check --json --character " + robot + " " + bml);
  EXPECT_EQ(real.status, 1) << real.out;
  EXPECT_NEAR(gestureEnd(real), 1.833, 1e-3);  // RobotExpressive's "Wave" clip (ASSETS.md)
  EXPECT_NE(real.out.find("\"type\": \"CANNOT_CREATE_BEHAVIOR\""), std::string::npos) << real.out;
  CliRun text = run("bml-check --character " + robot + " " + bml);
  // RobotExpressive's morphs are Angry, Surprised and Sad: no smile.
  EXPECT_NE(text.out.find("check_character.xml:3:3: warning: CANNOT_CREATE_BEHAVIOR: behavior 'f': character "
                          "'RobotExpressive': the character has no morphs for face expression 'SMILE' (its profile "
                          "maps ANGER, SADNESS, SURPRISE)"),
            std::string::npos)
      << text.out;
  EXPECT_EQ(run("bml-check --character /nonexistent.glb " + bml).status, 2);
}

// Without --character nothing says whether a character can do it: the check says so (issue 24,
// 8). --dialect reads SmartBody's blocks without ids; the JSON names how each block was read.
TEST(CliBmlCheck, SaysWhatItDidNotCheckAndHowItReadTheBlock) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const std::string noIds = tempFile("check_no_ids.xml", "<bml>\n  <head type=\"NOD\" start=\"0\" end=\"1\"/>\n</bml>\n");
  const CliRun text = run("bml-check " + noIds);
  EXPECT_EQ(text.status, 2) << "strict BML 1.0 by default (auto: nothing SmartBody-only here)\n" << text.out;
  EXPECT_NE(text.out.find("note: no --character: what a character can realize is not checked"), std::string::npos)
      << text.out;
  const CliRun sbm = run("bml-check --dialect smartbody " + noIds);
  EXPECT_EQ(sbm.status, 1) << "the generated ids are a warning\n" << sbm.out;
  EXPECT_NE(sbm.out.find("block 'sbm_block_1': warnings (read as SmartBody)"), std::string::npos) << sbm.out;
  const CliRun json = run("bml-check --json --dialect smartbody " + noIds);
  auto j = nlohmann::json::parse(json.out, nullptr, false);
  ASSERT_TRUE(j.is_array()) << json.out;
  const auto& block = j[0]["blocks"][0];
  EXPECT_EQ(block["dialect"], "smartbody");
  EXPECT_EQ(block["realizability"].get<std::string>().rfind("not checked", 0), 0u) << json.out;
  const CliRun withRobot = run("bml-check --json --dialect bml --character " + robot + " " + corpusFile("testnod.xml"));
  auto k = nlohmann::json::parse(withRobot.out, nullptr, false);
  ASSERT_TRUE(k.is_array()) << withRobot.out;
  EXPECT_EQ(k[0]["blocks"][0]["dialect"], "bml");
  EXPECT_EQ(k[0]["blocks"][0]["realizability"], "checked against " + robot);
  const CliRun bad = run("bml-check --dialect greta " + noIds);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("auto, bml or smartbody"), std::string::npos) << bad.out;
}
#endif

#ifdef MARIONETTE_CLI_HAS_BML
TEST(CliRunBml, SceneBmlAtItsTimeAndFeedbackLines) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  MARIONETTE_REQUIRE_FILE(corpusFile("testoffset.xml"));
  const std::string scene = tempFile("bml_scene.json", R"({"characters": [{"name": "robot", "asset": ")" + asset +
                                                           R"("}], "bml": [{"file": ")" + corpusFile("testoffset.xml") +
                                                           R"(", "time": 0.5}]})");
  const std::string feedback = ::testing::TempDir() + "feedback.jsonl";
  CliRun r = run("run " + scene + " --frames 600 --fps 60 --feedback " + feedback);
  // No warning (exit 0): the head nods and, RobotExpressive having no BEAT clip, the
  // BEATs are the procedural set's (issue 24, 7).
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find("CANNOT_CREATE_BEHAVIOR"), std::string::npos) << r.out;
  std::ifstream in(feedback);
  std::string line;
  int predictions = 0, syncs = 0;
  double start = -1, end = -1;
  while (std::getline(in, line)) {
    auto j = nlohmann::json::parse(line, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << line;
    if (j["kind"] == "prediction") ++predictions;
    if (j["kind"] == "syncPointProgress") ++syncs;
    if (j["kind"] == "blockProgress" && j["sync"] == "start") start = j["sceneTime"];
    if (j["kind"] == "blockProgress" && j["sync"] == "end") end = j["sceneTime"];
    EXPECT_NE(j["xml"].get<std::string>().find("xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\""), std::string::npos);
  }
  EXPECT_EQ(predictions, 21);  // head 7 + 2 gestures x 7
  EXPECT_EQ(syncs, 21);
  EXPECT_DOUBLE_EQ(start, 0.5);
  EXPECT_DOUBLE_EQ(end, 0.5 + 7.0);  // h1 ends at 7 s block time
}

TEST(CliRunBml, BmlWarningsAndFailuresSetTheExitCode) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const std::string scene = tempFile("bml_scene2.json", R"({"characters": [{"name": "robot", "asset": ")" + asset + R"("}]})");
  CliRun warned = run("run " + scene + " --frames 5 --bml " + corpusFile("testspeech_invalidtime.xml"));
  EXPECT_EQ(warned.status, 1) << warned.out;
  EXPECT_NE(warned.out.find(":17:2: warning: IMPOSSIBLE_TO_SCHEDULE"), std::string::npos) << warned.out;
  CliRun failed = run("run " + scene + " --frames 5 --bml " + corpusFile("testinvalidxml.xml"));
  EXPECT_EQ(failed.status, 2) << failed.out;
  EXPECT_EQ(run("run " + scene + " --frames 5 --bml /nonexistent.xml").status, 2);
}

// The dialect from the command line, from the scene file, and a character's own first.
TEST(CliRunBml, DialectFromTheOptionTheSceneOrTheCharacter) {
  const std::string asset = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(asset);
  const std::string noIds = tempFile("run_no_ids.xml", "<bml>\n  <head type=\"NOD\" start=\"0\" end=\"0.5\"/>\n</bml>\n");
  const std::string plain = tempFile("dialect_plain.json", R"({"characters": [{"name": "robot", "asset": ")" + asset + R"("}]})");
  const CliRun strict = run("run " + plain + " --frames 5 --bml " + noIds);
  EXPECT_EQ(strict.status, 2) << strict.out;
  EXPECT_NE(strict.out.find("has no id"), std::string::npos) << strict.out;
  const CliRun option = run("run " + plain + " --frames 5 --dialect smartbody --bml " + noIds);
  EXPECT_EQ(option.status, 1) << option.out;  // generated ids: a warning
  EXPECT_NE(option.out.find("SmartBody mode: ids generated"), std::string::npos) << option.out;
  const std::string fileWide = tempFile("dialect_file.json", R"({"bmlDialect": "smartbody", "characters": [{"name": "robot", "asset": ")" +
                                                                 asset + R"("}]})");
  EXPECT_EQ(run("run " + fileWide + " --frames 5 --bml " + noIds).status, 1);
  const std::string own = tempFile("dialect_own.json", R"({"bmlDialect": "smartbody", "characters": [{"name": "robot", "asset": ")" +
                                                           asset + R"(", "bmlDialect": "bml"}]})");
  EXPECT_EQ(run("run " + own + " --frames 5 --dialect smartbody --bml " + noIds).status, 2) << "the character's own comes first";
}
#endif

#ifdef MARIONETTE_CLI_HAS_BML  // the scene sends BML
// Issue 4's scene: the robot walks to (1.5, 1.2), ends facing 90 degrees, looks at
// Godette and nods; she looks back and smiles. Checked from what the tool prints.
TEST(CliRunBml, WalkLookNodSmileScene) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/Godette_vrm_v4.vrm"));
  const std::string feedback = ::testing::TempDir() + "walk_feedback.jsonl";
  CliRun r = run("run " + sourceFile("assets/scenes/walk_look_nod_smile.json") + " --frames 600 --fps 60 --stats" +
                 " --feedback " + feedback);
  ASSERT_EQ(r.status, 0) << r.out;
  double x = 0, y = 0, z = 0, heading = 0;
  const std::size_t at = r.out.find("  robot ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find("at (", at), "at (%lf, %lf, %lf) heading %lf", &x, &y, &z, &heading), 4)
      << r.out;
  EXPECT_LT(std::hypot(x - 1.5, z - 1.2), 0.2) << r.out;
  EXPECT_NEAR(heading, 90.0, 5.0) << r.out;
  EXPECT_NE(r.out.find("locomotion"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("face"), std::string::npos) << r.out;
  std::ifstream in(feedback);
  std::string line;
  double arrived = -1, nodStroke = -1, smileStart = -1;
  while (std::getline(in, line)) {
    auto j = nlohmann::json::parse(line, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << line;
    if (j["kind"] != "syncPointProgress") continue;
    if (j["behavior"] == "walk" && j["sync"] == "end") arrived = j["sceneTime"];
    if (j["behavior"] == "nod" && j["sync"] == "stroke") nodStroke = j["sceneTime"];
    if (j["behavior"] == "smile" && j["sync"] == "start") smileStart = j["sceneTime"];
  }
  EXPECT_GT(arrived, 0.5 + 1.0);     // a walk of about 3.7 m takes a while
  EXPECT_GT(nodStroke, arrived);     // the nod comes after the arrival
  EXPECT_NEAR(smileStart, nodStroke, 1e-6);  // she smiles at the nod's stroke
}
#endif

#if defined(MARIONETTE_CLI_HAS_BML) && defined(MARIONETTE_CLI_HAS_TTS)  // the voice fallback is espeak-ng's
// --scene (issue 45, 8): a block that gazes and points at a scene's object and asks for another
// engine's voice is unrealizable against the character alone and fine in the scene written for
// it (its objects; its voice names); --character-name picks the character, a wrong one is named.
TEST(CliBmlCheck, InTheSceneItsObjectsAndVoicesCount) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const std::string scene = tempFile("check_scene.json", "{\"characters\": [{\"name\": \"robot\", \"asset\": \"" + robot +
                                                             "\"}],\n \"objects\": [{\"name\": \"bluebox\", \"position\": [1, 0.5, 1]}],\n"
                                                             " \"speech\": {\"voices\": {\"openmary\": \"en-gb\"}}}\n");
  const std::string bml = tempFile("check_scene.xml",
                                   "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"p1\" characterId=\"robot\">\n"
                                   "  <pointing id=\"pt\" target=\"bluebox\" mode=\"RIGHT_HAND\"/>\n"
                                   "  <gaze id=\"g\" target=\"bluebox\"/>\n"
                                   "  <speech id=\"s\" voice=\"openmary\"><text>That one.</text></speech>\n"
                                   "</bml>\n");
  const CliRun alone = run("bml-check --character " + robot + " " + bml);
  EXPECT_EQ(alone.status, 1) << alone.out;
  EXPECT_NE(alone.out.find("pointing target 'bluebox': the scene has no character or object 'bluebox'"), std::string::npos)
      << alone.out;
  EXPECT_NE(alone.out.find("espeak-ng has no voice 'openmary'"), std::string::npos) << alone.out;
  const CliRun inScene = run("bml-check --scene " + scene + " " + bml);
  EXPECT_EQ(inScene.status, 0) << inScene.out;
  EXPECT_NE(inScene.out.find("block 'p1': ok"), std::string::npos) << inScene.out;
  const CliRun named = run("bml-check --json --scene " + scene + " --character-name robot " + bml);
  EXPECT_EQ(named.status, 0) << named.out;
  auto j = nlohmann::json::parse(named.out, nullptr, false);
  ASSERT_TRUE(j.is_array()) << named.out;
  EXPECT_EQ(j[0]["blocks"][0]["realizability"], "checked in the scene " + scene);
  const CliRun wrong = run("bml-check --scene " + scene + " --character-name nobody " + bml);
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.out.find("--character-name 'nobody': the scene has no such character (it has 'robot')"), std::string::npos)
      << wrong.out;
  EXPECT_EQ(run("bml-check --scene " + scene + " --character " + robot + " " + bml).status, 2);  // one or the other
  EXPECT_EQ(run("bml-check --scene /nonexistent.json " + bml).status, 2);
}
#endif
