// BML as other realizers' users write it (issue 24): Greta's draft namespace and
// lower-case compositions, and <required> around what cannot be realized. The blocks
// are written here after the published formats of those projects.
#include <gtest/gtest.h>

#include <cctype>
#include <string>
#include <vector>

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
      "<bml id=\"c\" xmlns:sbm=\"http://ict.usc.edu\"><required><sbm:animation id=\"a\" name=\"Wave\"/></required></bml>";
  EXPECT_TRUE(bml::scheduleText(custom).failed);
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
