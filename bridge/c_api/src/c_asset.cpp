// mn_asset: a character file loaded once (from a path or from memory, through the engine's
// file reader or the disk) and shared by the characters made from it.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "handles.hpp"
#if MARIONETTE_C_SHIPPED_DATA
#include "shipped_data.hpp"
#endif
#include "marionette/core/limits.hpp"
#include "marionette/io/import.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/rig/rig.hpp"

using marionette::capi::badStructSize;
using marionette::capi::fail;
using marionette::capi::guarded;
using marionette::capi::isLive;
using marionette::capi::notLive;

// The file the engine's read function is filling.
struct mn_file_sink {
  std::string* bytes = nullptr;
  bool tooLarge = false;
};

namespace {

// The C options as ImportOptions; the engine's read function behind a FileReader.
bool toImportOptions(const mn_scene* scene, const char* call, const mn_import_options* given,
                     marionette::ImportOptions& out, const char*& profilePath, mn_status& status) {
  const mn_import_options o = given ? *given : mn_import_options_default();
  if (given && given->struct_size != sizeof(mn_import_options)) {
    status = fail(scene, MN_ERROR_INVALID_ARGUMENT,
                  badStructSize(call, "mn_import_options", given->struct_size, sizeof(mn_import_options)));
    return false;
  }
  if (!(o.extra_scale > 0.0f) || !std::isfinite(o.extra_scale)) {
    status = fail(scene, MN_ERROR_INVALID_ARGUMENT,
                  std::string(call) + ": extra_scale must be a positive finite number, got " + std::to_string(o.extra_scale));
    return false;
  }
  out.loadMeshes = false;  // the runtime needs the skeleton, clips and morph names
  out.isolateThirdPartyParsers = o.isolate != 0;
  out.allowFilesOutsideModelFolder = o.allow_files_outside_model_folder != 0;
  out.extraScale = o.extra_scale;
  out.readFile = marionette::capi::engineReader(o.read_file, o.read_file_user);
  profilePath = o.profile_path;
  return true;
}

}  // namespace

marionette::FileReader marionette::capi::engineReader(mn_read_file_fn fn, void* user) {
  if (!fn) return {};
  return [fn, user](const std::string& path, std::string& bytes, std::string& why) {
    bytes.clear();
    mn_file_sink sink{&bytes};
    const int found = fn(user, path.c_str(), &sink);
    if (sink.tooLarge) {
      why = "the file reader gave more than " + std::to_string(marionette::limits::kMaxModelFileBytes >> 20) + " MiB";
      return false;
    }
    return found != 0;
  };
}

namespace {

// A missing file is MN_ERROR_IO, a file that is not valid MN_ERROR_LOAD.
bool unreadable(const marionette::Diagnostics& d) {
  for (const marionette::Diagnostic& item : d.items)
    if (item.severity == marionette::Severity::Error &&
        (item.message.rfind("file does not exist", 0) == 0 ||
         item.message.find("cannot read") != std::string::npos))
      return true;
  return false;
}

void addLines(std::string& to, const marionette::Diagnostics& d) {
  for (const marionette::Diagnostic& item : d.items) to += item.format() + "\n";
}

// The asset-handle functions' common checks and result.
mn_status newAsset(const char* call, const std::string& path, const std::string_view* bytes,
                   const mn_import_options* options, mn_asset** out) {
  return guarded(nullptr, [&] {
    marionette::ImportOptions io;
    const char* profile = nullptr;
    if (mn_status s{}; !toImportOptions(nullptr, call, options, io, profile, s)) return s;
    auto handle = std::make_unique<mn_asset>();
    std::string warnings;
    if (const mn_status s = marionette::capi::loadAsset(nullptr, call, path, bytes, io, profile, *handle, warnings);
        s != MN_OK)
      return s;
    handle->warnings = std::move(warnings);
    *out = handle.release();
    return MN_OK;
  });
}

}  // namespace

namespace marionette::capi {

mn_status loadAsset(const mn_scene* scene, const char* call, const std::string& path, const std::string_view* bytes,
                    const ImportOptions& options, const char* profilePath, mn_asset& out, std::string& warnings) {
  ImportResult imported = bytes ? importAssetFromMemory(*bytes, path, options) : importAsset(path, options);
  if (!imported.ok())
    return fail(scene, unreadable(imported.diagnostics) ? MN_ERROR_IO : MN_ERROR_LOAD,
                std::string(call) + ": " + imported.diagnostics.format());
  addLines(warnings, imported.diagnostics);
  auto asset = std::make_shared<Asset>(std::move(*imported.asset));
  auto rig = std::make_shared<Rig>(*asset);
  if (profilePath) {
    CharacterProfileResult p = loadCharacterProfile(profilePath, *asset, options.readFile);
    if (!p.diagnostics.ok())
      return fail(scene, unreadable(p.diagnostics) ? MN_ERROR_IO : MN_ERROR_LOAD,
                  std::string(call) + ": " + p.diagnostics.format());
    addLines(warnings, p.diagnostics);
    rig->setProfile(std::move(p.profile));
  } else if (auto shipped =
#if MARIONETTE_C_SHIPPED_DATA  // no file system: the profiles built in
                 findShippedProfile(*asset, {kShippedProfileFolder}, shippedFileReader())
#else
                 findShippedProfile(*asset, shippedProfileFolders(libraryFolder(), MARIONETTE_SOURCE_PROFILES))
#endif
             ) {
    warnings += "profile: " + shipped->file + " (the installed profile of this asset)\n";
    rig->setProfile(std::move(shipped->profile));
  }
  out.rig = std::move(rig);
  out.asset = std::move(asset);
  return MN_OK;
}

}  // namespace marionette::capi

extern "C" {

mn_status mn_file_sink_write(mn_file_sink* sink, const void* bytes, size_t size) {
  if (!sink || !sink->bytes || (!bytes && size > 0))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_file_sink_write: sink or bytes is NULL");
  if (size > marionette::limits::kMaxModelFileBytes - sink->bytes->size()) {
    sink->tooLarge = true;
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_file_sink_write: the file is larger than 512 MiB");
  }
  return guarded(nullptr, [&] {
    sink->bytes->append(static_cast<const char*>(bytes), size);
    return MN_OK;
  });
}

mn_import_options mn_import_options_default(void) {
  mn_import_options o{};
  o.struct_size = sizeof(mn_import_options);
  o.extra_scale = 1.0f;
  return o;
}

mn_status mn_asset_load_file(const char* path, const mn_import_options* options, mn_asset** out) {
  if (out) *out = nullptr;
  if (!path || !out) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_asset_load_file: path or out is NULL");
  return newAsset("mn_asset_load_file", path, nullptr, options, out);
}

mn_status mn_asset_load_memory(const void* bytes, size_t size, const char* name_hint, const mn_import_options* options,
                               mn_asset** out) {
  if (out) *out = nullptr;
  if (!bytes || size == 0 || !name_hint || !out)
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT,
                "mn_asset_load_memory: bytes, name_hint or out is NULL, or size is 0");
  const std::string_view view(static_cast<const char*>(bytes), size);
  return newAsset("mn_asset_load_memory", name_hint, &view, options, out);
}

void mn_asset_release(mn_asset* asset) {
  if (!asset) return;
  if (!isLive(asset)) {
    fail(nullptr, MN_ERROR_INVALID_ARGUMENT, "mn_asset_release: asset is not a live handle (released already?)");
    return;
  }
  delete asset;  // the characters made from it keep their shared rig and asset
}

const char* mn_asset_name(const mn_asset* asset) {
  return asset && isLive(asset) ? asset->rig->sourcePath().c_str() : "";
}
size_t mn_asset_joint_count(const mn_asset* asset) {
  return asset && isLive(asset) ? asset->rig->skeleton().jointCount() : 0;
}
size_t mn_asset_clip_count(const mn_asset* asset) { return asset && isLive(asset) ? asset->rig->clips().size() : 0; }
const char* mn_asset_report(const mn_asset* asset) {
  return asset && isLive(asset) ? asset->warnings.c_str() : "";
}

}  // extern "C"
