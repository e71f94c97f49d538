// The dialect corpus (assets/bml/dialects, issue 24): blocks written after the published
// forms of SmartBody, AsapRealizer and Greta, each with its expectations in a header comment:
//   dialect: smartbody | asaprealizer | greta   (smartbody files are sent in SmartBody mode)
//   expect: B:S=T (seconds of block time) | B:S=B2:S2 (the same time) | block:start=T | FAILED
//   unrealized-robot: ids | -      unrealized-godette: ids | -
//   approximated-robot: ids        approximated-godette: ids   (optional: each of these is
//     realized with a warning of its own saying how: FACS, a gesture vocabulary, ...)
// Each block is performed on RobotExpressive and on Godette (their shipped profiles) in a
// scene with the objects "camera", "door" and "bluebox" (SmartBody's prop), after two
// queued blocks ("asap1", 4 s, and "asapOther") that BMLA blocks refer to. The test fails on any expectation that does not
// hold and prints the figures docs/bml-compliance.md publishes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "marionette/bml/realizer.hpp"
#include "marionette/tts_espeak/espeak_backend.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::bml;

#ifdef MARIONETTE_HAS_TTS
namespace {

struct Expectations {
  std::string dialect;
  std::vector<std::string> expect;
  std::set<std::string> unrealized[2];  // robot, godette
  std::set<std::string> approximated[2];
};

std::string field(const std::string& text, const std::string& name) {
  const std::size_t at = text.find(name + ":");
  if (at == std::string::npos) return {};
  const std::size_t from = at + name.size() + 1, to = text.find('\n', from);
  std::string v = text.substr(from, to == std::string::npos ? std::string::npos : to - from);
  if (const std::size_t close = v.find("-->"); close != std::string::npos) v = v.substr(0, close);
  return v;
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;)
    if (w != "-") out.push_back(w);
  return out;
}

Expectations read(const std::string& text) {
  Expectations e;
  const auto d = words(field(text, "dialect"));
  e.dialect = d.empty() ? "" : d[0].substr(0, d[0].find_first_of(".,"));
  e.expect = words(field(text, "expect"));
  for (const std::string& id : words(field(text, "unrealized-robot"))) e.unrealized[0].insert(id);
  for (const std::string& id : words(field(text, "unrealized-godette"))) e.unrealized[1].insert(id);
  for (const std::string& id : words(field(text, "approximated-robot"))) e.approximated[0].insert(id);
  for (const std::string& id : words(field(text, "approximated-godette"))) e.approximated[1].insert(id);
  return e;
}

struct Outcome {
  bool scheduledAsMeant = true;
  bool allRealized = true;
};

// One block on one character: checks the expectations, returns the figures' two answers.
Outcome perform(const std::string& file, const std::string& text, const Expectations& e, const std::shared_ptr<Rig>& rig,
                int who) {
  Scene scene;
  speech::useEspeak(scene.speech());
  scene.addCharacter("c", rig);
  scene.setObject("camera", {0.0f, 1.6f, 3.0f});
  scene.setObject("door", {2.0f, 0.0f, 1.0f});
  scene.setObject("bluebox", {0.3f, 1.0f, 0.5f});  // before RobotExpressive, behind Godette
  Realizer r(scene);
  r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
  r.setForwardWarningsToScene(false);
  r.setFiles({}, test::sharedAsset("speech"));  // <bmlt:audiofile fileName="arctic_a0009.wav">
  if (e.dialect == "smartbody") r.setDialect(Dialect::SmartBody);
  EXPECT_FALSE(r.perform("<bml id=\"asap1\"><wait id=\"w\" start=\"0\" end=\"4\"/></bml>", "c").failed);
  EXPECT_FALSE(r.perform("<bml id=\"asapOther\"><wait id=\"w\" start=\"0\" end=\"10\"/></bml>", "c").failed);
  std::set<std::string> unrealized, warned;
  r.addFeedbackListener([&](const Feedback& f) {
    if (f.kind == Feedback::Kind::Warning && f.warning.type == WarningType::CannotCreateBehavior)
      unrealized.insert(f.behaviorId);
    else if (f.kind == Feedback::Kind::Warning)
      warned.insert(f.behaviorId);
  });
  const Schedule s = r.perform(text, "c");
  Outcome out;
  for (const std::string& x : e.expect) {
    SCOPED_TRACE(file + ": " + x);
    if (x == "FAILED") {
      EXPECT_TRUE(s.failed);
      out.scheduledAsMeant &= s.failed;
      continue;
    }
    const std::size_t eq = x.find('='), colon = x.find(':');
    if (eq == std::string::npos || colon == std::string::npos) {
      ADD_FAILURE() << "expected B:S=T";
      out.scheduledAsMeant = false;
      continue;
    }
    const std::string behavior = x.substr(0, colon), sync = x.substr(colon + 1, eq - colon - 1), rhs = x.substr(eq + 1);
    std::optional<double> got, want;
    if (behavior == "block") got = r.blockStart(s.blockId);
    else got = s.time(behavior, sync);
    if (const std::size_t c2 = rhs.find(':'); c2 != std::string::npos) want = s.time(rhs.substr(0, c2), rhs.substr(c2 + 1));
    else want = std::stod(rhs);
    const bool ok = got && want && std::fabs(*got - *want) < 1e-6;
    EXPECT_TRUE(ok) << "got " << (got ? std::to_string(*got) : "none") << ", want " << (want ? std::to_string(*want) : "none");
    out.scheduledAsMeant &= ok;
  }
  EXPECT_EQ(unrealized, e.unrealized[who]) << file << (who ? " on Godette" : " on RobotExpressive");
  for (const std::string& id : e.approximated[who])
    EXPECT_TRUE(warned.count(id) && !unrealized.count(id))
        << file << ": " << id << " should be realized with a warning" << (who ? " on Godette" : " on RobotExpressive");
  out.allRealized = !s.failed && unrealized.empty();
  for (int f = 0; f < 30; ++f) {  // the block runs: nothing breaks
    scene.update(1.0 / 10.0);
    r.update();
  }
  return out;
}

}  // namespace

TEST(DialectCorpus, EveryBlockIsScheduledAsItsSourceMeantAndTheFiguresArePublished) {
  const std::filesystem::path dir = test::sourceFile("assets/bml/dialects");
  auto robot = test::loadRigWithProfile(test::sharedAsset("characters/RobotExpressive.glb"), "RobotExpressive.json");
  auto godette = test::loadRigWithProfile(test::sharedAsset("characters/Godette_vrm_v4.vrm"), "Godette_vrm_v4.json");
  ASSERT_TRUE(robot && godette);
  struct Tally {
    int blocks = 0, meant = 0, robot = 0, godette = 0;
  };
  std::map<std::string, Tally> byDialect;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".xml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 15u);
  for (const auto& path : files) {
    const std::string text = test::readFile(path.string());
    const Expectations e = read(text);
    ASSERT_TRUE(e.dialect == "smartbody" || e.dialect == "asaprealizer" || e.dialect == "greta") << path;
    ASSERT_FALSE(e.expect.empty()) << path;
    const Outcome a = perform(path.filename().string(), text, e, robot, 0);
    const Outcome b = perform(path.filename().string(), text, e, godette, 1);
    Tally& t = byDialect[e.dialect];
    ++t.blocks;
    t.meant += a.scheduledAsMeant && b.scheduledAsMeant;
    t.robot += a.allRealized;
    t.godette += b.allRealized;
  }
  std::printf("| dialect | blocks | scheduled as its source would | every behavior realized on RobotExpressive | on Godette |\n");
  for (const auto& [dialect, t] : byDialect)
    std::printf("| %s | %d | %d of %d | %d of %d | %d of %d |\n", dialect.c_str(), t.blocks, t.meant, t.blocks, t.robot,
                t.blocks, t.godette, t.blocks);
  EXPECT_EQ(byDialect.size(), 3u);
}
#endif
