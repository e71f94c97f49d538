// Where a model file's external parts (buffers, images, textures) may come from:
// its own folder and below, unless ImportOptions::allowFilesOutsideModelFolder.
#pragma once
#include <filesystem>

namespace marionette::io_detail {

// True when `file` lies in `folder` or below it (compared lexically, after normalizing).
inline bool insideFolder(const std::filesystem::path& file, const std::filesystem::path& folder) {
  const std::filesystem::path relative = file.lexically_normal().lexically_relative(folder.lexically_normal());
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace marionette::io_detail
