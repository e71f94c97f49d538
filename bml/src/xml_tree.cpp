#include "xml_tree.hpp"

#include <algorithm>
#include <vector>

namespace marionette::bml::detail {

int XmlTree::append(int parent, XmlNode node) {
  const int index = static_cast<int>(nodes.size());
  node.parent = parent;
  node.firstChild = node.lastChild = node.nextSibling = -1;
  int previous = -1;
  if (parent >= 0) {
    previous = nodes[static_cast<std::size_t>(parent)].lastChild;
  } else {
    for (int r = root; r >= 0; r = nodes[static_cast<std::size_t>(r)].nextSibling) previous = r;
  }
  node.previousSibling = previous;
  const bool element = node.type == XmlNode::Type::Element;
  nodes.push_back(std::move(node));
  if (previous >= 0) nodes[static_cast<std::size_t>(previous)].nextSibling = index;
  if (parent >= 0) {
    XmlNode& p = nodes[static_cast<std::size_t>(parent)];
    if (p.firstChild < 0) p.firstChild = index;
    p.lastChild = index;
  } else if (root < 0 && element) {
    root = index;
  }
  return index;
}

void XmlTree::reserveFor(std::string_view text) {
  nodes.reserve(2 * static_cast<std::size_t>(std::count(text.begin(), text.end(), '<')) + 1);
}

int XmlTree::childElement(int parent, std::string_view name) const {
  for (int c = (*this)[parent].firstChild; c >= 0; c = (*this)[c].nextSibling)
    if ((*this)[c].type == XmlNode::Type::Element && (*this)[c].name == name) return c;
  return -1;
}

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
// pugixml's name grammar: a letter, '_', ':' or any byte >= 128 first, then also digits, '-', '.'.
bool isNameStart(char c) {
  return static_cast<unsigned char>(c) >= 128 || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
         c == ':';
}
bool isNameChar(char c) { return isNameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; }
// What rapidxml reads as an element's name, and as an attribute's.
bool isRapidxmlName(char c) { return !isSpace(c) && c != '/' && c != '>' && c != '?' && c != '\0'; }
bool isRapidxmlAttributeName(char c) { return isRapidxmlName(c) && c != '<' && c != '=' && c != '!'; }

class Scanner {
 public:
  explicit Scanner(std::string_view text) : text_(text.substr(0, text.find('\0'))) {}  // both stop at a NUL

  XmlScan run() {
    std::size_t i = 0;
    while (i < text_.size()) {
      if (text_[i] != '<') {
        ++i;
        continue;
      }
      i = markup(i);
      if (i == npos) break;
    }
    return scan_;
  }

 private:
  static constexpr std::size_t npos = XmlScan::npos;
  char at(std::size_t i) const { return i < text_.size() ? text_[i] : '\0'; }
  bool startsWith(std::size_t i, std::string_view s) const { return text_.substr(std::min(i, text_.size()), s.size()) == s; }
  std::size_t skipPast(std::size_t i, std::string_view end) const {
    const std::size_t e = text_.find(end, i);
    return e == npos ? npos : e + end.size();
  }
  std::size_t skipSpace(std::size_t i) const {
    while (i < text_.size() && isSpace(text_[i])) ++i;
    return i;
  }
  void stricter(std::size_t offset, const char* message) {
    if (scan_.stricter == npos) {
      scan_.stricter = offset;
      scan_.stricterMessage = message;
      scan_.stricterMarkup = markup_;
    }
  }
  // pugixml stops at the first byte its grammar does not allow in a name, and fails one after.
  void checkName(std::size_t start, std::size_t end, const char* badStart, const char* badChar) {
    if (start == end) return;
    if (!isNameStart(text_[start])) return stricter(start, badStart);
    for (std::size_t k = start + 1; k < end; ++k)
      if (!isNameChar(text_[k])) return stricter(k + 1, badChar);
  }

  // The markup at text_[i] ('<'): the index after it, or npos where rapidxml stops.
  std::size_t markup(std::size_t i) {
    markup_ = i;
    const char c = at(i + 1);
    if (c == '/') return endTag(i);
    if (c == '?') {  // processing instruction or declaration: pugixml wants a target name
      if (!isNameStart(at(i + 2))) stricter(i + 2, "Error parsing document declaration/processing instruction");
      return skipPast(i + 2, "?>");
    }
    if (c == '!') {
      if (startsWith(i, "<!--")) return skipPast(i + 4, "-->");
      if (startsWith(i, "<!-")) stricter(i + 3, "Error parsing comment");
      if (startsWith(i, "<![CDATA[")) {
        const std::size_t end = skipPast(i + 9, "]]>");
        if (end == npos) scan_.unterminated = i + 9;
        return end;
      }
      if (startsWith(i, "<![")) {
        std::size_t k = 0;
        while (k < 6 && at(i + 3 + k) == "CDATA["[k]) ++k;
        stricter(i + 3 + k, "Error parsing CDATA section");
      }
      if (startsWith(i, "<!DOCTYPE")) return doctype(i);
      if (!startsWith(i, "<!-") && !startsWith(i, "<!["))
        stricter(i + 2, "Could not determine tag type");
      // Any other <!...>: to the '>' (rapidxml's reading; pugixml has failed before).
      std::size_t k = i + 2;
      for (int brackets = 0; k < text_.size() && !(text_[k] == '>' && brackets == 0); ++k) {
        if (text_[k] == '[') ++brackets;
        else if (text_[k] == ']' && brackets > 0) --brackets;
      }
      return k < text_.size() ? k + 1 : npos;
    }
    return element(i);
  }

  // A DOCTYPE, read as pugixml reads it (rapidxml only counts brackets, and may end it
  // elsewhere): quoted strings, comments, processing instructions and <![ ]]> sections
  // inside it are skipped whole, <! ... > groups nest. The rapidxml backend blanks it out
  // (XmlScan::doctypes), so that both go on from the same byte.
  std::size_t doctype(std::size_t open) {
    static constexpr const char* kBad = "Error parsing document type declaration";
    if (!open_.empty()) {  // pugixml: only at the top level
      stricter(open, kBad);
      return npos;
    }
    std::size_t k = open + 2;
    for (std::size_t depth = 0;;) {
      if (k >= text_.size()) {
        stricter(text_.size(), kBad);
        return npos;
      }
      const char c = text_[k];
      if (c == '<' && at(k + 1) == '!' && at(k + 2) == '[') {
        k = ignoreSection(k);
      } else if (c == '<' && at(k + 1) == '!' && at(k + 2) != '-') {
        k += 2;
        ++depth;
      } else if (c == '"' || c == '\'') {
        const std::size_t close = text_.find(c, k + 1);
        k = close == npos ? npos : close + 1;
      } else if (c == '<' && at(k + 1) == '?') {
        k = skipPast(k + 2, "?>");
      } else if (startsWith(k, "<!--")) {
        k = skipPast(k + 4, "-->");
      } else if (c == '<') {
        stricter(k, kBad);
        return npos;
      } else if (c == '>' && depth == 0) {
        scan_.doctypes.push_back({open, k + 1});
        return k + 1;
      } else {
        if (c == '>') --depth;
        ++k;
      }
      if (k == npos) {
        stricter(text_.size(), kBad);
        return npos;
      }
    }
  }
  // A <![ ... ]]> section in a DOCTYPE (they nest): the index after it, or npos.
  std::size_t ignoreSection(std::size_t k) const {
    k += 3;
    for (std::size_t depth = 0; k < text_.size();) {
      if (startsWith(k, "<![")) {
        k += 3;
        ++depth;
      } else if (startsWith(k, "]]>")) {
        k += 3;
        if (depth == 0) return k;
        --depth;
      } else {
        ++k;
      }
    }
    return npos;
  }

  // An end tag, checked as pugixml does: the open element's name, spaces, '>'. Where it
  // fails, so does rapidxml (its name rule is looser, its offsets others), and both stop.
  std::size_t endTag(std::size_t open) {
    const std::size_t name = open + 2;
    const std::string_view expected = open_.empty() ? std::string_view() : open_.back();
    std::size_t k = name;
    for (; k < text_.size() && isNameChar(text_[k]); ++k)
      if (k - name >= expected.size() || text_[k] != expected[k - name]) break;
    if (open_.empty() || k - name != expected.size() || (k < text_.size() && isNameChar(text_[k]))) {
      stricter(name, "Start-end tags mismatch");
      return npos;
    }
    k = skipSpace(k);
    if (at(k) != '>') {
      stricter(k, "Error parsing end element tag");
      return npos;
    }
    open_.pop_back();
    return k + 1;
  }

  std::size_t element(std::size_t open) {
    std::size_t i = open + 1;
    const std::size_t name = i;
    while (i < text_.size() && isRapidxmlName(text_[i])) ++i;
    if (i == name) return npos;
    const std::string_view elementName = text_.substr(name, i - name);
    checkName(name, i, "Could not determine tag type", "Error parsing start element tag");
    if (at(i) == '?') stricter(i + 1, "Error parsing start element tag");  // pugixml: one past it, rapidxml: at it
    for (;;) {
      i = skipSpace(i);
      if (!isRapidxmlAttributeName(at(i))) break;
      const std::size_t attribute = i;
      while (i < text_.size() && isRapidxmlAttributeName(text_[i])) ++i;
      checkName(attribute, i, "Error parsing start element tag", "Error parsing element attribute");
      i = skipSpace(i);
      if (at(i) != '=') return npos;
      i = skipSpace(i + 1);
      const char quote = at(i);
      if (quote != '\'' && quote != '"') return npos;
      const std::size_t close = text_.find(quote, i + 1);
      if (close == npos) {
        scan_.unterminated = i + 1;
        return npos;
      }
      i = close + 1;
      if (isNameStart(at(i))) stricter(i, "Error parsing element attribute");  // pugixml wants a space first
    }
    if (at(i) == '/' && at(i + 1) == '>') return i + 2;
    if (at(i) != '>') return npos;
    if (open_.size() >= kMaxXmlDepth) {
      scan_.tooDeep = open;
      return npos;  // both parsers fail here
    }
    open_.push_back(elementName);
    return i + 1;
  }

  std::string_view text_;
  std::vector<std::string_view> open_;  // the elements open at this point, outermost first
  std::size_t markup_ = 0;              // where the markup being read starts
  XmlScan scan_;
};

}  // namespace

XmlScan scanXml(std::string_view text) { return Scanner(text).run(); }

XmlParseResult parseXml(std::string_view text) {
#ifdef MARIONETTE_BML_XML_RAPIDXML
  return parseXmlWithRapidxml(text);
#else
  return parseXmlWithPugixml(text);
#endif
}

}  // namespace marionette::bml::detail
