#include "marionette/core/text_file.hpp"

#include <filesystem>
#include <fstream>

#include "marionette/core/file_reader.hpp"
#include "marionette/core/limits.hpp"

namespace marionette {
namespace {

// On failure, `error` says what went wrong, without the path.
bool readFromDisk(const std::string& path, std::uintmax_t maxBytes, std::string& out, std::string& error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    error = "file does not exist";
    return false;
  }
  if (!fs::is_regular_file(status)) {
    error = fs::is_directory(status) ? "is a folder, not a regular file" : "is not a regular file (a device or a FIFO?)";
    return false;
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    error = "cannot read its size: " + ec.message();
    return false;
  }
  if (size > maxBytes) {
    error = std::to_string(size) + " bytes is more than the " + std::to_string(maxBytes) + " this kind of file may have";
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

bool readWholeFile(const FileReader& reader, const std::string& path, std::uintmax_t maxBytes, std::string& bytes,
                   std::string& why) {
  why.clear();
  if (!reader) return readFromDisk(path, maxBytes, bytes, why);
  bool ok = false;
  try {  // an engine's callback is not ours to trust: an exception from it is a failed read
    ok = reader(path, bytes, why);
  } catch (const std::exception& e) {
    why = std::string("the file reader threw: ") + e.what();
    ok = false;
  } catch (...) {
    why = "the file reader threw";
    ok = false;
  }
  if (!ok) {
    if (why.empty()) why = "file does not exist (the file reader could not read it)";
    bytes.clear();
    return false;
  }
  if (bytes.size() > maxBytes) {
    why = std::to_string(bytes.size()) + " bytes is more than the " + std::to_string(maxBytes) +
          " this kind of file may have";
    bytes.clear();
    return false;
  }
  return true;
}

bool readTextFile(const std::string& path, std::string& out, Diagnostics& diagnostics, std::string_view what) {
  return readTextFile(FileReader{}, path, out, diagnostics, what);
}

bool readTextFile(const FileReader& reader, const std::string& path, std::string& out, Diagnostics& diagnostics,
                  std::string_view what) {
  std::string why;
  if (readWholeFile(reader, path, limits::kMaxTextFileBytes, out, why)) return true;
  diagnostics.error(path, what.empty() ? why : std::string(what) + ": " + why);
  return false;
}

}  // namespace marionette
