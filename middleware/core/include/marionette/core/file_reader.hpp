// Where the library reads the files it is asked to read. An engine that keeps its data in
// packed archives or a virtual file system gives a FileReader; without one, the disk.
// Every reader of a user's file goes through readWholeFile: models (and a glTF's external
// buffers and images), joint maps, profiles, scene files, BML files, WAV and alignments.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "marionette/core/diagnostic.hpp"

namespace marionette {

// Reads the whole file `path` into `bytes` (replacing what it held). Returns false when the
// file does not exist or cannot be read, with a reason in `why` (may stay empty). `path` is as
// the library formed it: the one the caller gave, or one resolved against the file that names
// it (a glTF buffer's uri against the glTF's folder, a scene file's assets against the scene
// file), with '/' separators and "." and ".." folded. Called on the loading thread, during the
// load call only; it may be called several times for one load (a glTF and its buffers).
using FileReader = std::function<bool(const std::string& path, std::string& bytes, std::string& why)>;

// Reads `path` through `reader`, or from the disk when `reader` is empty: there, a regular
// file only (a FIFO, device or folder could block or be read forever). More than maxBytes is
// refused either way. On failure returns false and sets `why` (without the path).
[[nodiscard]] bool readWholeFile(const FileReader& reader, const std::string& path, std::uintmax_t maxBytes,
                                 std::string& bytes, std::string& why);

}  // namespace marionette
