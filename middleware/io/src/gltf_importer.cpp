// glTF 2.0 / GLB / VRM / VRMA import through tinygltf.
//
// Stages: read the file; check the GLB container and the JSON (our own schema
// type check, see gltf_json.hpp); let tinygltf parse the model and load the
// buffers; check every cross-reference; then build the node graph, skeleton,
// morph-target list, meshes, materials, clips and the VRM humanoid, each stage
// reading accessors only through the bounds-checked AccessorReader. Any error
// leaves the result without an asset; nothing here throws out or returns NaN.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "gltf_animation.hpp"
#include "gltf_mesh.hpp"
#include "gltf_vrm.hpp"
#include "marionette/core/file_reader.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/limits.hpp"
#include "marionette/io/import.hpp"

namespace marionette {
namespace {

using namespace gltf_detail;

// tinygltf would decode every image; we keep the encoded bytes of the images inside the file
// (for the asset's embeddedImages) when meshes are loaded, and nothing otherwise.
bool keepImageUndecoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void* keep) {
  // A buffer view's bytes are copied after the load, checked against their buffer (tinygltf
  // hands them over without that check: a view past its buffer's end was read out of bounds).
  if (keep && *static_cast<const bool*>(keep) && bytes && size > 0 && imageInsideFile(*image) && image->bufferView < 0)
    image->image.assign(bytes, bytes + size);
  return true;
}

// The encoded bytes of the images stored in buffer views, each view checked against its buffer.
bool keepBufferViewImages(const std::string& path, tinygltf::Model& model, Diagnostics& diag) {
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    tinygltf::Image& image = model.images[i];
    if (image.bufferView < 0) continue;
    const auto view = static_cast<std::size_t>(image.bufferView);
    const tinygltf::BufferView* v = view < model.bufferViews.size() ? &model.bufferViews[view] : nullptr;
    const tinygltf::Buffer* b =
        v && v->buffer >= 0 && static_cast<std::size_t>(v->buffer) < model.buffers.size() ? &model.buffers[static_cast<std::size_t>(v->buffer)] : nullptr;
    if (!b || v->byteOffset > b->data.size() || v->byteLength > b->data.size() - v->byteOffset) {
      diag.error(path, "image " + std::to_string(i) + ": its buffer view lies outside its buffer");
      return false;
    }
    const auto* first = b->data.data() + v->byteOffset;
    image.image.assign(first, first + v->byteLength);
  }
  return true;
}

std::uint32_t readU32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // GLB is little-endian, as is every platform we build for
}

// ---- the file ----------------------------------------------------------------------

struct Source {
  std::string bytes;  // as read (readWholeFile): not copied again
  bool binary = false;
  std::string jsonText;
  std::size_t glbLength = 0;  // bytes the GLB header declares
};

bool readFile(const std::string& path, const ImportOptions& options, Source& src, Diagnostics& diag) {
  std::string why;
  if (!readWholeFile(options.readFile, path, limits::kMaxModelFileBytes, src.bytes, why)) {
    diag.error(path, why);
    return false;
  }
  if (src.bytes.empty()) {
    diag.error(path, "file is empty");
    return false;
  }
  return true;
}

bool hasGlbMagic(const std::string& b) { return b.size() >= 4 && std::memcmp(b.data(), "glTF", 4) == 0; }

// Checks the 12-byte header and the JSON chunk and extracts the JSON text, so that
// a truncated file is reported as such rather than as a vague parse failure.
bool splitGlb(const std::string& path, Source& src, Diagnostics& diag) {
  const auto& b = src.bytes;
  if (b.size() < 20) {
    diag.error(path, "GLB file is only " + std::to_string(b.size()) + " bytes; the header alone needs 20");
    return false;
  }
  const std::uint32_t version = readU32(b, 4), length = readU32(b, 8);
  const std::uint32_t jsonLength = readU32(b, 12), jsonType = readU32(b, 16);
  if (version != 2) {
    diag.error(path, "GLB container version " + std::to_string(version) + " is not supported (expected 2)");
    return false;
  }
  if (length > b.size()) {
    diag.error(path, "GLB header declares " + std::to_string(length) + " bytes but the file has only " +
                         std::to_string(b.size()) + " (truncated file?)");
    return false;
  }
  if (jsonType != 0x4E4F534Au || jsonLength == 0 || 20ull + jsonLength > length) {
    diag.error(path,
               "GLB first chunk is not a JSON chunk that fits in the file (length " + std::to_string(jsonLength) + ")");
    return false;
  }
  src.glbLength = length;
  src.jsonText.assign(reinterpret_cast<const char*>(b.data()) + 20, jsonLength);
  return true;
}

bool prepareSource(const std::string& path, const ImportOptions& options, Source& src, Diagnostics& diag) {
  if (!readFile(path, options, src, diag)) return false;
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // .glb, .vrm and .vrma are GLB containers; a .gltf is JSON unless it carries the GLB magic.
  src.binary = ext == ".glb" || ext == ".vrm" || ext == ".vrma" || hasGlbMagic(src.bytes);
  if (!src.binary) {
    src.jsonText.assign(src.bytes.begin(), src.bytes.end());
    return true;
  }
  if (!hasGlbMagic(src.bytes)) {
    diag.error(path, "not a GLB file: it does not start with the 'glTF' magic");
    return false;
  }
  return splitGlb(path, src, diag);
}

// ---- JSON checks ---------------------------------------------------------------------

bool requiredExtensionSupported(const std::string& name) {
  static const char* kSupported[] = {"KHR_mesh_quantization", "KHR_texture_transform", "KHR_texture_basisu",
                                     "EXT_texture_webp",      "KHR_lights_punctual",   "KHR_materials_"};
  for (const char* s : kSupported)
    if (name.rfind(s, 0) == 0) return true;
  return name.rfind("VRM", 0) == 0;  // VRM, VRMC_*: data we read or may ignore
}

bool checkDocument(const std::string& path, const Json& doc, Diagnostics& diag) {
  // Real files nest a dozen levels; the limit only stops stack-exhausting input.
  constexpr std::size_t kMaxDepth = 128;
  if (const std::size_t depth = nestingDepth(doc); depth > kMaxDepth) {
    diag.error(path, "JSON is nested " + std::to_string(depth) + " levels deep; at most " + std::to_string(kMaxDepth) +
                         " are accepted");
    return false;
  }
  const auto problems = SchemaChecker().check(doc);
  for (const std::string& p : problems) diag.error(path, "glTF schema: " + p);
  if (!problems.empty()) return false;
  const std::string version = asString(member(*member(doc, "asset"), "version"));
  if (version.rfind("2.", 0) != 0) {
    diag.error(path, "glTF version '" + version + "' is not supported (expected 2.x)");
    return false;
  }
  bool ok = true;
  if (const Json* required = member(doc, "extensionsRequired"))
    for (const Json& e : *required)
      if (!requiredExtensionSupported(e.get<std::string>())) {
        diag.error(path, "the file requires extension '" + e.get<std::string>() + "', which is not supported");
        ok = false;
      }
  return ok;
}

std::optional<Json> parseJson(const std::string& path, const std::string& text, Diagnostics& diag) {
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    diag.error(path, std::string("invalid JSON: ") + e.what());
    return std::nullopt;
  }
}

void addLines(const std::string& path, const std::string& text, bool error, Diagnostics& diag) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    // tinygltf treats a skin's inverseBindMatrices as required; glTF does not (identity).
    if (line.empty() || line.find("'inverseBindMatrices' property is missing") != std::string::npos) continue;
    if (error)
      diag.error(path, line);
    else
      diag.warning(path, line);
  }
}

// tinygltf's file access for external buffers and images, kept inside the model's
// folder unless the caller allows more, and to regular files (a FIFO would block). With an
// engine's reader (ImportOptions::readFile) the files come from it, the folder compared by
// path alone (there is no disk to resolve links on), and each file is read once: tinygltf
// asks whether it exists, then reads it.
struct FolderGuard {
  std::filesystem::path root;  // canonical; with a reader, lexically normal
  bool allowOutside = false;
  const FileReader* reader = nullptr;  // null: the disk
  std::vector<std::string> refused, notRegular, unreadable;
  std::string lastPath, lastBytes;  // the reader's last file, between exists() and read()

  bool permits(const std::string& file) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (reader) {
      if (!allowOutside && !insideFolder(fs::path(file), root)) {
        refused.push_back(file);
        return false;
      }
      return true;
    }
    if (!allowOutside) {
      const fs::path resolved = fs::weakly_canonical(fs::path(file), ec);
      if (ec || !insideFolder(resolved, root)) {
        // tinygltf also probes other folders (the current one); only a file that is there counts
        if (fs::exists(file, ec)) refused.push_back(file);
        return false;
      }
    }
    if (fs::exists(file, ec) && !fs::is_regular_file(file, ec)) {
      notRegular.push_back(file);
      return false;
    }
    return true;
  }
  bool readThroughReader(const std::string& file) {
    if (lastPath == file) return true;
    std::string why;  // the reader gets the path folded, as FileReader promises
    const std::string folded = std::filesystem::path(file).lexically_normal().generic_string();
    if (!readWholeFile(*reader, folded, limits::kMaxModelFileBytes, lastBytes, why)) {
      unreadable.push_back(file + ": " + why);
      lastPath.clear();
      return false;
    }
    lastPath = file;
    return true;
  }
  static bool exists(const std::string& file, void* self) {
    auto& g = *static_cast<FolderGuard*>(self);
    if (!g.permits(file)) return false;
    return g.reader ? g.readThroughReader(file) : tinygltf::FileExists(file, nullptr);
  }
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& file, void* self) {
    auto& g = *static_cast<FolderGuard*>(self);
    if (!g.permits(file)) {
      if (err) *err += "refused: " + file + "\n";
      return false;
    }
    if (!g.reader) return tinygltf::ReadWholeFile(out, err, file, nullptr);
    if (!g.readThroughReader(file)) return false;
    out->assign(g.lastBytes.begin(), g.lastBytes.end());
    g.lastPath.clear();
    g.lastBytes = std::string();
    return true;
  }
  static std::string expand(const std::string& file, void*) { return file; }  // no ~ or $VAR expansion
  static bool write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }
};

bool loadModel(const std::string& path, const Source& src, const ImportOptions& options, tinygltf::Model& model,
               Diagnostics& diag) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keepImageUndecoded, const_cast<bool*>(&options.loadMeshes));
  std::string err, warn;
  const std::string baseDir = std::filesystem::path(path).parent_path().string();
  FolderGuard guard;
  std::error_code ec;
  if (options.readFile) {
    guard.reader = &options.readFile;
    guard.root = std::filesystem::path(path).parent_path().lexically_normal();
  } else {
    guard.root = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec).parent_path(), ec);
  }
  guard.allowOutside = options.allowFilesOutsideModelFolder;
  loader.SetFsCallbacks({&FolderGuard::exists, &FolderGuard::expand, &FolderGuard::read, &FolderGuard::write, &guard});
  const bool ok = src.binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(src.bytes.data()),
                                                           static_cast<unsigned int>(src.glbLength), baseDir)
                             : loader.LoadASCIIFromString(&model, &err, &warn, src.jsonText.data(),
                                                          static_cast<unsigned int>(src.jsonText.size()), baseDir);
  for (const std::string& file : guard.refused)
    diag.error(path, "'" + file + "' is outside the model's folder '" + guard.root.string() +
                         "': not read (ImportOptions::allowFilesOutsideModelFolder allows it)");
  for (const std::string& file : guard.notRegular)
    diag.error(path, "'" + file + "' is not a regular file (a device, FIFO or folder): not read");
  if (!ok)  // what the engine's reader said about a file the model needs
    for (const std::string& line : guard.unreadable) diag.error(path, "the file reader could not read " + line);
  if (!guard.refused.empty() || !guard.notRegular.empty()) return false;  // tinygltf's own lines add nothing
  addLines(path, warn, false, diag);
  // When tinygltf succeeds, what it still puts in `err` are properties it
  // skipped; our schema check has already rejected every such case we rely on.
  addLines(path, err, !ok, diag);
  if (!ok && err.empty()) diag.error(path, "tinygltf could not load the file");
  if (ok && options.loadMeshes) return keepBufferViewImages(path, model, diag);
  return ok;
}

// ---- cross-references ------------------------------------------------------------------

class ReferenceChecker {
 public:
  explicit ReferenceChecker(const Context& ctx) : ctx_(ctx), m_(ctx.model) {}

  bool check() {
    scenes();
    nodes();
    meshes();
    views();
    skins();
    animations();
    materials();
    return ok_;
  }

 private:
  const Context& ctx_;
  const tinygltf::Model& m_;
  bool ok_ = true;

  template <class T>
  void ref(int index, const std::vector<T>& list, const std::string& from, const char* kind) {
    if (index < 0 || static_cast<std::size_t>(index) < list.size()) return;
    ctx_.error(from + " refers to " + kind + " " + std::to_string(index) + ", which does not exist (the file has " +
               std::to_string(list.size()) + ")");
    ok_ = false;
  }

  void scenes() {
    ref(m_.defaultScene, m_.scenes, "the default scene", "scene");
    for (std::size_t s = 0; s < m_.scenes.size(); ++s)
      for (int n : m_.scenes[s].nodes) ref(n, m_.nodes, "scene " + std::to_string(s), "node");
  }
  void nodes() {
    for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
      ref(m_.nodes[i].mesh, m_.meshes, ctx_.nodeLabel(i), "mesh");
      ref(m_.nodes[i].skin, m_.skins, ctx_.nodeLabel(i), "skin");
      ref(m_.nodes[i].camera, m_.cameras, ctx_.nodeLabel(i), "camera");
    }
  }
  void meshes() {
    for (std::size_t i = 0; i < m_.meshes.size(); ++i) {
      const auto& prims = m_.meshes[i].primitives;
      for (std::size_t p = 0; p < prims.size(); ++p) {
        const std::string where = "mesh '" + ctx_.meshName(i) + "' primitive " + std::to_string(p);
        for (const auto& [name, a] : prims[p].attributes) ref(a, m_.accessors, where + " " + name, "accessor");
        ref(prims[p].indices, m_.accessors, where + " indices", "accessor");
        ref(prims[p].material, m_.materials, where, "material");
        for (const auto& target : prims[p].targets)
          for (const auto& [name, a] : target) ref(a, m_.accessors, where + " morph target " + name, "accessor");
      }
    }
  }
  void views() {
    for (std::size_t i = 0; i < m_.accessors.size(); ++i)
      ref(m_.accessors[i].bufferView, m_.bufferViews, "accessor " + std::to_string(i), "buffer view");
    for (std::size_t i = 0; i < m_.images.size(); ++i)
      ref(m_.images[i].bufferView, m_.bufferViews, "image " + std::to_string(i), "buffer view");
    for (std::size_t i = 0; i < m_.bufferViews.size(); ++i) {
      const auto& v = m_.bufferViews[i];
      ref(v.buffer, m_.buffers, "buffer view " + std::to_string(i), "buffer");
      if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m_.buffers.size()) continue;
      const std::size_t size = m_.buffers[static_cast<std::size_t>(v.buffer)].data.size();
      if (v.byteOffset > size || v.byteLength > size - v.byteOffset) {
        ctx_.error("buffer view " + std::to_string(i) + " (bytes " + std::to_string(v.byteOffset) + " to " +
                   std::to_string(v.byteOffset + v.byteLength) + ") extends past the end of buffer " +
                   std::to_string(v.buffer) + " (" + std::to_string(size) + " bytes)");
        ok_ = false;
      }
    }
  }
  void skins() {
    for (std::size_t s = 0; s < m_.skins.size(); ++s) {
      const std::string where = "skin " + std::to_string(s);
      ref(m_.skins[s].inverseBindMatrices, m_.accessors, where + " inverse bind matrices", "accessor");
      ref(m_.skins[s].skeleton, m_.nodes, where + " skeleton", "node");
      for (std::size_t k = 0; k < m_.skins[s].joints.size(); ++k)
        ref(m_.skins[s].joints[k], m_.nodes, where + " joint " + std::to_string(k), "node");
    }
  }
  void animations() {
    for (std::size_t a = 0; a < m_.animations.size(); ++a) {
      const auto& anim = m_.animations[a];
      const std::string where = "animation '" + ctx_.animationName(a) + "'";
      for (std::size_t c = 0; c < anim.channels.size(); ++c) {
        ref(anim.channels[c].sampler, anim.samplers, where + " channel " + std::to_string(c), "sampler");
        ref(anim.channels[c].target_node, m_.nodes, where + " channel " + std::to_string(c), "node");
      }
      for (std::size_t s = 0; s < anim.samplers.size(); ++s) {
        ref(anim.samplers[s].input, m_.accessors, where + " sampler " + std::to_string(s) + " input", "accessor");
        ref(anim.samplers[s].output, m_.accessors, where + " sampler " + std::to_string(s) + " output", "accessor");
      }
    }
  }
  void materials() {
    for (std::size_t t = 0; t < m_.textures.size(); ++t)
      ref(m_.textures[t].source, m_.images, "texture " + std::to_string(t), "image");
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      const auto& mat = m_.materials[i];
      const std::string where = "material " + std::to_string(i);
      ref(mat.pbrMetallicRoughness.baseColorTexture.index, m_.textures, where + " base color", "texture");
      ref(mat.pbrMetallicRoughness.metallicRoughnessTexture.index, m_.textures, where + " metallic-roughness",
          "texture");
      ref(mat.normalTexture.index, m_.textures, where + " normal map", "texture");
      ref(mat.occlusionTexture.index, m_.textures, where + " occlusion map", "texture");
      ref(mat.emissiveTexture.index, m_.textures, where + " emissive map", "texture");
    }
  }
};

// ---- final checks --------------------------------------------------------------------------


// Values computed on import (baked transforms, extraScale) can overflow even
// when the file's numbers are finite; nothing non-finite may leave the importer.
void checkFinite(const Context& ctx, const Asset& asset) {
  for (const Mesh& mesh : asset.meshes)
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const MeshPrimitive& prim = mesh.primitives[p];
      bool ok = allFinite(prim.positions) && allFinite(prim.normals) && allFinite(prim.uvs) &&
                allFinite(prim.weights);
      for (const MorphTargetDelta& d : prim.morphTargets)
        ok = ok && allFinite(d.positions) && allFinite(d.normals);
      if (!ok)
        ctx.error("mesh '" + mesh.name + "' primitive " + std::to_string(p) +
                  " has non-finite vertex data after transformation and scaling");
    }
  for (const Clip& clip : asset.clips) {
    bool ok = true;
    for (const JointTrack& jt : clip.tracks) {
      ok = ok && allFinite(jt.translation.values) && allFinite(jt.scale.values) &&
           allFinite(jt.translation.times) && allFinite(jt.rotation.times) && allFinite(jt.scale.times);
      for (const glm::quat& q : jt.rotation.values)
        ok = ok && isFinite(q);
    }
    for (const MorphTrack& m : clip.morphTracks) ok = ok && allFinite(m.times) && allFinite(m.weights);
    if (!ok) ctx.error("clip '" + clip.name + "' has non-finite key values after scaling");
  }
  if (!isFinite(asset.skeleton.rootTransform))
    ctx.error("the skeleton's root transform is not finite after scaling");
}

void validate(const Context& ctx, const Asset& asset) {
  if (std::string e = asset.skeleton.validate(); !e.empty()) ctx.error("skeleton: " + e);
  for (const Clip& clip : asset.clips)
    if (std::string e = clip.validate(asset.skeleton.jointCount()); !e.empty()) ctx.error(e);
  checkFinite(ctx, asset);
}

// ---- the asset -----------------------------------------------------------------------------

std::vector<Clip> buildClips(const Context& ctx, const AccessorReader& reader, const SkeletonMap& map,
                             const std::vector<std::vector<int>>& morphs) {
  std::vector<Clip> clips;
  ClipBuilder builder(ctx, reader, map, morphs);
  for (std::size_t a = 0; a < ctx.model.animations.size(); ++a)
    if (auto clip = builder.build(a)) clips.push_back(std::move(*clip));
  appendMergedClip(ctx, clips);
  return clips;
}

std::optional<Asset> buildAsset(const Context& ctx) {
  if (!ReferenceChecker(ctx).check()) return std::nullopt;
  NodeGraph graph;
  if (!buildNodeGraph(ctx, graph)) return std::nullopt;
  Asset asset;
  asset.sourcePath = ctx.file;
  asset.unitScale = 1.0f;  // glTF is in metres
  AccessorReader reader(ctx);
  SkeletonMap map;
  if (!SkeletonBuilder(ctx, reader, graph).build(asset.skeleton, map)) return std::nullopt;
  const auto morphs = collectMorphTargets(ctx, asset.morphTargets);
  if (ctx.options.loadMeshes) {
    if (!MeshBuilder(ctx, reader, graph, asset.skeleton, map, morphs).build(asset.meshes)) return std::nullopt;
    asset.materials = buildMaterials(ctx);
  }
  if (ctx.options.loadAnimations) asset.clips = buildClips(ctx, reader, map, morphs);
  HumanoidReader(ctx, asset.skeleton, map, morphs).read(asset);
  validate(ctx, asset);
  return asset;
}

void importInto(const std::string& path, const ImportOptions& options, ImportResult& result) {
  Diagnostics& diag = result.diagnostics;
  if (!std::isfinite(options.extraScale) || !(options.extraScale > 0.0f)) {
    diag.error(path,
               "ImportOptions::extraScale must be a positive finite number, got " + std::to_string(options.extraScale));
    return;
  }
  Source src;
  if (!prepareSource(path, options, src, diag)) return;
  const std::optional<Json> doc = parseJson(path, src.jsonText, diag);
  if (!doc || !checkDocument(path, *doc, diag)) return;
  tinygltf::Model model;
  if (!loadModel(path, src, options, model, diag)) return;
  const Context ctx{model, *doc, path, options, diag};
  result.asset = buildAsset(ctx);
  // The images inside the file ("embedded:N", textureReference), moved out of the model that
  // is dropped here; an image that is a file of its own stays empty.
  if (result.asset && options.loadMeshes)
    for (tinygltf::Image& image : model.images)
      result.asset->embeddedImages.push_back(imageInsideFile(image) ? std::move(image.image)
                                                                    : std::vector<unsigned char>{});
}

}  // namespace

ImportResult importGltf(const std::string& path, const ImportOptions& options) {
  ImportResult result;
  try {
    importInto(path, options, result);
  } catch (const std::bad_alloc&) {
    result.diagnostics.error(path, "out of memory while importing");
  } catch (const std::exception& e) {
    result.diagnostics.error(path, std::string("unexpected failure while importing: ") + e.what());
  } catch (...) {
    result.diagnostics.error(path, "unexpected failure while importing");
  }
  if (!result.diagnostics.ok()) result.asset.reset();  // errors: no partial asset
  return result;
}

}  // namespace marionette
