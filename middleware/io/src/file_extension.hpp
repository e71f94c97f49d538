// Private to the importers: the file's extension, lower case, with its dot (".fbx").
#pragma once
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace marionette::detail {

inline std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace marionette::detail
