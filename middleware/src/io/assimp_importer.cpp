#include "marionette/io/import.hpp"

namespace marionette {
ImportResult importWithAssimp(const std::string& path, const ImportOptions&) {
  ImportResult r;
  r.diagnostics.error(path, "Assimp import not yet written");
  return r;
}
}  // namespace marionette
