// Loading characters and motions from files. The format is chosen by extension:
// .gltf .glb .vrm .vrma through tinygltf; .fbx .dae .bvh .md5mesh .md5anim .x
// (and anything else Assimp reads) through Assimp when built with it.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "marionette/core/diagnostic.hpp"
#include "marionette/core/file_reader.hpp"
#include "marionette/asset/asset.hpp"

namespace marionette {

struct ImportOptions {
  bool loadMeshes = true;     // false: skeleton and clips only (faster; what a motion file needs)
  bool loadAnimations = true;
  // Multiplies every length (translations, positions) after the file's own unit
  // conversion. FBX files are converted to metres from their UnitScaleFactor;
  // BVH has no unit, so its numbers are kept unless this says otherwise.
  float extraScale = 1.0f;
  // Assimp's readers can crash or hang on malformed files (a bug in the dependency,
  // not catchable in-process). When true, the file is first read in a forked child
  // with the limits below, and a crash or hang there becomes an error; it costs one
  // extra parse of Assimp formats. Off by default: a library must not fork the process
  // that embeds it (an engine with a renderer, audio threads and a debugger; mobile
  // platforms forbid it). The command-line tools turn it on. Without it the host is
  // protected by the readers' limits and validation, fuzzed (docs/reliability.md).
  bool isolateThirdPartyParsers = false;
  // A glTF's external buffers and images are read only from the model's own folder
  // (and below): a uri like "../../etc/passwd" or an absolute path is an error naming
  // it, and nothing of that file is read. True allows any path (trusted files only).
  bool allowFilesOutsideModelFolder = false;
  // Where the files are read (core/file_reader.hpp): the model and every file it names (a
  // glTF's buffers and images, an OBJ's materials, ...), through an engine's archive or
  // virtual file system. Empty: the disk. The folder rule above holds through it, by path.
  FileReader readFile{};
  double parserTimeoutSeconds = 60.0;
  std::size_t parserMemoryLimitBytes = std::size_t{4} << 30;  // 4 GiB of address space
};

struct ImportResult {
  std::optional<Asset> asset;  // empty when loading failed
  Diagnostics diagnostics;     // errors and warnings, each naming the file
  [[nodiscard]] bool ok() const noexcept { return asset.has_value() && diagnostics.ok(); }
};

// Never throws; never returns NaN data (non-finite values are an error naming the place).
[[nodiscard]] ImportResult importAsset(const std::string& path, const ImportOptions& options = {});

// The same from bytes in memory (a file the engine has read or unpacked). `nameHint` is the
// file's name: its extension chooses the format, messages name it, and the files it refers
// to (a .gltf's buffers and images) are resolved against its folder and read through
// options.readFile (the disk when empty). The bytes are copied; they need not outlive the call.
[[nodiscard]] ImportResult importAssetFromMemory(std::string_view bytes, const std::string& nameHint,
                                                 const ImportOptions& options = {});

// The individual importers (importAsset dispatches to them).
[[nodiscard]] ImportResult importGltf(const std::string& path, const ImportOptions& options);
#ifdef MARIONETTE_HAS_ASSIMP
[[nodiscard]] ImportResult importWithAssimp(const std::string& path, const ImportOptions& options);
#endif

}  // namespace marionette
