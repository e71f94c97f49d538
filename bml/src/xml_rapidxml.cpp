// The web build's XML parser: rapidxml (header-only), read so that the tree, and the
// offset of each error, are pugixml's (xml_pugixml.cpp) on the same text. rapidxml reads
// in place without changing the text (parse_non_destructive): names and values point into
// a copy of the text, so element offsets are exact; entities, line ends and attribute
// whitespace are decoded here as pugixml's parse_default does.
//
// Errors: rapidxml stops at the first problem, as pugixml does, but not always at the same
// byte, and it accepts some texts pugixml rejects. The rules that make the offsets pugixml's
// (tests/bml/xml_parser_test.cpp checks them; docs/bml-compliance.md, "XML parsers"):
// - the end of the text: pugixml reports its last byte, rapidxml the byte after it;
// - a mismatched end tag: pugixml reports the start of its name, rapidxml its end; a missing
//   '=': pugixml one byte past rapidxml; a quoted value or CDATA that runs to the end (or to
//   a NUL byte): pugixml where its content starts;
// - what pugixml rejects and rapidxml accepts (names pugixml's grammar does not allow, no
//   space between attributes, "<!-x", a DOCTYPE inside an element, ...) and how pugixml
//   reads end tags and DOCTYPEs come from scanXml (xml_tree.cpp), at pugixml's offsets;
// - text at the top level is skipped by both (rapidxml fails there: it is read again after
//   it); a text without an element fails at its end, as pugixml's "no document element".
#include <rapidxml/rapidxml.hpp>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>

#include "xml_tree.hpp"

namespace marionette::bml::detail {

namespace {

constexpr int kFlags = rapidxml::parse_non_destructive | rapidxml::parse_validate_closing_tags;

void appendUtf8(std::string& out, std::uint32_t c) {
  auto byte = [&](std::uint32_t b) { out += static_cast<char>(static_cast<unsigned char>(b & 0xFF)); };
  if (c < 0x80) {
    byte(c);
  } else if (c < 0x800) {
    byte(0xC0 | (c >> 6));
    byte(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    byte(0xE0 | (c >> 12));
    byte(0x80 | ((c >> 6) & 0x3F));
    byte(0x80 | (c & 0x3F));
  } else {  // as pugixml, also past U+10FFFF (the top bits cut)
    byte(0xF0 | (c >> 18));
    byte(0x80 | ((c >> 12) & 0x3F));
    byte(0x80 | ((c >> 6) & 0x3F));
    byte(0x80 | (c & 0x3F));
  }
}

// The reference at s[i] ('&'), decoded into `out`; the index to go on from. Anything that
// is not one of XML's five names or a complete numeric reference stays as written, and
// the reading goes on from the first byte that did not fit (pugixml's rule).
std::size_t decodeReference(std::string_view s, std::size_t i, std::string& out) {
  auto at = [&](std::size_t k) { return k < s.size() ? s[k] : '\0'; };
  if (at(i + 1) == '#') {
    const bool hex = at(i + 2) == 'x';
    std::size_t k = i + (hex ? 3 : 2);
    std::uint32_t code = 0;
    if (at(k) == ';') {  // "&#;" or "&#x;"
      out.append(s.substr(i, k - i));
      return k;
    }
    for (;; ++k) {
      const char c = at(k);
      const auto lower = static_cast<char>(c | ' ');
      if (c >= '0' && c <= '9') {
        code = code * (hex ? 16u : 10u) + static_cast<std::uint32_t>(c - '0');
      } else if (hex && lower >= 'a' && lower <= 'f') {
        code = code * 16u + static_cast<std::uint32_t>(lower - 'a' + 10);
      } else if (c == ';') {
        appendUtf8(out, code);
        return k + 1;
      } else {
        out.append(s.substr(i, k - i));
        return k;
      }
    }
  }
  static constexpr std::pair<std::string_view, char> kNames[] = {
      {"&amp;", '&'}, {"&apos;", '\''}, {"&gt;", '>'}, {"&lt;", '<'}, {"&quot;", '"'}};
  for (const auto& [name, c] : kNames)
    if (s.substr(i, name.size()) == name) {
      out += c;
      return i + name.size();
    }
  // Not a name: keep what matched one of them, go on from the first byte that did not.
  std::size_t longest = 1;
  for (const auto& [name, c] : kNames) {
    std::size_t k = 1;
    while (k < name.size() && i + k < s.size() && s[i + k] == name[k]) ++k;
    longest = std::max(longest, k);
  }
  out.append(s.substr(i, longest));
  return i + longest;
}

// Text and CDATA: "\r\n" and "\r" become "\n"; entities in text only.
std::string decodeText(std::string_view s, bool entities) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '\r') {
      out += '\n';
      i += i + 1 < s.size() && s[i + 1] == '\n' ? 2 : 1;
    } else if (entities && s[i] == '&') {
      i = decodeReference(s, i, out);
    } else {
      out += s[i++];
    }
  }
  out.resize(std::min(out.size(), out.find('\0')));  // pugixml's strings end at a NUL ("&#0;")
  return out;
}

// Attribute values: each space, tab or line end a space ("\r\n" one), entities decoded.
std::string decodeAttribute(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '\r') {
      out += ' ';
      i += i + 1 < s.size() && s[i + 1] == '\n' ? 2 : 1;
    } else if (s[i] == '\t' || s[i] == '\n') {
      out += ' ';
      ++i;
    } else if (s[i] == '&') {
      i = decodeReference(s, i, out);
    } else {
      out += s[i++];
    }
  }
  out.resize(std::min(out.size(), out.find('\0')));
  return out;
}

struct Failure {
  std::size_t offset;
  std::string message;
};

class Reader {
 public:
  Reader(std::string_view text, XmlScan scan) : text_(text), scan_(std::move(scan)), buffer_(text.begin(), text.end()) {
    buffer_.push_back('\0');
    // DOCTYPEs as spaces (rapidxml skips them at the top level, the only place pugixml
    // allows one): rapidxml may end one elsewhere than pugixml does, and neither keeps it.
    for (const auto& [begin, end] : scan_.doctypes)
      std::fill(buffer_.data() + begin, buffer_.data() + end, ' ');
  }

  XmlParseResult run() {
    XmlParseResult result;
    // pugixml reads up to a NUL byte; so does rapidxml, on the zero-terminated copy.
    const std::size_t end = std::min(text_.size(), text_.find('\0'));
    result.tree.reserveFor(text_);
    std::size_t start = 0;
    std::optional<Failure> failure;
    std::size_t failedAt = 0;  // rapidxml's own offset of the failure
    // On the heap: a rapidxml document holds a 64 KB memory pool, the web build's whole stack.
    const auto doc = std::make_unique<rapidxml::xml_document<char>>();
    while (!failure) {
      doc->clear();
      try {
        doc->parse<kFlags>(buffer_.data() + start);
        copy(*doc, result.tree);
        break;
      } catch (const rapidxml::parse_error& e) {
        const auto where = static_cast<std::size_t>(e.where<char>() - buffer_.data());
        if (std::string_view(e.what()) == "expected <") {
          // Text at the top level: pugixml skips it, up to the next '<'.
          copy(*doc, result.tree);
          const std::size_t next = text_.find('<', where);
          if (next == std::string_view::npos || next >= end) break;
          start = next;
          continue;
        }
        failure = Failure{errorOffset(e.what(), where), e.what()};
        failedAt = where;
      }
    }
    // Where pugixml fails and rapidxml does not, or not at the same byte: pugixml's failure,
    // unless rapidxml failed before the markup it is in.
    if (scan_.stricter != XmlScan::npos && (!failure || failedAt >= scan_.stricterMarkup))
      failure = Failure{scan_.stricter, scan_.stricterMessage};
    if (failure) {
      result.tree = {};
      // pugixml reports the end of the text at its last byte (and a byte past it as it is).
      result.errorOffset = failure->offset == text_.size() && !text_.empty() ? text_.size() - 1 : failure->offset;
      result.errorMessage = failure->message;
      return result;
    }
    if (result.tree.root < 0) {
      result.tree = {};
      result.errorOffset = text_.size();
      result.errorMessage = "no document element";
      return result;
    }
    result.ok = true;
    return result;
  }

 private:
  std::size_t offsetOf(const char* p) const { return static_cast<std::size_t>(p - buffer_.data()); }

  // rapidxml's offset of an error, as pugixml gives it.
  std::size_t errorOffset(std::string_view what, std::size_t where) const {
    if (what == "invalid closing tag name") {  // pugixml: where the end tag's name starts
      const std::size_t open = text_.rfind("</", where);
      return open == std::string_view::npos ? where : open + 2;
    }
    // An end tag with nothing open: pugixml, after "</"; rapidxml, at the '/'.
    if (what == "expected element name" && where > 0 && text_[where - 1] == '<' && where < text_.size() && text_[where] == '/')
      return where + 1;
    if (what == "expected =") return where + 1;  // pugixml: one past the byte that is not '='
    // The text ended (or a NUL byte came) inside a quoted value or CDATA: pugixml reports
    // where its content starts.
    if (where >= std::min(text_.size(), text_.find('\0')) && scan_.unterminated != XmlScan::npos)
      return scan_.unterminated;
    return where;
  }

  // rapidxml's tree (elements, text, CDATA) into `tree`, iteratively.
  void copy(const rapidxml::xml_document<char>& doc, XmlTree& tree) {
    std::vector<std::pair<const rapidxml::xml_node<char>*, int>> stack;
    // last_node() asserts that there is a child
    for (const rapidxml::xml_node<char>* c = doc.first_node() ? doc.last_node() : nullptr; c; c = c->previous_sibling()) stack.push_back({c, -1});
    while (!stack.empty()) {
      const auto [n, parent] = stack.back();
      stack.pop_back();
      XmlNode node;
      const std::string_view value(n->value(), n->value_size());
      switch (n->type()) {
        case rapidxml::node_element: node.type = XmlNode::Type::Element; break;
        case rapidxml::node_data: node.type = XmlNode::Type::Pcdata; break;
        case rapidxml::node_cdata: node.type = XmlNode::Type::Cdata; break;
        default: continue;
      }
      if (parent < 0 && node.type != XmlNode::Type::Element) continue;
      if (node.type == XmlNode::Type::Element) {
        node.name.assign(n->name(), n->name_size());
        node.offset = offsetOf(n->name());
        std::size_t count = 0;
        for (const rapidxml::xml_attribute<char>* a = n->first_attribute(); a; a = a->next_attribute()) ++count;
        node.attributes.reserve(count);
        for (const rapidxml::xml_attribute<char>* a = n->first_attribute(); a; a = a->next_attribute()) {
          node.attributes.push_back({std::string(a->name(), a->name_size()), decodeAttribute({a->value(), a->value_size()})});
        }
      } else {
        node.value = decodeText(value, node.type == XmlNode::Type::Pcdata);
      }
      const int index = tree.append(parent, std::move(node));
      for (const rapidxml::xml_node<char>* c = n->first_node() ? n->last_node() : nullptr; c; c = c->previous_sibling()) stack.push_back({c, index});
    }
  }

  std::string_view text_;
  XmlScan scan_;
  std::vector<char> buffer_;  // rapidxml's: zero-terminated, and it must be mutable
};

}  // namespace

XmlParseResult parseXmlWithRapidxml(std::string_view text) {
  XmlParseResult result;
  XmlScan scan = scanXml(text);
  if (scan.tooDeep != XmlScan::npos) {
    result.errorOffset = scan.tooDeep;
    result.errorMessage = "elements nested more than " + std::to_string(kMaxXmlDepth) + " levels deep";
    return result;
  }
  result = Reader(text, std::move(scan)).run();
  if (!result.ok) result.errorMessage = "rapidxml: " + result.errorMessage;
  return result;
}

}  // namespace marionette::bml::detail
