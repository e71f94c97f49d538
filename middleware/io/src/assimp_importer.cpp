// Imports FBX, COLLADA, BVH, MD5, X (and whatever else Assimp reads) into an Asset.
//
// What comes out:
//  - Skeleton: the nodes that are mesh bones or animation targets, plus all their
//    ancestors below the scene root, depth-first (parents before children). A file
//    with neither (a static model) gets its whole node tree, so every import has a
//    skeleton. The scene root's transform becomes Skeleton::rootTransform unless the
//    root is itself a joint (BVH puts the hips there).
//  - Lengths: FBX is converted to metres from its UnitScaleFactor (centimetres per
//    unit); other formats keep their numbers. ImportOptions::extraScale multiplies both.
//  - One Clip per aiAnimation, in seconds, starting at 0.
//  - One Mesh per node that carries meshes, one primitive per aiMesh (Assimp has
//    already split them by material).
//
// This file: the file checks, Assimp's read (first in an isolated child), the
// unit scale and the order of the stages. The skeleton, clips and meshes are
// converted by assimp_skeleton.cpp, assimp_animation.cpp and assimp_meshes.cpp,
// sharing the state in assimp_conversion.hpp.
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "assimp_conversion.hpp"
#include "assimp_file_system.hpp"
#include "file_extension.hpp"
#include "isolated_call.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/limits.hpp"
#include "marionette/io/import.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;
using assimp_detail::buildSkeleton;
using assimp_detail::convertAnimations;
using assimp_detail::convertMeshes;
using assimp_detail::Importing;
using detail::lowerExtension;

// ---------------------------------------------------------------- before reading

// The first `count` whitespace-separated words of a text file, skipping '#' comments.
std::vector<std::string> firstWords(std::string_view head, std::size_t count) {
  auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  std::vector<std::string> words;
  for (std::size_t i = 0; i < head.size() && words.size() < count;) {
    if (head[i] == '#') {
      while (i < head.size() && head[i] != '\n') ++i;
    } else if (space(head[i])) {
      ++i;
    } else {
      const std::size_t start = i;
      while (i < head.size() && !space(head[i]) && head[i] != '#') ++i;
      words.emplace_back(head.substr(start, i - start));
    }
  }
  return words;
}

// A non-negative decimal count (saturating), or nothing if `word` is not one.
std::optional<std::uint64_t> parseCount(const std::string& word) {
  if (word.empty() || !std::all_of(word.begin(), word.end(), [](unsigned char c) { return std::isdigit(c); }))
    return std::nullopt;
  if (word.size() > 18) return std::numeric_limits<std::uint64_t>::max();
  return std::stoull(word);
}

// Assimp's OFF reader allocates (and zero-fills) as many vertices as the header
// declares before it notices that the file is short, so a 300-byte file declaring
// 10^11 vertices costs gigabytes and minutes. Refuse counts the file cannot hold.
bool checkOffCounts(const std::string& path, std::string_view head, std::uintmax_t size, Diagnostics& diag) {
  const std::vector<std::string> words = firstWords(head, 4);
  std::size_t first = 0;  // a header-less OFF starts with the counts
  if (!words.empty() && words[0].size() >= 3 && words[0].compare(words[0].size() - 3, 3, "OFF") == 0) {
    // [ST][C][N][4][n]OFF: the 'n' variant puts a dimension before the counts.
    first = words[0].find('n') != std::string::npos ? 2 : 1;
  }
  if (words.size() < first + 2) return true;  // Assimp reports a broken header itself
  const auto vertices = parseCount(words[first]), faces = parseCount(words[first + 1]);
  if (!vertices || !faces) return true;
  // Every vertex and every face needs at least two bytes ("0\n").
  const std::uint64_t room = size / 2;
  if (*vertices <= room && *faces <= room) return true;
  diag.error(path, "OFF header declares " + words[first] + " vertices and " + words[first + 1] +
                       " faces, more than a file of " + std::to_string(size) + " bytes can hold");
  return false;
}

// `bytes`: the file as the engine's reader gave it; null: on disk.
bool checkFile(const std::string& path, const std::string* bytes, Diagnostics& diag) {
  std::error_code ec;
  const std::uintmax_t size = bytes ? bytes->size() : fs::file_size(path, ec);
  if (ec) {
    diag.error(path, "cannot read the file: " + ec.message());
    return false;
  }
  if (size > limits::kMaxModelFileBytes) {
    diag.error(path, "file is " + std::to_string(size >> 20) +
                         " MiB; model files over 512 MiB are refused (limits::kMaxModelFileBytes)");
    return false;
  }
  if (lowerExtension(path) != ".off") return true;
  if (bytes) return checkOffCounts(path, std::string_view(*bytes).substr(0, 4096), size, diag);
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return checkOffCounts(path, head, size, diag);
}

// With an engine's reader, Assimp reads every file through it (the importer owns the
// handler; the returned pointer lives as long as the importer). Null: the disk.
assimp_detail::ReaderFileSystem* useReader(Assimp::Importer& importer, const std::string& path,
                                           const ImportOptions& options) {
  if (!options.readFile) return nullptr;
  auto* files = new assimp_detail::ReaderFileSystem(options.readFile, path, options.allowFilesOutsideModelFolder);
  importer.SetIOHandler(files);
  return files;
}

unsigned postProcessFlags(bool meshes) {
  unsigned flags = aiProcess_ValidateDataStructure;
  if (meshes)
    flags |= aiProcess_Triangulate | aiProcess_LimitBoneWeights | aiProcess_JoinIdenticalVertices |
             aiProcess_GenSmoothNormals;
  return flags;
}

void configure(Assimp::Importer& importer) {
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  // BVH (and a lone MD5 animation) would otherwise get a generated stick-figure
  // mesh that we would import as real geometry.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
  // A bone without weights is still a skin joint with a real inverse bind.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_REMOVE_EMPTY_BONES, false);
  importer.SetPropertyInteger(AI_CONFIG_PP_LBW_MAX_WEIGHTS, 4);
}

const aiScene* readScene(Assimp::Importer& importer, const std::string& path, bool meshes, Diagnostics& diag,
                         const assimp_detail::ReaderFileSystem* files = nullptr) {
  // Post-processing is a second step: a motion-only file has no meshes, and the
  // validator rejects that unless the scene is flagged incomplete first.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (files)  // what the engine's reader refused or could not give
    for (const std::string& problem : files->problems()) diag.error(path, problem);
  if (!scene) {
    diag.error(path, std::string("Assimp could not read the file: ") + importer.GetErrorString());
    return nullptr;
  }
  if (files && !files->problems().empty()) return nullptr;
  if (scene->mNumMeshes == 0) {
    // The importer owns this scene; flagging it is how Assimp marks skeleton- or
    // animation-only data (some readers, e.g. FBX, set the flag themselves).
    const_cast<aiScene*>(scene)->mFlags |= AI_SCENE_FLAGS_INCOMPLETE;
  }
  scene = importer.ApplyPostProcessing(postProcessFlags(meshes));
  if (!scene) {
    diag.error(path, std::string("Assimp rejected the file's contents: ") + importer.GetErrorString());
    return nullptr;
  }
  if (!scene->mRootNode) {
    diag.error(path, "Assimp returned a scene without a root node");
    return nullptr;
  }
  if (scene->mFlags & AI_SCENE_FLAGS_VALIDATION_WARNING)
    diag.warning(path, "Assimp's validator reported minor problems in the file's data");
  return scene;
}

// ---------------------------------------------------------------- units

std::optional<double> metadataNumber(const aiMetadata* meta, const std::string& key) {
  if (!meta) return std::nullopt;
  float f = 0.0f;
  double d = 0.0;
  std::int32_t i = 0;
  if (meta->Get(key, f)) return f;
  if (meta->Get(key, d)) return d;
  if (meta->Get(key, i)) return i;
  return std::nullopt;
}

bool isFbx(const Importing& im) {
  if (lowerExtension(im.path) == ".fbx") return true;
  aiString format;
  return im.scene.mMetaData && im.scene.mMetaData->Get("SourceAsset_Format", format) &&
         std::string_view(format.C_Str()).find("FBX") != std::string_view::npos;
}

// Metres per file unit. Assimp leaves FBX lengths in the file's unit, which the
// file states as UnitScaleFactor = centimetres per unit.
float fileUnitScale(Importing& im) {
  if (!isFbx(im)) return 1.0f;
  const std::optional<double> cm = metadataNumber(im.scene.mMetaData, "UnitScaleFactor");
  if (!cm) {
    im.warning("FBX file states no UnitScaleFactor; assuming centimetres");
    return 0.01f;
  }
  if (!std::isfinite(*cm) || *cm <= 0.0) {
    im.warning("FBX UnitScaleFactor " + std::to_string(*cm) + " is not a positive number; assuming centimetres");
    return 0.01f;
  }
  return static_cast<float>(*cm / 100.0);
}

// ---------------------------------------------------------------- whole asset

void validate(Importing& im) {
  const Skeleton& skeleton = im.asset.skeleton;
  if (std::string e = skeleton.validate(); !e.empty()) im.error("skeleton: " + e);
  if (!isFinite(skeleton.rootTransform)) im.error("the scene root's transform is not finite");
  for (const Clip& clip : im.asset.clips)
    if (std::string e = clip.validate(skeleton.jointCount()); !e.empty()) im.error(e);
}

void convertScene(Importing& im) {
  im.asset.sourcePath = im.path;
  im.asset.unitScale = fileUnitScale(im) * im.options.extraScale;
  im.scale = im.asset.unitScale;
  buildSkeleton(im);
  if (!im.diag.ok()) return;
  if (im.options.loadAnimations) convertAnimations(im);
  if (im.options.loadMeshes && im.diag.ok()) convertMeshes(im);
  if (im.scene.mNumMeshes == 0 && im.scene.mNumAnimations == 0 && im.scene.mRootNode->mNumChildren == 0)
    im.warning("the file holds no meshes, no animations and no nodes besides the root");
  if (im.diag.ok()) validate(im);
}

// Reads the file once in a child process first: if Assimp crashes, hangs or
// runs out of memory there, the caller gets an error instead (isolated_call.hpp).
// The in-process read that follows is the same deterministic code on the same
// bytes, so it succeeds where the child did.
bool parsesInIsolation(const std::string& path, const ImportOptions& options, Diagnostics& diag) {
  const detail::IsolatedOutcome outcome = detail::runIsolated(
      [&] {
        Assimp::Importer importer;
        configure(importer);
        const auto* files = useReader(importer, path, options);
        Diagnostics ignored;
        return readScene(importer, path, options.loadMeshes, ignored, files) ? 0 : 1;
      },
      options.parserTimeoutSeconds, options.parserMemoryLimitBytes);
  using Kind = detail::IsolatedOutcome::Kind;
  if (outcome.kind == Kind::Crashed || outcome.kind == Kind::TimedOut) {
    diag.error(path, "Assimp's reader " + outcome.describe(options.parserTimeoutSeconds) +
                         " on this file; it is malformed or too large, and nothing was loaded");
    return false;
  }
  return true;  // Completed (either way) or Unavailable: the in-process read reports the details
}

void importInto(ImportResult& result, const std::string& path, const ImportOptions& options) {
  Diagnostics& diag = result.diagnostics;
  if (!std::isfinite(options.extraScale) || options.extraScale <= 0.0f) {
    diag.error(path, "ImportOptions::extraScale must be a positive number, got " + std::to_string(options.extraScale));
    return;
  }
  std::string bytes;
  if (options.readFile) {  // the size and header checks on the engine's bytes
    std::string why;
    if (!readWholeFile(options.readFile, path, limits::kMaxModelFileBytes, bytes, why)) {
      diag.error(path, why);
      return;
    }
  }
  if (!checkFile(path, options.readFile ? &bytes : nullptr, diag)) return;
  bytes = std::string();
  if (options.isolateThirdPartyParsers && !parsesInIsolation(path, options, diag)) return;
  Assimp::Importer importer;
  configure(importer);
  const auto* files = useReader(importer, path, options);
  const aiScene* scene = readScene(importer, path, options.loadMeshes, diag, files);
  if (!scene) return;
  Importing im{*scene, path, options, diag, {}, 1.0f, {}, {}, {}};
  convertScene(im);
  result.asset = std::move(im.asset);
}

}  // namespace

ImportResult importWithAssimp(const std::string& path, const ImportOptions& options) {
  ImportResult result;
  try {
    importInto(result, path, options);
  } catch (const std::exception& e) {
    result.diagnostics.error(path, std::string("import failed: ") + e.what());
  } catch (...) {
    result.diagnostics.error(path, "import failed with an unknown exception");
  }
  if (!result.diagnostics.ok()) result.asset.reset();
  return result;
}

}  // namespace marionette
