// The XML of a BML block as document.cpp reads it, whichever parser read it: pugixml
// natively, rapidxml in the web build (no pugixml there). Both backends fill the same
// flat tree, so that a block gives the same result, warnings and line:column with either
// (tests/bml/xml_parser_test.cpp compares them).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace marionette::bml::detail {

struct XmlAttribute {
  std::string name, value;  // the value with entities decoded, whitespace as pugixml's parse_default has it
  bool operator==(const XmlAttribute&) const = default;
};

struct XmlNode {
  enum class Type : std::uint8_t { Element, Pcdata, Cdata };
  Type type = Type::Element;
  std::string name;                      // elements
  std::string value;                     // text: entities decoded, "\r\n" and "\r" as "\n"
  std::vector<XmlAttribute> attributes;  // in document order
  std::size_t offset = 0;  // elements: byte offset of the name in the text ('<' is one before)
  int parent = -1, firstChild = -1, lastChild = -1, nextSibling = -1, previousSibling = -1;
  bool operator==(const XmlNode&) const = default;

  // The value of the attribute `n`, or nullptr.
  [[nodiscard]] const std::string* attribute(std::string_view n) const noexcept {
    for (const XmlAttribute& a : attributes)
      if (a.name == n) return &a.value;
    return nullptr;
  }
};

// Elements and their text (no comments, processing instructions or DOCTYPE: the
// parsers' defaults drop them). Top-level elements have parent -1; the first is `root`.
struct XmlTree {
  std::vector<XmlNode> nodes;
  int root = -1;
  bool operator==(const XmlTree&) const = default;

  const XmlNode& operator[](int i) const { return nodes[static_cast<std::size_t>(i)]; }
  // Appends `node` as the last child of `parent` (-1: top level); its index.
  int append(int parent, XmlNode node);
  // Room for the nodes `text` can have (one element or text per '<', and one more text):
  // the tree is built without moving nodes.
  void reserveFor(std::string_view text);
  // The first child element of `parent` with this name, or -1.
  [[nodiscard]] int childElement(int parent, std::string_view name) const;
};

struct XmlParseResult {
  bool ok = false;
  std::size_t errorOffset = 0;  // byte offset of the problem in the text
  std::string errorMessage;     // the parser's own words (document.cpp adds "malformed XML: ")
  XmlTree tree;
};

// Elements nested deeper fail the parse with either backend (rapidxml recurses once per
// level; the web build's stack is small). Real blocks nest a few levels.
inline constexpr std::size_t kMaxXmlDepth = 256;

// What a scan of the text finds before a parser reads it. It follows rapidxml's reading
// of tags, quotes, comments, CDATA, processing instructions and DOCTYPE (rapidxml is the
// parser that recurses), and stops where rapidxml would stop with an error.
struct XmlScan {
  static constexpr std::size_t npos = std::string_view::npos;
  // The '<' of the first element nested deeper than kMaxXmlDepth: both backends fail there.
  std::size_t tooDeep = npos;
  // The first place where pugixml fails and rapidxml does not (a name pugixml's grammar
  // does not allow, no space between attributes, "<!-x", "<![CDAT[", "<? ?>", a DOCTYPE
  // inside an element), or where pugixml fails differently (an end tag), at pugixml's
  // offset, with pugixml's words.
  std::size_t stricter = npos;
  std::string stricterMessage;
  std::size_t stricterMarkup = npos;  // the '<' of the tag (or comment, ...) it is in
  // Where the content of a quoted value or CDATA section that the text ends in starts
  // (pugixml reports that place, rapidxml the end of the text).
  std::size_t unterminated = npos;
  // The DOCTYPE declarations, [begin, end) as pugixml reads them.
  std::vector<std::pair<std::size_t, std::size_t>> doctypes;
};
[[nodiscard]] XmlScan scanXml(std::string_view text);

XmlParseResult parseXmlWithPugixml(std::string_view text);   // xml_pugixml.cpp (native builds)
XmlParseResult parseXmlWithRapidxml(std::string_view text);  // xml_rapidxml.cpp
// The parser this build uses (MARIONETTE_BML_XML).
XmlParseResult parseXml(std::string_view text);

}  // namespace marionette::bml::detail
