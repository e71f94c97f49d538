#include <cstdlib>
#include <filesystem>

#include "commands.hpp"

namespace marionette::cli {

std::vector<std::string> jointMapFolders() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("MARIONETTE_JOINTMAPS"); env && *env) out.emplace_back(env);
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back((exe.parent_path().parent_path() / "share/marionette/jointmaps").string());
  out.emplace_back(MARIONETTE_SOURCE_JOINTMAPS);
  return out;
}

}  // namespace marionette::cli
