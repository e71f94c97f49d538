// Private to the writers: replacing a file with new contents, all or nothing.
#pragma once
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "marionette/core/diagnostic.hpp"

namespace marionette::detail {

// Writes `bytes` to `path`: first beside it as PATH.partial, then renamed over
// it, so a failed write never leaves half a file. Errors name `path`; `kind`
// says what the path should be ("a BVH file path").
inline bool writeFileReplacing(const std::string& path, std::string_view bytes, const char* kind, Diagnostics& d) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    d.error(path, std::string("is a directory, expected ") + kind);
    return false;
  }
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    if (!out) {
      d.error(path, "cannot open for writing (" + std::error_code(errno, std::generic_category()).message() + ")");
      return false;
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      d.error(path, "write failed (" + std::error_code(errno, std::generic_category()).message() + ")");
      std::filesystem::remove(partial, ec);
      return false;
    }
  }
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    d.error(path, "cannot replace the file (" + ec.message() + ")");
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    return false;
  }
  return true;
}

}  // namespace marionette::detail
