// BML's two XML parsers (bml/src/xml_tree.hpp): pugixml (native) and rapidxml (the web
// build) must give the same tree, the same BML result and warnings, and fail at the same
// byte on malformed text, so that a block reads the same, line:column included, in either.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "document_detail.hpp"
#include "marionette/bml/document.hpp"
#include "test_data.hpp"
#include "xml_tree.hpp"

using namespace marionette;
using namespace marionette::bml;
using namespace marionette::bml::detail;
using marionette::test::readFile;

namespace {

std::string shown(std::string_view text) {
  std::string out;
  for (char c : text.substr(0, 70)) {
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c == '\0') out += "\\0";
    else if (static_cast<unsigned char>(c) >= 128) out += "\\x" + std::to_string(static_cast<unsigned char>(c));
    else out += c;
  }
  return (text.size() > 70 ? out + "..." : out) + " (" + std::to_string(text.size()) + " bytes)";
}

// The first difference between two trees, in words ("" when equal).
std::string treeDifference(const XmlTree& a, const XmlTree& b) {
  if (a.root != b.root) return "root " + std::to_string(a.root) + " vs " + std::to_string(b.root);
  if (a.nodes.size() != b.nodes.size())
    return std::to_string(a.nodes.size()) + " nodes vs " + std::to_string(b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const XmlNode &x = a.nodes[i], &y = b.nodes[i];
    if (x == y) continue;
    std::ostringstream s;
    s << "node " << i << ": <" << x.name << "> vs <" << y.name << ">, value '" << shown(x.value) << "' vs '"
      << shown(y.value) << "', offset " << x.offset << " vs " << y.offset << ", " << x.attributes.size() << " vs "
      << y.attributes.size() << " attributes";
    for (std::size_t k = 0; k < std::min(x.attributes.size(), y.attributes.size()); ++k)
      if (!(x.attributes[k] == y.attributes[k]))
        s << "; attribute " << x.attributes[k].name << "='" << shown(x.attributes[k].value) << "' vs "
          << y.attributes[k].name << "='" << shown(y.attributes[k].value) << "'";
    return s.str();
  }
  return "";
}

// Both parsers on `text`: the same success, tree, or error offset.
void expectSameParse(std::string_view text, const std::string& what) {
  const XmlParseResult p = parseXmlWithPugixml(text), r = parseXmlWithRapidxml(text);
  ASSERT_EQ(p.ok, r.ok) << what << ": " << shown(text) << "\n  pugixml: " << (p.ok ? "ok" : p.errorMessage)
                        << "\n  rapidxml: " << (r.ok ? "ok" : r.errorMessage);
  if (p.ok) {
    EXPECT_EQ(treeDifference(p.tree, r.tree), "") << what << ": " << shown(text);
    EXPECT_TRUE(p.tree == r.tree) << what;
  } else {
    EXPECT_EQ(p.errorOffset, r.errorOffset) << what << ": " << shown(text) << "\n  pugixml: " << p.errorMessage
                                            << "\n  rapidxml: " << r.errorMessage;
    EXPECT_TRUE(r.tree.nodes.empty() && p.tree.nodes.empty()) << what << ": a failed parse leaves no tree";
    if (r.errorMessage.find("nested more than") == std::string::npos) {  // the depth limit is neither parser's
      EXPECT_EQ(r.errorMessage.rfind("rapidxml: ", 0), 0u) << r.errorMessage;
    }
  }
}

// parseBlock's result with each parser: the same block and the same warnings (type,
// place, fatality; the words too, except a malformed-XML failure's, which are the parser's).
void expectSameBlock(std::string_view text, const std::string& what) {
  for (const Dialect dialect : {Dialect::Auto, Dialect::Bml, Dialect::SmartBody}) {
    ParseOptions options;
    options.dialect = dialect;
    const ParseResult p = parseBlockWith(text, options, parseXmlWithPugixml);
    const ParseResult r = parseBlockWith(text, options, parseXmlWithRapidxml);
    const std::string where = what + " (" + std::string(toString(dialect)) + ")";
    ASSERT_EQ(p.block.has_value(), r.block.has_value()) << where;
    ASSERT_EQ(p.warnings.size(), r.warnings.size()) << where << "\n" << p.format("pugixml") << r.format("rapidxml");
    for (std::size_t k = 0; k < p.warnings.size(); ++k) {
      const Warning &x = p.warnings[k], &y = r.warnings[k];
      EXPECT_EQ(x.type, y.type) << where << ": " << x.message;
      EXPECT_EQ(x.line, y.line) << where << ": " << x.message << " / " << y.message;
      EXPECT_EQ(x.column, y.column) << where << ": " << x.message << " / " << y.message;
      EXPECT_EQ(x.fatal, y.fatal) << where;
      EXPECT_EQ(x.blockId, y.blockId) << where;
      EXPECT_EQ(x.behaviorId, y.behaviorId) << where;
      if (x.message.rfind("malformed XML: ", 0) == 0 && x.message != y.message)
        EXPECT_EQ(y.message.rfind("malformed XML: rapidxml: ", 0), 0u) << where << ": " << y.message;
      else
        EXPECT_EQ(x.message, y.message) << where;
    }
    if (!p.block) continue;
    const Block &a = *p.block, &b = *r.block;
    EXPECT_EQ(a.id, b.id) << where;
    EXPECT_EQ(a.characterId, b.characterId) << where;
    EXPECT_EQ(a.composition, b.composition) << where;
    EXPECT_EQ(std::tie(a.line, a.column), std::tie(b.line, b.column)) << where;
    EXPECT_EQ(a.bmla.interrupt, b.bmla.interrupt) << where;
    EXPECT_EQ(a.bmla.onStart, b.bmla.onStart) << where;
    ASSERT_EQ(a.behaviors.size(), b.behaviors.size()) << where;
    for (std::size_t k = 0; k < a.behaviors.size(); ++k) {
      const Behavior &x = a.behaviors[k], &y = b.behaviors[k];
      EXPECT_EQ(x.id, y.id) << where;
      EXPECT_EQ(x.type, y.type) << where;
      EXPECT_EQ(x.text, y.text) << where << ": " << x.id;
      EXPECT_EQ(std::tie(x.line, x.column), std::tie(y.line, y.column)) << where << ": " << x.id;
      ASSERT_EQ(x.attributes.size(), y.attributes.size()) << where << ": " << x.id;
      for (std::size_t m = 0; m < x.attributes.size(); ++m)
        EXPECT_EQ(x.attributes[m].name + "=" + x.attributes[m].value, y.attributes[m].name + "=" + y.attributes[m].value)
            << where << ": " << x.id;
      ASSERT_EQ(x.marks.size(), y.marks.size()) << where << ": " << x.id;
      for (std::size_t m = 0; m < x.marks.size(); ++m) {
        EXPECT_EQ(x.marks[m].id, y.marks[m].id) << where;
        EXPECT_EQ(x.marks[m].characterOffset, y.marks[m].characterOffset) << where;
      }
    }
    ASSERT_EQ(a.constraints.size(), b.constraints.size()) << where;
    for (std::size_t k = 0; k < a.constraints.size(); ++k) {
      EXPECT_EQ(a.constraints[k].anchor.ref, b.constraints[k].anchor.ref) << where;
      ASSERT_EQ(a.constraints[k].syncs.size(), b.constraints[k].syncs.size()) << where;
      for (std::size_t m = 0; m < a.constraints[k].syncs.size(); ++m)
        EXPECT_EQ(a.constraints[k].syncs[m].ref + "@" + std::to_string(a.constraints[k].syncs[m].line),
                  b.constraints[k].syncs[m].ref + "@" + std::to_string(b.constraints[k].syncs[m].line))
            << where;
    }
  }
}

// Every .xml under `dir`, sorted.
std::vector<std::string> xmlFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (std::filesystem::exists(dir))
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
      if (e.path().extension() == ".xml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

const char* kValidBlock = "<bml xmlns=\"http://www.bml-initiative.org/bml/bml-1.0\" id=\"b1\" characterId=\"robot\">\r\n"
                          "  <speech id=\"s1\"><text>Hello &amp; welcome, <sync id=\"w1\"/>nice to see you.</text></speech>\n"
                          "  <head id=\"h1\" lexeme='NOD' start=\"s1:w1\"/><!-- a nod -->\n"
                          "  <constraint id=\"c1\"><synchronize><sync ref=\"h1:end\"/><sync ref=\"s1:end\"/></synchronize></constraint>\n"
                          "</bml>\n";

}  // namespace

TEST(XmlParsersOnCorpus, EveryFileGivesTheSameTreeAndTheSameBlock) {
  std::vector<std::string> files = xmlFiles(test::sharedDir() + "/bml-corpus");
  ASSERT_GE(files.size(), 50u) << "the BML corpus (../shared/bml-corpus) is missing";
  const std::vector<std::string> own = xmlFiles(test::sourceFile("assets/bml"));
  ASSERT_GE(own.size(), 30u) << "the project's own blocks (assets/bml)";
  files.insert(files.end(), own.begin(), own.end());
  for (const std::string& repro : xmlFiles(test::sharedDir() + "/repro")) files.push_back(repro);
  std::size_t parsed = 0;
  for (const std::string& file : files) {
    const std::string text = readFile(file);
    ASSERT_FALSE(text.empty()) << file;
    expectSameParse(text, file);
    expectSameBlock(text, file);
    parsed += parseXmlWithPugixml(text).ok ? 1 : 0;
  }
  EXPECT_GE(parsed + 2, files.size()) << "the corpus's two invalid files aside, every file is XML";
}

TEST(XmlParsers, WellFormedEdgeCasesGiveTheSameTree) {
  const std::vector<std::string> texts = {
      kValidBlock,
      "<bml id='b'/>",
      "\xEF\xBB\xBF<bml id='b'/>",  // UTF-8 BOM
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE bml [<!ELEMENT bml ANY>]>\n<!-- c --><?pi x?><bml id='b'/>",
      "<bml id='b'><?xml version='1.0'?><!-- -- --></bml>",
      "<bml id='a&lt;&gt;&amp;&quot;&apos;b'>x &lt; y &#65;&#x42;&#x10437;&#0;z</bml>",  // entities; &#0; ends the text
      "<bml id='&foo; &amp &#; &#x; &#12a; &#X41; &am;p &ap &quo &' x=\"&#xFFFFFFFF;&#99999999999;\">&bar; & &#xg;</bml>",
      "<bml id='b'\r\n x='a\r\nb\tc\nd\re  f'>line\r\nline\rline\n<![CDATA[cd\r\nata & <no> ]] ]]></bml>",
      "<bml id='<'>a > b</bml>",  // '<' in an attribute value: both accept it
      "<bml id=\"it's\" x='\"q\"'/>",
      "<bml id='b'>   <a/>  \n\t <b>  text  </b>\n</bml>",  // whitespace-only text is dropped
      "<bml id='b'/>trailing text",                       // text after the root: both skip it
      "leading text<bml id='b'/>",
      "<bml id='b'/><second id='c'/>more<third/>",
      "<bml id='b'/>\0</garbage>",  // both stop at a NUL byte
      "<bml id='b'></bml >",
      "<bml\tid = 'b' \n/>",
      "<sbm:act xmlns:sbm='x'><bml><sbm:event message='m'/></bml></sbm:act>",
      "<bml id='b'><speech id='s'><text><![CDATA[a]]>b<mark name='m'/>c&#10;d</text></speech></bml>",
      "<a\xC3\xA9 \xC3\xA9t\xC3\xA9='\xE2\x82\xAC'>\xC3\xBC</a\xC3\xA9>",  // non-ASCII names
      "<a.b-c_d:e x.y-z='1'/>",
      "<!DOCTYPE bml SYSTEM \"a>b\"><bml id='b'/>",  // rapidxml alone ends this DOCTYPE at the quoted '>'
      "<!DOCTYPE bml [<!ENTITY x \"]>\"><![ <![ x ]]> ]]>]><bml id='b'/>",
  };
  for (const std::string& text : texts) {
    expectSameParse(text, "well-formed");
    EXPECT_TRUE(parseXmlWithPugixml(text).ok) << shown(text);
  }
  // The tree is what pugixml reads: spot checks that would catch a backend reading otherwise.
  const XmlParseResult r = parseXmlWithRapidxml("<bml id='a&lt;b' x='1\r\n2'>p &amp; q\r\n<c/></bml>");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(*r.tree[r.tree.root].attribute("id"), "a<b");
  EXPECT_EQ(*r.tree[r.tree.root].attribute("x"), "1 2");
  EXPECT_EQ(r.tree[r.tree[r.tree.root].firstChild].value, "p & q\n");
  EXPECT_EQ(r.tree[r.tree[r.tree.root].lastChild].offset, 38u);  // the name, after the '<'
}

TEST(XmlParsers, MalformedDocumentsFailAtTheSameOffset) {
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"empty", ""},
      {"only whitespace", " \n\t\r\n "},
      {"only a comment", "<!-- nothing else -->"},
      {"only a processing instruction", "<?xml version='1.0'?>"},
      {"only a DOCTYPE", "<!DOCTYPE bml>"},
      {"only a BOM", "\xEF\xBB\xBF"},
      {"unclosed root", "<bml id='b'>"},
      {"unclosed root after a BOM", "\xEF\xBB\xBF<bml id='b'><head id='h'/>"},
      {"unclosed child", "<bml id='b'><head id='h'></bml>"},
      {"mismatched end tag", "<bml id='b'></bm>"},
      {"longer end tag", "<bml id='b'></bmlx>"},
      {"space in end tag", "<bml id='b'></ bml>"},
      {"end tag after the root", "<bml id='b'/></bml>"},
      {"only an end tag", "</bml>"},
      {"attribute value without quotes", "<bml id=b/>"},
      {"missing closing quote", "<bml id='b/>"},
      {"attribute without value", "<bml id='b' required/>"},
      {"attribute without =", "<bml id 'b'/>"},
      {"no space between attributes", "<bml id='b'x='1'/>"},
      {"tag not closed", "<bml id='b'><head id='h' lexeme='NOD'</bml>"},
      {"space before />", "<bml id='b'><head/ ></bml>"},
      {"empty tag", "<>"},
      {"space after <", "< bml id='b'/>"},
      {"name starting with a digit", "<1bml/>"},
      {"bad character in a name", "<bml$ id='b'/>"},
      {"bad character in an attribute name", "<bml i$d='b'/>"},
      {"a last <", "<bml id='b'/><"},
      {"a last < inside", "<bml id='b'><"},
      {"unterminated CDATA", "<bml id='b'><![CDATA[no end</bml>"},
      {"CDATA without >", "<bml id='b'><![CDATA[x]]</bml>"},
      {"misspelt CDATA", "<bml id='b'><![CDAT[x]]></bml>"},
      {"unterminated comment", "<bml id='b'><!-- no end</bml>"},
      {"bad comment start", "<bml id='b'><!- x --></bml>"},
      {"DOCTYPE inside an element", "<bml id='b'><!DOCTYPE x></bml>"},
      {"processing instruction without target", "<bml id='b'><? ?></bml>"},
      {"NUL byte inside the root", std::string("<bml id='b'>\0</bml>", 19)},
      {"NUL byte first", std::string("\0<bml id='b'/>", 14)},
      {"deeply nested", deep},
      {"truncated UTF-8 BOM", "\xEF\xBB"},
      {"DOCTYPE with a bad declaration inside", "<!DOCTYPE bml [<!ELE&MENT bml A<Y>]><bml id='b'/>"},
      {"unterminated DOCTYPE", "<!DOCTYPE bml [<!ELEMENT bml ANY>"},
      {"DOCTYPE with an unterminated string", "<!DOCTYPE bml SYSTEM 'x><bml id='b'/>"},
      {"unrecognized <!", "<bml id='b'><!ELEMENT x></bml>"},
      {"'?' ending a name", "<bml? id='b'/>"},
      {"end tag with a bad character", "<bml id='b'></bml[>"},
      {"truncated end tag", "<bml id='b'></bml"},
      {"truncated attribute name", "<bml x"},
  };
  ASSERT_GE(cases.size(), 25u);
  std::ostringstream table;  // shown on failure: where each parser stopped
  for (const auto& [what, text] : cases) {
    const XmlParseResult p = parseXmlWithPugixml(text), r = parseXmlWithRapidxml(text);
    table << what << ": pugixml " << (p.ok ? "ok" : std::to_string(p.errorOffset) + " " + p.errorMessage) << " | "
          << (r.ok ? "ok" : std::to_string(r.errorOffset) + " " + r.errorMessage) << "\n";
    EXPECT_FALSE(p.ok) << what;
    expectSameParse(text, what);
    expectSameBlock(text, what);
  }
  std::cout << table.str();
}

TEST(XmlParsers, EveryTruncationOfABlockFailsAtTheSameOffset) {
  const std::string block = kValidBlock;
  for (std::size_t n = 0; n < block.size(); ++n) {
    const std::string prefix = block.substr(0, n);
    expectSameParse(prefix, "the block's first " + std::to_string(n) + " bytes");
    if (HasFatalFailure()) return;
  }
  expectSameParse(block, "the whole block");
  EXPECT_TRUE(parseXmlWithRapidxml(block).ok);
}

// Random edits of valid blocks (a byte changed, removed or inserted, from XML's marks):
// the parsers agree on every result (a difference found this way is named in the failure).
TEST(XmlParsers, MutatedBlocksGiveTheSameResult) {
  const std::vector<std::string> seeds = {
      kValidBlock,
      "<?xml version='1.0'?>\n<!DOCTYPE bml [<!ELEMENT bml ANY>]>\n<!-- c --><bml id='b' x='a&lt;&#65;'>"
      "<![CDATA[c\r\nd]]>t\r\n&amp; &foo;<a/><?p y?></bml>\n",
      "\xEF\xBB\xBF<act><bml>\n<sbm:event message='m' xmlns:sbm='x'/></bml></act>"};
  const std::string marks = std::string("<>/='\"!?-[]&;# \n\rax:$1") + '\0';
  std::uint32_t state = 12345;
  auto next = [&] { return state = state * 1664525u + 1013904223u, state >> 8; };
  int differences = 0, failures = 0;
  for (int k = 0; k < 20000 && differences < 5; ++k) {
    std::string t = seeds[next() % seeds.size()];
    for (std::uint32_t edits = 1 + next() % 3; edits > 0 && !t.empty(); --edits) {
      const std::size_t at = next() % t.size();
      const char mark = marks[next() % marks.size()];
      switch (next() % 3) {
        case 0: t[at] = mark; break;
        case 1: t.erase(at, 1 + next() % 4); break;
        default: t.insert(at, 1, mark); break;
      }
    }
    const XmlParseResult p = parseXmlWithPugixml(t), r = parseXmlWithRapidxml(t);
    failures += p.ok ? 0 : 1;
    if (p.ok == r.ok && (p.ok ? p.tree == r.tree : p.errorOffset == r.errorOffset)) continue;
    ++differences;
    ADD_FAILURE() << shown(t) << "\n  pugixml: " << (p.ok ? "ok" : std::to_string(p.errorOffset) + " " + p.errorMessage)
                  << "\n  rapidxml: " << (r.ok ? "ok" : std::to_string(r.errorOffset) + " " + r.errorMessage);
  }
  EXPECT_GT(failures, 5000) << "most edits make the text malformed";
}

TEST(XmlParsers, DeepNestingFailsWithBothInsteadOfOverflowingTheStack) {
  auto nested = [](std::size_t levels) {
    std::string s = "<bml id='b'>";
    for (std::size_t i = 1; i < levels; ++i) s += "<x a='/>'>";  // a quoted "/>" is no end
    for (std::size_t i = 1; i < levels; ++i) s += "</x>";
    return s + "</bml>";
  };
  expectSameParse(nested(kMaxXmlDepth), "as deep as allowed");
  EXPECT_TRUE(parseXmlWithRapidxml(nested(kMaxXmlDepth)).ok);
  const std::string tooDeep = nested(kMaxXmlDepth + 1);
  const XmlParseResult r = parseXmlWithRapidxml(tooDeep);
  ASSERT_FALSE(r.ok);
  EXPECT_EQ(r.errorOffset, tooDeep.rfind("<x a='/>'>"));  // the innermost element's '<'
  EXPECT_NE(r.errorMessage.find("nested more than"), std::string::npos) << r.errorMessage;
  expectSameParse(tooDeep, "one level too deep");
  expectSameParse(nested(200000), "200000 levels");
  const ParseResult block = parseBlock(nested(200000));
  ASSERT_EQ(block.warnings.size(), 1u);
  EXPECT_TRUE(block.warnings[0].fatal);
  EXPECT_NE(block.warnings[0].message.find("malformed XML: "), std::string::npos);
}

TEST(XmlParsers, ParseBlockGivesTheSameWarningsWithEither) {
  const std::vector<std::string> blocks = {
      kValidBlock,
      "<bml id='b' composition='append' bmla:interrupt='x, y' xmlns:bmla='http://www.asap-project.org/bmla' other='1'>"
      "\n  <head id='h' lexeme='NOD' strok='1' sbm:x='2'/>\n  <gaze lexeme='x'/>\n  <head id='h' lexeme='SHAKE'/>"
      "\n  <my:thing xmlns:my='urn:x' id='t'/>\n  <required><gesture id='g' lexeme='BEAT'/><foo id='f'/></required>"
      "\n  <posture id='p'><stance type='SITTING'/><pose/></posture>\n  <constraint id='c'><before ref='h:end'>"
      "<sync ref='g:start'/></before><oops/></constraint>\n</bml>",
      "<act><bml><head lexeme='NOD'/><sbm:event message='m' xmlns:sbm='urn:sbm'/></bml></act>",
      "<bml id='b'>\r\n<speech id='s'>\r\n<text>One\r\n<sync id='a'/> two <mark/> <tm id='t'/>three &amp; four</text></speech></bml>",
      "<bml id='b'><head id='h' lexeme='NOD'\r\n",  // malformed: the warning's line:column
      "<bml id='b'>\n\n   </bmx>",
      "<nobml/>",
      "",
  };
  for (const std::string& text : blocks) expectSameBlock(text, shown(text));
  // The public entry point uses this build's parser (MARIONETTE_BML_XML).
  const ParseResult r = parseBlock("<bml id='b'><head id='h'></bml>");
  ASSERT_EQ(r.warnings.size(), 1u);
#ifdef MARIONETTE_BML_XML_RAPIDXML
  EXPECT_EQ(r.warnings[0].message.rfind("malformed XML: rapidxml: ", 0), 0u) << r.warnings[0].message;
#else
  EXPECT_EQ(r.warnings[0].message.find("rapidxml"), std::string::npos) << r.warnings[0].message;
#endif
}
