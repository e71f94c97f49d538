#include "marionette/io/import.hpp"

namespace marionette {
ImportResult importGltf(const std::string& path, const ImportOptions&) {
  ImportResult r;
  r.diagnostics.error(path, "glTF import not yet written");
  return r;
}
}  // namespace marionette
