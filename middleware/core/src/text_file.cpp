#include "marionette/core/text_file.hpp"

#include <filesystem>
#include <fstream>

#include "marionette/core/limits.hpp"

namespace marionette {
namespace {

// On failure, `error` says what went wrong, without the path.
bool readWithin(const std::string& path, std::string& out, std::string& error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    error = "no such file";
    return false;
  }
  if (!fs::is_regular_file(status)) {
    error = fs::is_directory(status) ? "is a folder, not a file" : "is not a regular file (a device or a FIFO?)";
    return false;
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    error = "cannot read its size: " + ec.message();
    return false;
  }
  if (size > limits::kMaxTextFileBytes) {
    error = std::to_string(size) + " bytes is more than the " + std::to_string(limits::kMaxTextFileBytes >> 20) +
            " MiB a text file may have (limits::kMaxTextFileBytes)";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out.assign(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(out.data(), static_cast<std::streamsize>(size))) {
    error = "cannot be read";
    return false;
  }
  // A file that grew since: read no more than the limit allows.
  if (in.peek() != std::ifstream::traits_type::eof()) {
    error = "changed while it was read";
    return false;
  }
  return true;
}

}  // namespace

bool readTextFile(const std::string& path, std::string& out, Diagnostics& diagnostics, std::string_view what) {
  std::string why;
  if (readWithin(path, out, why)) return true;
  diagnostics.error(path, what.empty() ? why : std::string(what) + ": " + why);
  return false;
}

}  // namespace marionette
