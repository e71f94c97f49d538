#include <gtest/gtest.h>

#include <filesystem>

#include "marionette/bml/document.hpp"
#include "test_data.hpp"

using namespace marionette;
using marionette::test::readFile;

namespace {
std::string corpus(const std::string& name) { return std::string(MARIONETTE_SHARED_DIR) + "/bml-corpus/openbmlparser/" + name; }
}  // namespace

TEST(BmlDocument, MalformedXmlNamesFileLineAndColumn) {
  const std::string path = corpus("testinvalidxml.xml");
  MARIONETTE_REQUIRE_FILE(path);
  bml::ParseResult r = bml::parseBlock(readFile(path), path);
  ASSERT_FALSE(r.block.has_value());
  ASSERT_EQ(r.diagnostics.items.size(), 1u);
  const Diagnostic& d = r.diagnostics.items[0];
  EXPECT_EQ(d.file, path);
  EXPECT_EQ(d.line, 26);  // the stray second </speech>
  EXPECT_GT(d.column, 0);
  EXPECT_NE(d.message.find("malformed XML"), std::string::npos);
}

TEST(BmlDocument, MissingIdsAndDuplicatesAreErrors) {
  auto r = bml::parseBlock("<bml><head lexeme='NOD'/></bml>", "inline");
  EXPECT_FALSE(r.block);
  EXPECT_NE(r.diagnostics.format().find("inline:1:1: error: <bml> has no id"), std::string::npos);
  r = bml::parseBlock("<bml id='b'>\n  <head lexeme='NOD'/>\n  <gaze id='g' target='x'/><gaze id='g'/></bml>", "s");
  EXPECT_FALSE(r.block);
  EXPECT_NE(r.diagnostics.format().find("s (block b):2:3: error: <head> has no id"), std::string::npos);
  EXPECT_NE(r.diagnostics.format().find("used twice"), std::string::npos);
  r = bml::parseBlock("<notbml id='x'/>", "s");
  EXPECT_FALSE(r.block);
  r = bml::parseBlock("", "empty");
  EXPECT_FALSE(r.block);
}

TEST(BmlDocument, EveryCorpusFileParsesOrFailsWithAPlace) {
  const std::string dir = std::string(MARIONETTE_SHARED_DIR) + "/bml-corpus/openbmlparser";
  MARIONETTE_REQUIRE_FILE(dir);
  int parsed = 0, rejected = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".xml") continue;
    const std::string path = e.path().string();
    auto r = bml::parseBlock(readFile(path), path);
    // testinvalidxml2.xml is well-formed XML with a bad sync reference
    // ("nod1:relax:2"): the scheduler rejects it, not this layer.
    const bool invalid = e.path().filename() == "testinvalidxml.xml";
    if (invalid) {
      EXPECT_FALSE(r.block) << path;
      ASSERT_FALSE(r.diagnostics.items.empty()) << path;
      EXPECT_GT(r.diagnostics.items[0].line, 0) << path;
      ++rejected;
    } else {
      EXPECT_TRUE(r.block) << path << "\n" << r.diagnostics.format();
      if (r.block) {
        EXPECT_FALSE(r.block->id.empty());
      }
      ++parsed;
    }
  }
  EXPECT_GE(parsed, 50);
  EXPECT_EQ(rejected, 1);
}

TEST(BmlDocument, BehaviorsAttributesAndSpeechText) {
  const std::string path = corpus("testnod.xml");
  MARIONETTE_REQUIRE_FILE(path);
  auto r = bml::parseBlock(readFile(path), path);
  ASSERT_TRUE(r.block);
  EXPECT_EQ(r.block->id, "bml1");
  ASSERT_EQ(r.block->behaviors.size(), 1u);
  const bml::Behavior& b = r.block->behaviors[0];
  EXPECT_EQ(b.type, "head");
  EXPECT_EQ(b.id, "nod1");
  ASSERT_NE(b.attribute("lexeme"), nullptr);
  EXPECT_EQ(*b.attribute("lexeme"), "NOD");
  EXPECT_EQ(b.line, 12);
  EXPECT_EQ(b.column, 2);  // after a tab
  auto s = bml::parseBlock("<bml id='b'><speech id='s1'><text>Hello <sync id='x'/> world</text></speech></bml>", "s");
  ASSERT_TRUE(s.block);
  EXPECT_EQ(s.block->behaviors[0].text, "Hello world");
}
