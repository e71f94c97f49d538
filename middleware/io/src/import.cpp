#include "marionette/io/import.hpp"

#include "file_extension.hpp"
#include "marionette/core/limits.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace marionette {

using detail::lowerExtension;

ImportResult importAsset(const std::string& path, const ImportOptions& options) {
  ImportResult result;
  std::error_code ec;
  if (!options.readFile && !std::filesystem::exists(path, ec)) {  // an engine's reader says so when it reads
    result.diagnostics.error(path, "file does not exist");
    return result;
  }
  if (!options.readFile && std::filesystem::is_directory(path, ec)) {
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

ImportResult importAssetFromMemory(std::string_view bytes, const std::string& nameHint, const ImportOptions& options) {
  const std::string name = std::filesystem::path(nameHint).lexically_normal().generic_string();
  if (name.empty() || lowerExtension(name).empty()) {
    ImportResult result;
    result.diagnostics.error(nameHint.empty() ? "<memory>" : nameHint,
                             "a file in memory needs a name with an extension (.glb, .gltf, .vrm, .fbx, .bvh, ...): "
                             "it chooses the format");
    return result;
  }
  // The bytes are the file `name`; the files it names come from the caller's reader or the disk.
  ImportOptions withBytes = options;
  withBytes.readFile = [&bytes, &name, &options](const std::string& path, std::string& out, std::string& why) {
    if (path == name) {
      out.assign(bytes.data(), bytes.size());
      return true;
    }
    return readWholeFile(options.readFile, path, limits::kMaxModelFileBytes, out, why);
  };
  return importAsset(name, withBytes);
}

}  // namespace marionette
