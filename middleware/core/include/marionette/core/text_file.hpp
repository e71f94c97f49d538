// Reading a whole text file that a user named, within limits::kMaxTextFileBytes.
#pragma once
#include <string>

namespace marionette {

// Reads `path` into `out`. Refuses what is not a regular file (/dev/zero, a FIFO, a
// folder: they could be read forever) and files over limits::kMaxTextFileBytes. On
// failure returns false and sets `error` to what went wrong, without the path (the
// caller names the file and what it is for).
[[nodiscard]] bool readTextFile(const std::string& path, std::string& out, std::string& error);

}  // namespace marionette
