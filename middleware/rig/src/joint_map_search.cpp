// findJointMap: which of a folder's joint maps fits a skeleton (joint_map.hpp).
#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "marionette/rig/joint_map.hpp"

namespace marionette::retarget {

std::vector<std::string> shippedJointMapFolders(const std::string& binaryFolder, const std::string& sourceFolder) {
  std::vector<std::string> out;
  if (const char* env = std::getenv("MARIONETTE_JOINTMAPS"); env && *env) out.emplace_back(env);
  if (!binaryFolder.empty())
    out.push_back((std::filesystem::path(binaryFolder).parent_path() / "share/marionette/jointmaps").string());
  if (!sourceFolder.empty()) out.push_back(sourceFolder);
  return out;
}

std::optional<JointMapMatch> findJointMap(const Asset& asset, const std::vector<std::string>& folders) {
  namespace fs = std::filesystem;
  const std::string stem = fs::path(asset.sourcePath).stem().string();
  std::vector<fs::path> named, others;
  for (const std::string& folder : folders) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".json" && it->is_regular_file(ec)) files.push_back(it->path());
    std::sort(files.begin(), files.end());
    for (fs::path& f : files) (!stem.empty() && f.stem() == stem ? named : others).push_back(std::move(f));
  }
  named.insert(named.end(), others.begin(), others.end());
  for (const fs::path& file : named) {
    JointMapResult r = loadJointMap(file.string(), asset);
    if (r.diagnostics.items.empty()) return JointMapMatch{file.string(), std::move(r)};
  }
  return std::nullopt;
}

}  // namespace marionette::retarget
