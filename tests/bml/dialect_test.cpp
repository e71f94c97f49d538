// BML as other realizers' users write it (issue 24): Greta's draft namespace and
// lower-case compositions, and <required> around what cannot be realized. The blocks
// are written here after the published formats of those projects.
#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <vector>

#include "marionette/bml/behavior_parameters.hpp"
#include "marionette/bml/document.hpp"
#include "marionette/bml/scheduler.hpp"

using namespace marionette;

namespace {
int count(const bml::ParseResult& r, bml::WarningType type) {
  int n = 0;
  for (const auto& w : r.warnings) n += w.type == type;
  return n;
}
}  // namespace

// Greta (and Elckerlyc before BML 1.0) declare the draft namespace: its behaviors are BML.
TEST(BmlDialect, TheDraftNamespaceIsReadAsBml) {
  const auto r = bml::parseBlock(
      "<bml xmlns=\"http://www.mindmakers.org/projects/BML\" id=\"greta1\" composition=\"append\">\n"
      "  <gaze id=\"g1\" target=\"user\" start=\"0\" end=\"2\"/>\n"
      "  <head id=\"h1\" lexeme=\"NOD\" start=\"0.5\"/>\n"
      "</bml>");
  ASSERT_TRUE(r.block) << r.format("greta");
  EXPECT_EQ(r.block->behaviors.size(), 2u) << r.format("greta");
  EXPECT_EQ(count(r, bml::WarningType::CustomBehaviorNotSupported), 0) << r.format("greta");
  EXPECT_EQ(r.block->composition, "APPEND");
  EXPECT_TRUE(r.warnings.empty()) << r.format("greta");
  // Prefixed, as in Greta's FML-APML files that embed BML.
  const auto prefixed = bml::parseBlock(
      "<b:bml xmlns:b=\"http://www.mindmakers.org/projects/BML\" id=\"g2\"><b:head id=\"h\" lexeme=\"SHAKE\"/></b:bml>");
  ASSERT_TRUE(prefixed.block) << prefixed.format("prefixed");
  EXPECT_EQ(prefixed.block->behaviors.size(), 1u) << prefixed.format("prefixed");
  // A namespace that is neither BML 1.0 nor the draft is still someone else's.
  const auto other = bml::parseBlock("<bml xmlns=\"http://example.org/notbml\" id=\"x\"><head id=\"h\" lexeme=\"NOD\"/></bml>");
  ASSERT_TRUE(other.block);
  EXPECT_TRUE(other.block->behaviors.empty());
  EXPECT_EQ(count(other, bml::WarningType::CustomBehaviorNotSupported), 1) << other.format("other");
}

TEST(BmlDialect, CompositionsAreReadCaseInsensitively) {
  for (const char* written : {"merge", "Append", "REPLACE", "replace"}) {
    const auto r = bml::parseBlock(std::string("<bml id=\"b\" composition=\"") + written + "\"/>");
    ASSERT_TRUE(r.block);
    EXPECT_TRUE(r.warnings.empty()) << written << ": " << r.format("c");
    std::string upper = written;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    EXPECT_EQ(r.block->composition, upper);
  }
  const auto bad = bml::parseBlock("<bml id=\"b\" composition=\"sideways\"/>");
  ASSERT_TRUE(bad.block);
  EXPECT_EQ(bad.block->composition, "MERGE");
  EXPECT_NE(bad.format("c").find("composition 'sideways' is not MERGE, APPEND or REPLACE"), std::string::npos)
      << bad.format("c");
}

// BML 1.0: a behavior in <required> that cannot be realized fails the whole block; outside
// it, the behavior is left out and the block goes on.
TEST(BmlDialect, RequiredAroundAnUnsupportedBehaviorFailsTheBlock) {
  const std::string unsupported =
      "<bml id=\"r\" xmlns:sbm=\"http://ict.usc.edu\"><required><head id=\"h\" lexeme=\"NOD\"/>"
      "<frobnicate id=\"f\"/></required></bml>";
  const auto r = bml::parseBlock(unsupported);
  ASSERT_EQ(count(r, bml::WarningType::BehaviorTypeNotSupported), 1) << r.format("r");
  EXPECT_TRUE(r.warnings.back().fatal);
  EXPECT_NE(r.format("r").find("being required, it made the block fail"), std::string::npos) << r.format("r");
  EXPECT_TRUE(bml::scheduleText(unsupported).failed);
  const std::string custom =
      "<bml id=\"c\" xmlns:sbm=\"http://ict.usc.edu\"><required><sbm:grab id=\"a\" target=\"ball\"/></required></bml>";
  EXPECT_TRUE(bml::scheduleText(custom).failed);
  // SmartBody's <sbm:reach> is a behavior here (issue 45, 7): required, it schedules.
  const std::string reach =
      "<bml id=\"c\" xmlns:sbm=\"http://ict.usc.edu\"><required><sbm:reach id=\"a\" target=\"ball\"/></required></bml>";
  const bml::Schedule reached = bml::scheduleText(reach);
  EXPECT_FALSE(reached.failed);
  EXPECT_EQ(reached.behaviors.size(), 1u);
  // The same outside <required>: left out with a warning, the head still scheduled.
  const bml::Schedule free = bml::scheduleText(
      "<bml id=\"o\"><head id=\"h\" lexeme=\"NOD\"/><frobnicate id=\"f\"/></bml>");
  EXPECT_FALSE(free.failed);
  EXPECT_EQ(free.behaviors.size(), 1u);
}

// SmartBody's execBML adds the ids its scripts leave out (issue 24, 1).
TEST(BmlDialect, SmartBodyBlocksAndBehaviorsWithoutIdsGetStableGeneratedOnes) {
  const std::string text =
      "<act><bml xmlns:sbm=\"http://ict.usc.edu\">\n"
      "  <head type=\"NOD\"/>\n"
      "  <gaze target=\"camera\"/>\n"
      "  <head id=\"head_1\" lexeme=\"SHAKE\"/>\n"  // an id the generated ones must not take
      "  <head lexeme=\"TOSS\"/>\n"
      "</bml></act>";
  const auto r = bml::parseBlock(text);
  ASSERT_TRUE(r.block) << r.format("sbm");
  EXPECT_TRUE(r.block->smartBody);
  EXPECT_TRUE(r.block->generatedIds);
  std::vector<std::string> ids;
  for (const auto& b : r.block->behaviors) ids.push_back(b.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"head_2", "gaze_1", "head_1", "head_3"})) << r.format("sbm");
  EXPECT_EQ(r.block->id.rfind("sbm_", 0), 0u) << r.block->id;
  EXPECT_EQ(bml::parseBlock(text).block->id, r.block->id) << "generated from the text: the same on every run";
  // One warning names everything generated, with places.
  ASSERT_EQ(count(r, bml::WarningType::ParsingFailure), 1) << r.format("sbm");
  const std::string w = r.format("sbm");
  EXPECT_NE(w.find("SmartBody mode: ids generated for the block ('" + r.block->id + "'), <head> at 2:3 ('head_2'), "
                   "<gaze> at 3:3 ('gaze_1') and <head> at 5:3 ('head_3')"),
            std::string::npos)
      << w;
  // The caller's id for the block (the Realizer numbers its blocks).
  bml::ParseOptions o;
  o.generatedBlockId = "sbm_block_7";
  EXPECT_EQ(bml::parseBlock(text, o).block->id, "sbm_block_7");
}

TEST(BmlDialect, TheDialectIsDetectedOrChosen) {
  const std::string plain = "<bml><head lexeme=\"NOD\"/></bml>";
  // BML 1.0 (no SmartBody form): a missing id fails, as the standard says.
  EXPECT_FALSE(bml::parseBlock(plain).block);
  bml::ParseOptions smartbody;
  smartbody.dialect = bml::Dialect::SmartBody;
  const auto chosen = bml::parseBlock(plain, smartbody);
  ASSERT_TRUE(chosen.block) << chosen.format("p");
  EXPECT_EQ(chosen.block->behaviors.at(0).id, "head_1");
  // An sbm: attribute alone makes it SmartBody's; Bml refuses it even so.
  const std::string sbm = "<bml xmlns:sbm=\"http://ict.usc.edu\"><head lexeme=\"NOD\" sbm:smooth=\"0.5\"/></bml>";
  EXPECT_TRUE(bml::parseBlock(sbm).block);
  bml::ParseOptions strict;
  strict.dialect = bml::Dialect::Bml;
  EXPECT_FALSE(bml::parseBlock(sbm, strict).block);
  // A block that has its ids is not changed and gets no warning about them.
  const auto given = bml::parseBlock("<bml id=\"b\" xmlns:sbm=\"http://ict.usc.edu\"><head id=\"h\" lexeme=\"NOD\"/></bml>");
  ASSERT_TRUE(given.block);
  EXPECT_FALSE(given.block->generatedIds);
  EXPECT_TRUE(given.warnings.empty()) << given.format("g");
  for (bml::Dialect d : {bml::Dialect::Auto, bml::Dialect::Bml, bml::Dialect::SmartBody})
    EXPECT_EQ(bml::dialectFromName(bml::toString(d)), d);
  EXPECT_FALSE(bml::dialectFromName("greta").has_value());
}

// An attribute a behavior does not have (a misspelt sync point, another realizer's option)
// is named, with what the behavior has, in one warning per behavior (issue 24, 8); the
// behavior itself stays, without it.
TEST(BmlDialect, UnknownAttributesAreNamed) {
  const auto r = bml::parseBlock(
      "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b\">\n"
      "  <head id=\"h\" lexeme=\"NOD\" strok=\"0.5\" velocity=\"2\"/>\n"
      "  <gaze id=\"g\" target=\"user\" influence=\"HEAD\" ready=\"1\"/>\n"
      "</bml>");
  ASSERT_TRUE(r.block) << r.format("unknown");
  ASSERT_EQ(r.block->behaviors.size(), 2u);
  ASSERT_EQ(count(r, bml::WarningType::CustomAttributeNotSupported), 1) << r.format("unknown");
  const bml::Warning& w = r.warnings.front();
  EXPECT_EQ(w.behaviorId, "h");
  EXPECT_EQ(w.line, 2);
  EXPECT_NE(w.message.find("<head> has no attributes 'strok', 'velocity'"), std::string::npos) << w.message;
  EXPECT_NE(w.message.find("strokeStart, stroke, strokeEnd"), std::string::npos) << w.message;
  EXPECT_FALSE(w.fatal);
  EXPECT_EQ(r.block->behaviors[0].attribute("strok"), nullptr);
  EXPECT_NE(r.block->behaviors[0].attribute("lexeme"), nullptr);
}

namespace {
const bml::Behavior* behavior(const bml::ParseResult& r, const std::string& id) {
  if (!r.block) return nullptr;
  for (const bml::Behavior& b : r.block->behaviors)
    if (b.id == id) return &b;
  return nullptr;
}
std::string value(const bml::Behavior* b, const char* name) {
  const bml::Attribute* a = b ? b->attribute(name) : nullptr;
  return a ? a->value : "<none>";
}
}  // namespace

// Standard forms the attribute-only reading missed, and SmartBody's spellings (issue 24, 5).
TEST(BmlDialect, PostureChildrenAndSmartBodySpellingsAreReadAsTheStandardForm) {
  const auto r = bml::parseBlock(
      "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b\">\n"
      "  <postureShift id=\"p\"><stance type=\"SITTING\"/></postureShift>\n"
      "  <posture id=\"q\" start=\"3\"><stance type=\"STANDING\"/><pose part=\"WHOLEBODY\" lexeme=\"RELAXED\"/></posture>\n"
      "  <head id=\"h\" type=\"NOD\" repeats=\"2\"/>\n"
      "  <head id=\"h2\" type=\"SHAKE\" repeats=\"1.4\" lexeme=\"TILT\"/>\n"
      "  <face id=\"f\" type=\"facs\" au=\"12\" amount=\"0.5\"/>\n"
      "  <gesture id=\"g\" name=\"Wave\"/>\n"
      "  <posture id=\"bad\"><stance/></posture>\n"
      "</bml>");
  ASSERT_TRUE(r.block) << r.format("forms");
  EXPECT_EQ(value(behavior(r, "p"), "stance"), "SITTING");
  EXPECT_EQ(value(behavior(r, "q"), "stance"), "STANDING");
  EXPECT_EQ(value(behavior(r, "q"), "lexeme"), "RELAXED");
  EXPECT_EQ(value(behavior(r, "h"), "lexeme"), "NOD");
  EXPECT_EQ(value(behavior(r, "h"), "repetition"), "2");
  EXPECT_EQ(value(behavior(r, "h2"), "lexeme"), "TILT") << "the standard spelling wins";
  EXPECT_EQ(value(behavior(r, "h2"), "repetition"), "1");
  ASSERT_NE(behavior(r, "f"), nullptr);
  EXPECT_EQ(behavior(r, "f")->type, "faceFacs");
  EXPECT_EQ(value(behavior(r, "f"), "au"), "12");
  EXPECT_EQ(value(behavior(r, "f"), "type"), "<none>");
  EXPECT_EQ(value(behavior(r, "g"), "lexeme"), "Wave");
  // What could only be read approximately, or not at all, is said where it is.
  const std::string all = r.format("forms");
  EXPECT_NE(all.find("forms:5:3: warning: CUSTOM_ATTRIBUTE_NOT_SUPPORTED: block 'b', behavior 'h2': repeats=\"1.4\" is "
                     "read as 1 repetitions"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("forms:8:21: warning: PARSING_FAILURE: block 'b', behavior 'bad': <stance> has no type"), std::string::npos) << all;
  EXPECT_EQ(r.warnings.size(), 2u) << all;
}

// SSML's <mark name> (SmartBody, Greta) and AsapRealizer's <tm id> are word marks, inside
// SSML elements too; the text is the words alone.
TEST(BmlDialect, SsmlMarksAndTimeMarkersAreSyncPoints) {
  const auto r = bml::parseBlock(
      "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b\">\n"
      "  <speech id=\"s1\" type=\"application/ssml+xml\"><text><speak>Hello <mark name=\"T1\"/>there, "
      "<prosody rate=\"slow\">my <mark name=\"T2\"/>friend</prosody>.</speak></text></speech>\n"
      "  <speech id=\"s2\">Good <tm id=\"tm1\"/>morning.</speech>\n"
      "  <head id=\"h\" lexeme=\"NOD\" stroke=\"s1:T2\"/>\n"
      "  <speech id=\"s3\">No <mark/>name.</speech>\n"
      "</bml>");
  ASSERT_TRUE(r.block) << r.format("ssml");
  const bml::Behavior* s1 = behavior(r, "s1");
  ASSERT_NE(s1, nullptr);
  EXPECT_EQ(s1->text, "Hello there, my friend.");
  ASSERT_EQ(s1->marks.size(), 2u);
  EXPECT_EQ(s1->marks[0].id, "T1");
  EXPECT_EQ(s1->marks[0].characterOffset, 6u);
  EXPECT_EQ(s1->marks[1].id, "T2");
  EXPECT_EQ(s1->text.substr(s1->marks[1].characterOffset), "friend.");
  const bml::Behavior* s2 = behavior(r, "s2");
  ASSERT_NE(s2, nullptr);
  ASSERT_EQ(s2->marks.size(), 1u);
  EXPECT_EQ(s2->text.substr(s2->marks[0].characterOffset), "morning.");
  // The head's stroke is scheduled at the mark.
  const bml::Schedule s = bml::scheduleParsed(r);
  ASSERT_NE(s.find("h"), nullptr);
  EXPECT_DOUBLE_EQ(*s.time("h", "stroke"), *s.time("s1", "T2"));
  EXPECT_NE(r.format("ssml").find("<mark> in speech text has no name"), std::string::npos) << r.format("ssml");
}

// SmartBody's own behaviors: <animation name speed> and <sbm:event message> / <event>.
TEST(BmlDialect, SmartBodyAnimationsAndEventsAreBehaviors) {
  const auto r = bml::parseBlock(
      "<bml xmlns:sbm=\"http://ict.usc.edu\">\n"
      "  <animation name=\"ChrBrad@Idle01\" speed=\"2\"/>\n"
      "  <sbm:event message=\"cue lights\" stroke=\"animation_1:stroke\"/>\n"
      "  <event message=\"second\" start=\"1\"/>\n"
      "  <animation speed=\"-1\"/>\n"
      "</bml>");
  ASSERT_TRUE(r.block) << r.format("sbm");
  EXPECT_TRUE(r.block->smartBody);
  ASSERT_EQ(r.block->behaviors.size(), 4u) << r.format("sbm");
  EXPECT_EQ(r.block->behaviors[0].type, "animation");
  EXPECT_EQ(r.block->behaviors[1].type, "event");
  EXPECT_EQ(value(&r.block->behaviors[1], "message"), "cue lights");
  const bml::Schedule s = bml::scheduleParsed(r);
  EXPECT_DOUBLE_EQ(*s.time("event_1", "stroke"), *s.time("animation_1", "stroke"));
  EXPECT_DOUBLE_EQ(*s.time("event_1", "start"), *s.time("event_1", "end")) << "an event is an instant";
  EXPECT_DOUBLE_EQ(*s.time("event_2", "stroke"), 1.0);
  const std::string all = r.format("sbm");
  EXPECT_NE(all.find("<animation> needs a name"), std::string::npos) << all;
  EXPECT_NE(all.find("speed=\"-1\" is not a positive number"), std::string::npos) << all;
  // <animation> alone makes Auto read the block as SmartBody's (no ids needed).
  EXPECT_TRUE(bml::parseBlock("<bml><animation name=\"Wave\"/></bml>").block);
}

// SmartBody's locomotion targets are z-up (issue 24, 9): "9 9 0" is the ground point x=9,
// z=9 in its dialect; BML's x y z is y-up. When the reading taken leaves a height, both
// readings are named.
TEST(BmlDialect, LocomotionTargetsAreReadInTheBlocksConvention) {
  auto waypoint = [](const bml::ParseResult& r, std::string& warning) {
    const bml::ReadParameters p = bml::readParameters(r.block->behaviors.at(0), BehaviorKind::Locomotion);
    warning = p.warning;
    const auto* l = std::get_if<LocomotionParameters>(&p.parameters);
    return l && l->waypoints.size() == 1 ? l->waypoints[0] : glm::vec2(-1e9f);
  };
  std::string warning;
  const auto sbm = bml::parseBlock("<bml xmlns:sbm=\"http://ict.usc.edu\"><locomotion target=\"9.0 9.0 0\"/></bml>");
  ASSERT_TRUE(sbm.block) << sbm.format("sbm");
  EXPECT_EQ(waypoint(sbm, warning), glm::vec2(9.0f, 9.0f));
  EXPECT_TRUE(warning.empty()) << warning;
  EXPECT_EQ(count(sbm, bml::WarningType::CustomAttributeNotSupported), 0) << sbm.format("sbm");
  const auto bml = bml::parseBlock("<bml id=\"b\"><locomotion id=\"l\" target=\"9.0 9.0 0\"/></bml>");
  ASSERT_TRUE(bml.block) << bml.format("bml");
  EXPECT_EQ(waypoint(bml, warning), glm::vec2(9.0f, 0.0f));
  EXPECT_NE(warning.find("read as BML's x y z (y up): the ground point x=9, z=0, its height 9 dropped (SmartBody's z-up "
                         "reading, in its dialect, would be x=9, z=9)"),
            std::string::npos)
      << warning;
  const auto flat = bml::parseBlock("<bml id=\"b\"><locomotion id=\"l\" target=\"2 0 3\"/></bml>");
  EXPECT_EQ(waypoint(flat, warning), glm::vec2(2.0f, 3.0f));
  EXPECT_TRUE(warning.empty()) << "y = 0: nothing to doubt";
  const auto high = bml::parseBlock("<act><bml><locomotion target=\"1 2 3\"/></bml></act>");
  ASSERT_TRUE(high.block);
  EXPECT_EQ(waypoint(high, warning), glm::vec2(1.0f, 2.0f));
  EXPECT_NE(high.format("sbm").find("read as SmartBody's (z up): the ground point x=1, z=2 here, its height 3 dropped (as "
                                    "BML's y-up x y z it would be x=1, z=3)"),
            std::string::npos)
      << high.format("sbm");
}

// Bad input across dialects: ids that sync references could not name, a block mixing
// SmartBody's forms into BML 1.0 (read as SmartBody's, its BML kept), another namespace.
TEST(BmlDialect, MalformedIdsAndMixedDialectsAreNamed) {
  const auto colon = bml::parseBlock("<bml id=\"b\"><head id=\"h:1\" lexeme=\"NOD\"/><head id=\"ok\" lexeme=\"NOD\"/></bml>");
  ASSERT_TRUE(colon.block);
  EXPECT_EQ(colon.block->behaviors.size(), 1u);
  EXPECT_NE(colon.format("m").find("<head> id 'h:1' has a ':' or a space"), std::string::npos) << colon.format("m");
  EXPECT_FALSE(bml::parseBlock("<bml id=\"a b\"><head id=\"h\" lexeme=\"NOD\"/></bml>").block);
  EXPECT_TRUE(bml::scheduleText("<bml id=\"b\"><required><head id=\"x y\" lexeme=\"NOD\"/></required></bml>").failed);
  // Mixed: BML 1.0's namespace, an sbm: event and a BMLA attribute in one block.
  const auto mixed = bml::parseBlock(
      "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" xmlns:sbm=\"http://ict.usc.edu\" "
      "xmlns:bmla=\"http://www.asap-project.org/bmla\" bmla:chunkAfter=\"prev\">\n"
      "  <head id=\"h\" lexeme=\"NOD\"/><sbm:event message=\"m\" stroke=\"h:stroke\"/>\n"
      "  <other:thing xmlns:other=\"urn:x\" id=\"t\"/>\n"
      "</bml>");
  ASSERT_TRUE(mixed.block) << mixed.format("mixed");
  EXPECT_TRUE(mixed.block->smartBody);
  EXPECT_EQ(mixed.block->behaviors.size(), 2u);
  EXPECT_EQ(mixed.block->bmla.chunkAfter, std::vector<std::string>{"prev"});
  EXPECT_EQ(count(mixed, bml::WarningType::CustomBehaviorNotSupported), 1) << mixed.format("mixed");
  // Generated ids never repeat, whatever the block gives itself.
  const auto taken = bml::parseBlock("<act><bml><head id=\"head_2\" lexeme=\"NOD\"/><head lexeme=\"NOD\"/>"
                                     "<head lexeme=\"NOD\"/><head id=\"head_1b\" lexeme=\"NOD\"/></bml></act>");
  ASSERT_TRUE(taken.block);
  std::vector<std::string> ids;
  for (const bml::Behavior& b : taken.block->behaviors) ids.push_back(b.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"head_2", "head_1", "head_3", "head_1b"}));
}

// SmartBody's <saccade>: a model (mode), a finish, or one saccade with sbm:duration kept.
TEST(BmlDialect, SaccadesAreReadIntoTheirParameters) {
  const auto r = bml::parseBlock(
      "<bml xmlns:sbm=\"http://ict.usc.edu\"><saccade mode=\"listen\"/><saccade finish=\"true\" start=\"5\"/>"
      "<saccade direction=\"45\" magnitude=\"15\" sbm:duration=\".5\"/><saccade mode=\"dream\"/></bml>");
  ASSERT_TRUE(r.block) << r.format("s");
  ASSERT_EQ(r.block->behaviors.size(), 4u);
  EXPECT_EQ(count(r, bml::WarningType::CustomAttributeNotSupported), 0) << r.format("s");
  auto read = [&](int i) { return bml::readParameters(r.block->behaviors.at(static_cast<std::size_t>(i)), BehaviorKind::Saccade); };
  EXPECT_EQ(std::get<SaccadeParameters>(read(0).parameters).mode, SaccadeMode::Listen);
  EXPECT_TRUE(std::get<SaccadeParameters>(read(1).parameters).finish);
  const auto one = std::get<SaccadeParameters>(read(2).parameters);
  EXPECT_EQ(one.mode, SaccadeMode::None);
  EXPECT_FLOAT_EQ(one.directionDegrees, 45.0f);
  EXPECT_FLOAT_EQ(one.magnitudeDegrees, 15.0f);
  EXPECT_EQ(r.block->behaviors[2].attribute("duration")->value, ".5");
  const bml::ReadParameters dream = read(3);
  EXPECT_EQ(std::get<SaccadeParameters>(dream.parameters).mode, SaccadeMode::Talk);
  EXPECT_NE(dream.warning.find("saccade mode 'DREAM' is not TALK, LISTEN or THINK"), std::string::npos) << dream.warning;
}
