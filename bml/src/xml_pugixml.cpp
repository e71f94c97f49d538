// The native build's XML parser: pugixml, with its default options (entities decoded,
// "\r\n" read as "\n", whitespace-only text dropped).
#include <pugixml.hpp>

#include "xml_tree.hpp"

namespace marionette::bml::detail {

XmlParseResult parseXmlWithPugixml(std::string_view text) {
  XmlParseResult result;
  if (const std::size_t deep = scanXml(text).tooDeep; deep != XmlScan::npos) {
    result.errorOffset = deep;
    result.errorMessage = "elements nested more than " + std::to_string(kMaxXmlDepth) + " levels deep";
    return result;
  }
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    result.errorOffset = static_cast<std::size_t>(parsed.offset);
    result.errorMessage = parsed.description();
    return result;
  }
  result.tree.reserveFor(text);
  // Iterative: the tree may be deep (up to kMaxXmlDepth).
  std::vector<std::pair<pugi::xml_node, int>> stack;  // a node still to copy, its parent's index
  for (pugi::xml_node c = doc.last_child(); c; c = c.previous_sibling()) stack.push_back({c, -1});
  while (!stack.empty()) {
    const auto [n, parent] = stack.back();
    stack.pop_back();
    XmlNode node;
    switch (n.type()) {
      case pugi::node_element: node.type = XmlNode::Type::Element; break;
      case pugi::node_pcdata: node.type = XmlNode::Type::Pcdata; break;
      case pugi::node_cdata: node.type = XmlNode::Type::Cdata; break;
      default: continue;  // none with parse_default
    }
    if (parent < 0 && node.type != XmlNode::Type::Element) continue;
    node.name = n.name();
    node.value = n.value();
    if (node.type == XmlNode::Type::Element) {
      node.offset = static_cast<std::size_t>(n.offset_debug());
      std::size_t count = 0;
      for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute()) ++count;
      node.attributes.reserve(count);
      for (pugi::xml_attribute a : n.attributes()) node.attributes.push_back({a.name(), a.value()});
    }
    const int index = result.tree.append(parent, std::move(node));
    for (pugi::xml_node c = n.last_child(); c; c = c.previous_sibling()) stack.push_back({c, index});
  }
  result.ok = true;
  return result;
}

}  // namespace marionette::bml::detail
