#include "marionette/io/import.hpp"

#include "file_extension.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace marionette {

using detail::lowerExtension;

ImportResult importAsset(const std::string& path, const ImportOptions& options) {
  ImportResult result;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    result.diagnostics.error(path, "file does not exist");
    return result;
  }
  if (std::filesystem::is_directory(path, ec)) {
    result.diagnostics.error(path, "is a directory, expected a character or motion file");
    return result;
  }
  const std::string ext = lowerExtension(path);
  // The project's own files and media are never models; Assimp would read some of them as
  // a one-node scene (a joint map given as a character became a 1-joint character).
  for (const char* other : {".json", ".bml", ".wav", ".hdr", ".exr", ".png", ".jpg", ".jpeg", ".csv", ".txt"})
    if (ext == other) {
      result.diagnostics.error(path, "a '" + ext + "' file is not a character or motion (" +
                                         (ext == ".json" ? "a joint map, profile or scene file?; " : "") +
                                         "expected glTF, GLB, VRM, VRMA or a format Assimp reads: FBX, BVH, DAE, X, ...)");
      return result;
    }
  if (ext == ".gltf" || ext == ".glb" || ext == ".vrm" || ext == ".vrma") return importGltf(path, options);
#ifdef MARIONETTE_HAS_ASSIMP
  return importWithAssimp(path, options);
#else
  result.diagnostics.error(path, "format '" + ext +
                                     "' needs Assimp; this build has MARIONETTE_WITH_ASSIMP=OFF (glTF, GLB, "
                                     "VRM and VRMA are always supported)");
  return result;
#endif
}

}  // namespace marionette
