// findShippedProfile: the installed profile of a known asset (character_profile.hpp).
#include <cstdlib>
#include <filesystem>

#include "marionette/rig/character_profile.hpp"

namespace marionette {

std::vector<std::string> shippedProfileFolders(const std::string& binaryFolder, const std::string& sourceFolder) {
  std::vector<std::string> out;
  if (const char* env = std::getenv("MARIONETTE_PROFILES"); env && *env) out.emplace_back(env);
  if (!binaryFolder.empty())
    out.push_back((std::filesystem::path(binaryFolder).parent_path() / "share/marionette/profiles").string());
  if (!sourceFolder.empty()) out.push_back(sourceFolder);
  return out;
}

std::optional<ProfileMatch> findShippedProfile(const Asset& asset, const std::vector<std::string>& folders,
                                               const FileReader& files) {
  namespace fs = std::filesystem;
  const std::string stem = fs::path(asset.sourcePath).stem().string();
  if (stem.empty()) return std::nullopt;
  for (const std::string& folder : folders) {
    const fs::path file = fs::path(folder) / (stem + ".json");
    std::error_code ec;
    if (!files && !fs::is_regular_file(file, ec)) continue;  // a reader says so by failing to read it
    // The file of the same name, if it fits: a profile written for another asset of that
    // name names joints this one lacks (warnings) and is passed over.
    CharacterProfileResult r = loadCharacterProfile(file.generic_string(), asset, files);
    if (r.diagnostics.items.empty()) return ProfileMatch{file.string(), std::move(r.profile)};
  }
  return std::nullopt;
}

}  // namespace marionette
