// libFuzzer target: differential, pugixml against rapidxml (bml/src/xml_tree.hpp). The web
// build reads BML with rapidxml and the native build with pugixml; for any bytes both must
// give the same tree, or fail at the same byte (the line:column users see). A difference
// aborts, and scripts/fuzz keeps the input. Built and run by scripts/fuzz xml_parsers.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "xml_tree.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marionette::bml::detail;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const XmlParseResult a = parseXmlWithPugixml(text);
  const XmlParseResult b = parseXmlWithRapidxml(text);
  if (a.ok != b.ok || (!a.ok && a.errorOffset != b.errorOffset) || (a.ok && !(a.tree == b.tree))) {
    std::fprintf(stderr, "xml parsers differ: pugixml %s at %zu (%s), rapidxml %s at %zu (%s)\n", a.ok ? "ok" : "fails",
                 a.errorOffset, a.errorMessage.c_str(), b.ok ? "ok" : "fails", b.errorOffset, b.errorMessage.c_str());
    std::abort();
  }
  return 0;
}
