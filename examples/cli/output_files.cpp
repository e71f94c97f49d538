#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "commands.hpp"

namespace marionette::cli {

std::string prepareOutputFile(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  if (path.empty() || !p.has_filename()) return "'" + path + "' names a folder, not a file";
  std::error_code ec;
  if (fs::is_directory(p, ec)) return "'" + path + "' is a folder, not a file";
  if (const fs::path dir = p.parent_path(); !dir.empty() && !fs::is_directory(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec) return "cannot create the folder '" + dir.string() + "': " + ec.message();
  }
  // Opened for appending, so that an existing file is not truncated by a command that fails later.
  const bool existed = fs::exists(p, ec);
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (!f) return "cannot write '" + path + "': " + std::strerror(errno);
  std::fclose(f);
  if (!existed) fs::remove(p, ec);
  return {};
}

std::string prepareOutputFolder(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path.empty()) return "an empty folder name";
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) return "'" + path + "' is a file, not a folder";
  fs::create_directories(path, ec);
  if (ec) return "cannot create the folder '" + path + "': " + ec.message();
  // A probe file: access(W_OK) says nothing of a read-only mount or a full quota.
  const std::string probe = (fs::path(path) / ".marionette-write-check").string();
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) return "cannot write into the folder '" + path + "': " + std::strerror(errno);
  std::fclose(f);
  fs::remove(probe, ec);
  return {};
}

}  // namespace marionette::cli
