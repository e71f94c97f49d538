// What the libFuzzer targets share: readers that take a path get the input as a file in
// a per-process temporary folder; contract checks that say which one broke before
// trapping; the finite checks; the project's real characters, imported once.
#pragma once
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/io/import.hpp"

namespace marionette::fuzz {

// The contract is broken: say which part, then stop (libFuzzer keeps the input).
[[noreturn]] inline void broken(const char* what) {
  std::fprintf(stderr, "fuzz contract broken: %s\n", what);
  std::fflush(stderr);
  __builtin_trap();
}
inline void require(bool ok, const char* what) {
  if (!ok) broken(what);
}

// /tmp/marionette-fuzz-<pid>/, removed when the process exits normally.
inline const std::filesystem::path& tempDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("marionette-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(tempDir(), ec);
    });
    return d;
  }();
  return dir;
}

// Writes the input to tempDir()/name (replacing the last one) and returns its path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, std::string_view name) {
  const std::string path = (tempDir() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) broken("cannot write the input to the temporary folder");
  return path;
}

// Every diagnostic names `file` (the contract of every reader: diagnostic.hpp).
[[nodiscard]] inline bool allName(const Diagnostics& d, const std::string& file) {
  for (const Diagnostic& item : d.items)
    if (item.file != file && item.message.find(file) == std::string::npos) return false;
  return true;
}
// A failed read says why: at least one error, every diagnostic naming the file.
inline void requireNamedFailure(const Diagnostics& d, const std::string& file) {
  require(!d.ok(), "a failed read has no error");
  require(allName(d, file), "a diagnostic does not name the file");
}

[[nodiscard]] inline bool finite(float v) { return std::isfinite(v); }
template <class V>  // glm vectors and quaternions
[[nodiscard]] bool finiteAll(const std::vector<V>& values) {
  for (const V& v : values)
    for (int c = 0; c < V::length(); ++c)
      if (!std::isfinite(static_cast<float>(v[c]))) return false;
  return true;
}
[[nodiscard]] inline bool finiteAll(const std::vector<float>& values) {
  for (float v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// The real characters the project's profiles and joint maps are written for
// (../shared/assets/characters, glTF only: no Assimp child process in the fuzzer),
// imported once without meshes. Exits when one is missing: no silent empty fuzzing.
inline const std::vector<Asset>& realCharacters() {
  static const std::vector<Asset> assets = [] {
    std::vector<Asset> out;
    for (const char* name : {"RobotExpressive.glb", "Godette_vrm_v4.vrm", "CesiumMan.glb"}) {
      const std::string path = std::string(MARIONETTE_SOURCE_DIR "/../shared/assets/characters/") + name;
      ImportOptions options;
      options.loadMeshes = false;
      ImportResult r = importAsset(path, options);
      if (!r.ok()) {
        std::fprintf(stderr, "fuzz: cannot import %s:\n%s", path.c_str(), r.diagnostics.format().c_str());
        std::exit(2);
      }
      out.push_back(std::move(*r.asset));
    }
    return out;
  }();
  return assets;
}

}  // namespace marionette::fuzz
