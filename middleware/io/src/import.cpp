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

Clip bindClipByName(const Clip& clip, const Skeleton& from, const Skeleton& to, int* unmatched) {
  Clip out;
  out.name = clip.name;
  out.duration = clip.duration;
  out.morphTracks = clip.morphTracks;
  int missing = 0;
  for (const JointTrack& jt : clip.tracks) {
    if (jt.joint < 0 || static_cast<std::size_t>(jt.joint) >= from.jointCount()) {
      ++missing;
      continue;
    }
    int target = to.findJoint(from.names[jt.joint]);
    if (target < 0) {
      ++missing;
      continue;
    }
    JointTrack copy = jt;
    copy.joint = target;
    out.tracks.push_back(std::move(copy));
  }
  std::sort(out.tracks.begin(), out.tracks.end(),
            [](const JointTrack& a, const JointTrack& b) { return a.joint < b.joint; });
  if (unmatched) *unmatched = missing;
  return out;
}

}  // namespace marionette
