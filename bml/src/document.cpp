#include "marionette/bml/document.hpp"

#include <tuple>

#include <pugixml.hpp>

namespace marionette::bml {

namespace {

std::string_view localName(const char* name) {
  std::string_view n(name);
  auto colon = n.find(':');
  return colon == std::string_view::npos ? n : n.substr(colon + 1);
}

std::string trimmed(std::string s) {
  const char* ws = " \t\r\n";
  auto b = s.find_first_not_of(ws);
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

void collectText(const pugi::xml_node& n, std::string& out) {
  for (pugi::xml_node c : n.children()) {
    if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) {
      if (!out.empty()) out += ' ';
      out += trimmed(c.value());
    } else if (c.type() == pugi::node_element) {
      collectText(c, out);
    }
  }
}
}  // namespace

const std::string* Behavior::attribute(std::string_view name) const noexcept {
  for (const Attribute& a : attributes)
    if (a.name == name) return &a.value;
  return nullptr;
}

ParseResult parseBlock(std::string_view text, const std::string& source) {
  ParseResult result;
  pugi::xml_document doc;
  pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    auto [line, col] = lineColumnAt(text, parsed.offset);
    result.diagnostics.error(source, std::string("malformed XML: ") + parsed.description(), line, col);
    return result;
  }
  pugi::xml_node root = doc.document_element();
  // offset_debug() points at the element name; report the '<' before it.
  auto place = [&](const pugi::xml_node& n) { return lineColumnAt(text, n.offset_debug() - 1); };
  if (!root || localName(root.name()) != "bml") {
    auto [line, col] = root ? place(root) : std::pair{0, 0};
    result.diagnostics.error(source, "expected a <bml> element at the top", line, col);
    return result;
  }
  Block block;
  std::tie(block.line, block.column) = place(root);
  block.id = root.attribute("id").as_string();
  block.characterId = root.attribute("characterId").as_string();
  block.composition = root.attribute("composition").as_string("MERGE");
  if (block.id.empty()) {
    result.diagnostics.error(source, "<bml> has no id (BML 1.0 requires one)", block.line, block.column);
    return result;
  }
  const std::string where = source + " (block " + block.id + ")";
  // <required> wraps behaviors that must not be dropped; <constraint> needs no id.
  auto readBehaviors = [&](auto& self, const pugi::xml_node& parent, bool required) -> void {
    for (pugi::xml_node n : parent.children()) {
      if (n.type() != pugi::node_element) continue;
      Behavior b;
      b.type = std::string(localName(n.name()));
      if (b.type == "required") {
        self(self, n, true);
        continue;
      }
      b.required = required;
      std::tie(b.line, b.column) = place(n);
      for (pugi::xml_attribute a : n.attributes()) {
        if (std::string_view(a.name()) == "id") b.id = a.value();
        else b.attributes.push_back({a.name(), a.value()});
      }
      if (b.id.empty() && b.type != "constraint") {
        result.diagnostics.error(where, "<" + b.type + "> has no id (BML 1.0 requires one on every behavior)", b.line,
                                 b.column);
        continue;
      }
      for (const Behavior& other : block.behaviors)
        if (!b.id.empty() && other.id == b.id)
          result.diagnostics.error(where, "behavior id '" + b.id + "' is used twice in the block", b.line, b.column);
      collectText(n, b.text);
      block.behaviors.push_back(std::move(b));
    }
  };
  readBehaviors(readBehaviors, root, false);
  if (result.diagnostics.ok()) result.block = std::move(block);
  return result;
}

}  // namespace marionette::bml
