#include <gtest/gtest.h>

#include <filesystem>

#include "marionette/bml/document.hpp"
#include "test_data.hpp"

using namespace marionette;
using marionette::test::readFile;

namespace {
std::string corpus(const std::string& name) { return ::marionette::test::sharedDir() + "/bml-corpus/openbmlparser/" + name; }
bool hasWarning(const bml::ParseResult& r, bml::WarningType type) {
  for (const auto& w : r.warnings)
    if (w.type == type) return true;
  return false;
}
}  // namespace

TEST(BmlDocument, MalformedXmlNamesFileLineAndColumn) {
  const std::string path = corpus("testinvalidxml.xml");
  MARIONETTE_REQUIRE_FILE(path);
  bml::ParseResult r = bml::parseBlock(readFile(path));
  ASSERT_FALSE(r.block.has_value());
  ASSERT_EQ(r.warnings.size(), 1u);
  const bml::Warning& w = r.warnings[0];
  EXPECT_EQ(w.type, bml::WarningType::ParsingFailure);
  EXPECT_TRUE(w.fatal);
  EXPECT_EQ(w.line, 26);  // the stray second </speech>
  EXPECT_GT(w.column, 0);
  const std::string text = r.format(path);
  EXPECT_NE(text.find(path + ":26:"), std::string::npos) << text;
  EXPECT_NE(text.find("error: PARSING_FAILURE: malformed XML"), std::string::npos) << text;
}

TEST(BmlDocument, MissingIdsAndDuplicatesAreTypedWarnings) {
  auto r = bml::parseBlock("<bml><head lexeme='NOD'/></bml>");
  EXPECT_FALSE(r.block);
  EXPECT_NE(r.format("inline").find("inline:1:1: error: PARSING_FAILURE: <bml> has no id"), std::string::npos)
      << r.format("inline");
  r = bml::parseBlock("<bml id='b'>\n  <head lexeme='NOD'/>\n  <gaze id='g' target='x'/><gaze id='g'/></bml>");
  ASSERT_TRUE(r.block);  // the block survives; the faulty behaviors are left out, with warnings
  EXPECT_EQ(r.block->behaviors.size(), 1u);
  const std::string text = r.format("s");
  EXPECT_NE(text.find("s:2:3: warning: PARSING_FAILURE: block 'b': <head> has no id"), std::string::npos) << text;
  EXPECT_NE(text.find("used twice"), std::string::npos);
  EXPECT_FALSE(bml::parseBlock("<notbml id='x'/>").block);
  EXPECT_FALSE(bml::parseBlock("").block);
}

TEST(BmlDocument, CustomElementsAttributesAndUnknownTypes) {
  auto r = bml::parseBlock(
      "<bml xmlns='http://www.bml-initiative.org/bml/bml-1.0' xmlns:x='urn:custom' xmlns:sbm='urn:sbm' id='b'>"
      "<x:dance id='d1'/><head id='h1' lexeme='NOD' x:speed='2' sbm:joint-range='1'/><juggle id='j1'/></bml>");
  ASSERT_TRUE(r.block);
  ASSERT_EQ(r.block->behaviors.size(), 1u);
  EXPECT_EQ(r.block->behaviors[0].id, "h1");
  EXPECT_EQ(r.block->behaviors[0].attributes.size(), 1u);  // lexeme only
  EXPECT_TRUE(hasWarning(r, bml::WarningType::CustomBehaviorNotSupported));
  EXPECT_TRUE(hasWarning(r, bml::WarningType::CustomAttributeNotSupported));
  EXPECT_TRUE(hasWarning(r, bml::WarningType::BehaviorTypeNotSupported));
  for (const auto& w : r.warnings) EXPECT_FALSE(w.fatal);
}

TEST(BmlDocument, SmartBodyActWrapperAndBodyPosture) {
  auto r = bml::parseBlock("<act><bml id='b'><body id='p1' posture='ChrUtah_Idle001'/></bml></act>");
  ASSERT_TRUE(r.block);
  ASSERT_EQ(r.block->behaviors.size(), 1u);
  EXPECT_EQ(r.block->behaviors[0].type, "posture");
}

TEST(BmlDocument, AMarkAfterTheLastWordAndItsSpaceIsAtTheEndOfTheText) {
  // The offset counted the space after the mark, which collapsing the text trims away.
  for (const char* text : {"Hello there <sync id='m'/> ", "Hello there <sync id='m'/>   \n ", "Hello there<sync id='m'/>"}) {
    auto r = bml::parseBlock(std::string("<bml id='b'><speech id='s'><text>") + text + "</text></speech></bml>");
    ASSERT_TRUE(r.block) << r.format("s");
    const auto& speech = r.block->behaviors.at(0);
    EXPECT_EQ(speech.text, "Hello there") << text;
    ASSERT_EQ(speech.marks.size(), 1u) << text;
    EXPECT_EQ(speech.marks[0].characterOffset, speech.text.size()) << text;
  }
}

TEST(BmlDocument, ConstraintsRequiredAndSpeechMarks) {
  auto r = bml::parseBlock(
      "<bml id='b'><required><head id='h1' lexeme='NOD'/></required>"
      "<speech id='s'><text>Hello <sync id='m1'/>big   world<sync id='m2'/></text></speech>"
      "<constraint id='c'><synchronize><sync ref='s:m1'/><sync ref='h1:stroke'/></synchronize>"
      "<after ref='s:m2'><sync ref='h1:end'/></after></constraint></bml>");
  ASSERT_TRUE(r.block) << r.format("s");
  const auto& b = *r.block;
  ASSERT_EQ(b.behaviors.size(), 2u);
  EXPECT_TRUE(b.behaviors[0].required);
  EXPECT_EQ(b.behaviors[1].text, "Hello big world");
  ASSERT_EQ(b.behaviors[1].marks.size(), 2u);
  EXPECT_EQ(b.behaviors[1].marks[0].characterOffset, 6u);
  EXPECT_EQ(b.behaviors[1].marks[1].characterOffset, 15u);
  ASSERT_EQ(b.constraints.size(), 2u);
  EXPECT_EQ(b.constraints[0].kind, bml::Constraint::Kind::Synchronize);
  EXPECT_EQ(b.constraints[0].syncs.size(), 2u);
  EXPECT_EQ(b.constraints[1].kind, bml::Constraint::Kind::After);
  EXPECT_EQ(b.constraints[1].anchor.ref, "s:m2");
}

TEST(BmlDocument, EveryCorpusFileParsesOrFailsWithAPlace) {
  const std::string dir = ::marionette::test::sharedDir() + "/bml-corpus/openbmlparser";
  MARIONETTE_REQUIRE_FILE(dir);
  int parsed = 0, rejected = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    const std::string path = e.path().string();
    auto r = bml::parseBlock(readFile(path));
    // testinvalidxml2.xml is well-formed XML; its "nod1:relax:2" is a repetition
    // index here (see sync_ref_test.cpp).
    if (e.path().filename() == "testinvalidxml.xml") {
      EXPECT_FALSE(r.block) << path;
      ASSERT_FALSE(r.warnings.empty()) << path;
      EXPECT_GT(r.warnings[0].line, 0) << path;
      ++rejected;
    } else {
      EXPECT_TRUE(r.block) << path << "\n" << r.format(path);
      ++parsed;
    }
  }
  EXPECT_EQ(parsed, 57);
  EXPECT_EQ(rejected, 1);
}

TEST(BmlDocument, BehaviorsAttributesAndPlaces) {
  const std::string path = corpus("testnod.xml");
  MARIONETTE_REQUIRE_FILE(path);
  auto r = bml::parseBlock(readFile(path));
  ASSERT_TRUE(r.block);
  EXPECT_EQ(r.block->id, "bml1");
  ASSERT_EQ(r.block->behaviors.size(), 1u);
  const bml::Behavior& b = r.block->behaviors[0];
  EXPECT_EQ(b.type, "head");
  EXPECT_EQ(b.id, "nod1");
  ASSERT_NE(b.attribute("lexeme"), nullptr);
  EXPECT_EQ(b.attribute("lexeme")->value, "NOD");
  EXPECT_EQ(b.line, 12);
  EXPECT_EQ(b.column, 2);  // after a tab
}
