#include <filesystem>

#include "commands.hpp"
#include "marionette/rig/joint_map.hpp"

namespace marionette::cli {

std::vector<std::string> jointMapFolders() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return retarget::shippedJointMapFolders(ec ? std::string() : exe.parent_path().string(), MARIONETTE_SOURCE_JOINTMAPS);
}

}  // namespace marionette::cli
