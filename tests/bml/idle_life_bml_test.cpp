// AsapRealizer's idle life in BML (issue 45, 5): <bmlt:blinkemitter> and <bmlt:breathingemitter>
// with their published attributes (range, avgwaitingtime), written after AsapRealizer's own
// demo; read into the emitters' parameters, realized, replaced and stopped.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "marionette/bml/behavior_parameters.hpp"
#include "marionette/bml/document.hpp"
#include "marionette/bml/realizer.hpp"
#include "synthetic_upper_body.hpp"

using namespace marionette;
using namespace marionette::bml;

namespace {

const char* kAsapIdle =
    "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"bml1\" xmlns:bmlt=\"http://hmi.ewi.utwente.nl/bmlt\">"
    "<bmlt:blinkemitter id=\"blinkemitter1\" start=\"0\" range=\"0.5\" avgwaitingtime=\"4.5\"/>"
    "<bmlt:breathingemitter id=\"breathingemitter1\" start=\"0\" range=\"2\" avgwaitingtime=\"9\"/>"
    "</bml>";

std::shared_ptr<Rig> rigWithBlinkMorphs(bool morphs) {
  auto asset = test::makeUpperBodyAsset();
  if (morphs) asset->morphTargets = {"blink_left", "blink_right"};
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfile p = test::upperBodyProfile();
  if (morphs) p.face["CLOSE_EYES"] = {{"blink_left", 1.0f}, {"blink_right", 1.0f}};
  rig->setProfile(std::move(p));
  return rig;
}

ReadParameters readOne(const std::string& element, BehaviorKind kind, ParseResult* parsed = nullptr) {
  ParseResult r = parseBlock("<bml id=\"b\" xmlns:bmlt=\"http://hmi.ewi.utwente.nl/bmlt\">" + element + "</bml>");
  EXPECT_TRUE(r.block && r.block->behaviors.size() == 1) << r.format("b");
  if (parsed) *parsed = r;
  if (!r.block || r.block->behaviors.empty()) return {};
  return readParameters(r.block->behaviors.front(), kind);
}

}  // namespace

TEST(IdleLifeBml, AsapEmittersAreReadIntoTheirParameters) {
  const ParseResult r = parseBlock(kAsapIdle);
  ASSERT_TRUE(r.block) << r.format("asap");
  ASSERT_EQ(r.block->behaviors.size(), 2u);
  EXPECT_TRUE(r.warnings.empty()) << r.format("asap");
  const ReadParameters blink = readParameters(r.block->behaviors[0], BehaviorKind::BlinkEmitter);
  const auto& b = std::get<BlinkParameters>(blink.parameters);
  EXPECT_FLOAT_EQ(b.meanIntervalSeconds, 4.5f);
  EXPECT_NEAR(b.variation, 0.5 / (std::sqrt(3.0) * 4.5), 1e-6);  // the same spread as ASAP's uniform 4.5 +- 0.5
  EXPECT_FALSE(b.stop);
  const ReadParameters breath = readParameters(r.block->behaviors[1], BehaviorKind::BreathingEmitter);
  const auto& p = std::get<BreathingParameters>(breath.parameters);
  EXPECT_NEAR(p.breathsPerMinute, 60.0f / 9.0f, 1e-5f);
  EXPECT_FLOAT_EQ(p.periodRangeSeconds, 2.0f);
  EXPECT_EQ(blink.warning + breath.warning, "");
  // avgwaitingtime 0 stops the emitter (AsapRealizer's emitters wait forever then).
  EXPECT_TRUE(std::get<BlinkParameters>(readOne("<bmlt:blinkemitter id=\"s\" avgwaitingtime=\"0\"/>",
                                                BehaviorKind::BlinkEmitter).parameters).stop);
  EXPECT_TRUE(std::get<BreathingParameters>(readOne("<bmlt:breathingemitter id=\"s\" avgwaitingtime=\"0\"/>",
                                                    BehaviorKind::BreathingEmitter).parameters).stop);
}

TEST(IdleLifeBml, BadValuesAreNamedWithTheValueUsed) {
  const ReadParameters soon = readOne("<bmlt:blinkemitter id=\"e\" avgwaitingtime=\"soon\" range=\"-1\"/>", BehaviorKind::BlinkEmitter);
  EXPECT_NE(soon.warning.find("avgwaitingtime 'soon' is not a number"), std::string::npos) << soon.warning;
  EXPECT_NE(soon.warning.find("3.5 s is used"), std::string::npos) << soon.warning;
  EXPECT_NE(soon.warning.find("range '-1' is not a number in [0, 3.5]; the default spread, variation 0.6, is used"),
            std::string::npos) << soon.warning;
  EXPECT_FLOAT_EQ(std::get<BlinkParameters>(soon.parameters).meanIntervalSeconds, BlinkParameters::kDefaultMeanInterval);
  const ReadParameters wide = readOne("<bmlt:breathingemitter id=\"e\" avgwaitingtime=\"4\" range=\"6\" amplitude=\"big\"/>",
                                      BehaviorKind::BreathingEmitter);
  EXPECT_NE(wide.warning.find("range '6' is not below avgwaitingtime 4"), std::string::npos) << wide.warning;
  EXPECT_NE(wide.warning.find("amplitude 'big' is not a number"), std::string::npos) << wide.warning;
  // An attribute neither AsapRealizer nor this realizer has is named too.
  ParseResult parsed;
  (void)readOne("<bmlt:blinkemitter id=\"e\" rate=\"20\"/>", BehaviorKind::BlinkEmitter, &parsed);
  ASSERT_EQ(parsed.warnings.size(), 1u);
  EXPECT_NE(parsed.warnings[0].message.find("'rate'"), std::string::npos) << parsed.warnings[0].message;
  // Other bmlt: elements stay custom behaviors, left out with a warning.
  const ParseResult noise = parseBlock("<bml id=\"b\" xmlns:bmlt=\"http://hmi.ewi.utwente.nl/bmlt\"><bmlt:noise id=\"n\"/></bml>");
  ASSERT_EQ(noise.warnings.size(), 1u);
  EXPECT_EQ(noise.warnings[0].type, WarningType::CustomBehaviorNotSupported);
}

TEST(IdleLifeBml, EmittersRunUntilAnotherOfTheirKindStopsThem) {
  Scene scene;
  Realizer r(scene);
  r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
  std::vector<Feedback> feedback;
  r.addFeedbackListener([&](const Feedback& f) { feedback.push_back(f); });
  Character* c = scene.addCharacter("ann", rigWithBlinkMorphs(true));
  const Schedule s = r.perform(kAsapIdle, "ann");
  ASSERT_FALSE(s.failed);
  for (const Feedback& f : feedback) EXPECT_NE(f.kind, Feedback::Kind::Warning) << f.xml();
  const int chest = c->rig().joints().spine.back();
  auto chestAngle = [&] {
    glm::mat3 m(c->transformBuffer().modelMatrices()[static_cast<std::size_t>(chest)]);
    return glm::degrees(std::acos(std::clamp(glm::normalize(m[1]).y, -1.0f, 1.0f)));
  };
  float blink = 0.0f, breath = 0.0f;
  for (int f = 0; f < 20 * 30; ++f) {  // 20 s: the block ended long ago, the emitters run on
    scene.update(1.0 / 30.0);
    r.update();
    blink = std::max(blink, c->transformBuffer().morphWeights()[0]);
    breath = std::max(breath, chestAngle());
  }
  EXPECT_GE(blink, 0.99f);
  EXPECT_NEAR(breath, BreathingParameters::kDefaultAmplitudeDegrees, 0.05f);
  EXPECT_TRUE(c->behaviors().find("bml1:blinkemitter1"));
  // A later block stops both (avgwaitingtime 0): blended out, then nothing moves.
  ASSERT_FALSE(r.perform("<bml id=\"bml2\" xmlns:bmlt=\"http://hmi.ewi.utwente.nl/bmlt\">"
                         "<bmlt:blinkemitter id=\"b\" avgwaitingtime=\"0\"/><bmlt:breathingemitter id=\"s\" avgwaitingtime=\"0\"/>"
                         "</bml>", "ann").failed);
  for (int f = 0; f < 2 * 30; ++f) scene.update(1.0 / 30.0), r.update();
  blink = breath = 0.0f;
  for (int f = 0; f < 10 * 30; ++f) {
    scene.update(1.0 / 30.0);
    r.update();
    blink = std::max(blink, c->transformBuffer().morphWeights()[0]);
    breath = std::max(breath, chestAngle());
  }
  EXPECT_EQ(blink, 0.0f);
  EXPECT_LT(breath, 1e-3f);
  EXPECT_FALSE(c->behaviors().find("bml1:blinkemitter1"));  // replaced: pruned
}

TEST(IdleLifeBml, WithoutBlinkMorphsTheBlinkIsNotRealizedAndSaysWhy) {
  Scene scene;
  Realizer r(scene);
  r.setSpeechSynthesis(Realizer::SpeechSynthesis::Inline);
  std::vector<Feedback> warnings;
  r.addFeedbackListener([&](const Feedback& f) {
    if (f.kind == Feedback::Kind::Warning) warnings.push_back(f);
  });
  scene.addCharacter("ann", rigWithBlinkMorphs(false));
  ASSERT_FALSE(r.perform(kAsapIdle, "ann").failed);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].warning.type, WarningType::CannotCreateBehavior);
  EXPECT_EQ(warnings[0].behaviorId, "blinkemitter1");
  EXPECT_NE(warnings[0].warning.message.find("no blink morphs"), std::string::npos) << warnings[0].warning.message;
}
