// Reading a whole text file that a user named, within limits::kMaxTextFileBytes.
#pragma once
#include <string>
#include <string_view>

#include "marionette/core/diagnostic.hpp"
#include "marionette/core/file_reader.hpp"

namespace marionette {

// Reads `path` into `out`. Refuses what is not a regular file (/dev/zero, a FIFO, a
// folder: they could be read forever) and files over limits::kMaxTextFileBytes. On
// failure returns false with an error in `diagnostics` naming `path`: `what` (what the
// file is for, "cannot read the scene file"), ": " and what went wrong; the reason
// alone when `what` is empty.
[[nodiscard]] bool readTextFile(const std::string& path, std::string& out, Diagnostics& diagnostics,
                                std::string_view what = {});
// The same through an engine's reader (file_reader.hpp; empty: the disk).
[[nodiscard]] bool readTextFile(const FileReader& reader, const std::string& path, std::string& out,
                                Diagnostics& diagnostics, std::string_view what = {});

}  // namespace marionette
