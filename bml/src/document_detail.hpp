// parseBlock with a given XML parser: the tests compare pugixml's and rapidxml's results
// (the build's own is detail::parseXml).
#pragma once
#include "marionette/bml/document.hpp"
#include "xml_tree.hpp"

namespace marionette::bml::detail {

using XmlParser = XmlParseResult (*)(std::string_view text);

[[nodiscard]] ParseResult parseBlockWith(std::string_view text, const ParseOptions& options, XmlParser xml);

}  // namespace marionette::bml::detail
