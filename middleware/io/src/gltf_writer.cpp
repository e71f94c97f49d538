// glTF 2.0 / GLB writer (see marionette/io/gltf_writer.hpp and docs/gltf-export.md).
//
// Stages: check the inputs (skeleton, clips cleaned then Clip::validate, finite
// data); lay out nodes (joints, the root space, mesh nodes), the skin, materials
// and images, meshes and animations into one JSON document and one binary
// buffer; only then write the file(s), so an error leaves nothing half written.
// The JSON is written with nlohmann::json directly rather than through
// tinygltf's writer: we need exact control over accessor types, min/max and
// image bytes, which is what the validator checks.
#include "marionette/core/finite.hpp"
#include "marionette/io/gltf_writer.hpp"

#include "marionette/io/embedded_images.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "file_extension.hpp"
#include "file_write.hpp"
#include "gltf_skeleton.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using gltf_detail::maxDifference;

constexpr int kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::vec2) == 2 * sizeof(float) &&
              sizeof(glm::mat4) == 16 * sizeof(float) && sizeof(glm::u16vec4) == 4 * sizeof(std::uint16_t));


// glTF stores quaternions as x, y, z, w.
Json quatJson(const glm::quat& q) { return Json::array({q.x, q.y, q.z, q.w}); }
Json vec3Json(const glm::vec3& v) { return Json::array({v.x, v.y, v.z}); }

// ---- the binary buffer -----------------------------------------------------------------

// One buffer holding every accessor's data and the embedded images; each view
// starts on a 4-byte boundary, which satisfies every component type's alignment.
class BinaryBuffer {
 public:
  std::vector<unsigned char> bytes;
  Json views = Json::array();
  Json accessors = Json::array();

  int view(const void* data, std::size_t size, int target) {
    bytes.resize((bytes.size() + 3) & ~std::size_t{3}, 0);
    Json v = {{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", size}};
    if (target != 0) v["target"] = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bytes.insert(bytes.end(), p, p + size);
    views.push_back(std::move(v));
    return static_cast<int>(views.size()) - 1;
  }

  // Float accessor of `count` elements of `components` floats; min/max when asked
  // (required for POSITION and animation input; the validator checks them exactly).
  int floats(const float* data, std::size_t count, int components, const char* type, int target, bool bounds) {
    const int v = view(data, count * static_cast<std::size_t>(components) * sizeof(float), target);
    Json a = {{"bufferView", v}, {"componentType", kFloat}, {"count", count}, {"type", type}};
    if (bounds && count > 0) {
      Json lo = Json::array(), hi = Json::array();
      for (int c = 0; c < components; ++c) {
        float mn = data[c], mx = data[c];
        for (std::size_t i = 1; i < count; ++i) {
          mn = std::min(mn, data[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)]);
          mx = std::max(mx, data[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(c)]);
        }
        lo.push_back(mn);
        hi.push_back(mx);
      }
      a["min"] = std::move(lo);
      a["max"] = std::move(hi);
    }
    accessors.push_back(std::move(a));
    return static_cast<int>(accessors.size()) - 1;
  }

  int vec3s(const std::vector<glm::vec3>& v, int target, bool bounds) {
    return floats(reinterpret_cast<const float*>(v.data()), v.size(), 3, "VEC3", target, bounds);
  }
  int scalars(const std::vector<float>& v, bool bounds) { return floats(v.data(), v.size(), 1, "SCALAR", 0, bounds); }

  // Triangle indices in the smallest type that holds them. The largest value of
  // a type is the primitive-restart marker, which glTF forbids as an index.
  int indices(const std::vector<std::uint32_t>& idx, std::uint32_t maxIndex) {
    int v = 0, type = kUnsignedInt;
    if (maxIndex < 0xFFFFu) {
      std::vector<std::uint16_t> shorts(idx.begin(), idx.end());
      v = view(shorts.data(), shorts.size() * 2, kElementArrayBuffer);
      type = kUnsignedShort;
    } else {
      v = view(idx.data(), idx.size() * 4, kElementArrayBuffer);
    }
    accessors.push_back({{"bufferView", v}, {"componentType", type}, {"count", idx.size()}, {"type", "SCALAR"}});
    return static_cast<int>(accessors.size()) - 1;
  }

  int joints(const std::vector<glm::u16vec4>& j) {
    const int v = view(j.data(), j.size() * sizeof(glm::u16vec4), kArrayBuffer);
    accessors.push_back({{"bufferView", v}, {"componentType", kUnsignedShort}, {"count", j.size()}, {"type", "VEC4"}});
    return static_cast<int>(accessors.size()) - 1;
  }
};

// ---- clips --------------------------------------------------------------------------------

// What cleaning a clip changed, for one warning per clip.
struct ClipRepairs {
  std::size_t duplicateKeys = 0;
  std::size_t zeroQuaternions = 0;
  std::size_t nonUnitQuaternions = 0;
  std::string firstDuplicate;  // where the first duplicate key was, for the message
};

// Drops keys whose time equals the previous key's (the first is kept, as the
// importer does), with their value block of `stride` values. Left alone when
// the sizes disagree: Clip::validate then names the problem.
template <class T>
std::size_t dropDuplicateTimes(std::vector<float>& times, std::vector<T>& values, std::size_t stride) {
  if (stride == 0 || values.size() != times.size() * stride) return 0;
  std::size_t kept = 0, dropped = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (kept > 0 && times[k] == times[kept - 1]) {
      ++dropped;
      continue;
    }
    times[kept] = times[k];
    std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(k * stride), stride,
                values.begin() + static_cast<std::ptrdiff_t>(kept * stride));
    ++kept;
  }
  times.resize(kept);
  values.resize(kept * stride);
  return dropped;
}

template <class T>
std::size_t perKey(const Track<T>& t) {
  return t.interpolation == Interpolation::CubicSpline ? 3 : 1;
}

// The clip as it will be written: duplicate key times merged, rotation values
// normalized (cubic-spline tangents are not unit quaternions and stay as they are).
Clip cleanClip(const Clip& in, const Skeleton& skeleton, ClipRepairs& r) {
  Clip c = in;
  auto note = [&](std::size_t dropped, std::size_t joint, const char* what) {
    if (dropped > 0 && r.firstDuplicate.empty())
      r.firstDuplicate = std::string(what) + " of joint '" +
                         (joint < skeleton.jointCount() ? skeleton.names[joint] : std::to_string(joint)) + "'";
    r.duplicateKeys += dropped;
  };
  for (JointTrack& jt : c.tracks) {
    const auto j = static_cast<std::size_t>(jt.joint);
    note(dropDuplicateTimes(jt.translation.times, jt.translation.values, perKey(jt.translation)), j, "translation");
    note(dropDuplicateTimes(jt.rotation.times, jt.rotation.values, perKey(jt.rotation)), j, "rotation");
    note(dropDuplicateTimes(jt.scale.times, jt.scale.values, perKey(jt.scale)), j, "scale");
    const std::size_t per = perKey(jt.rotation);
    for (std::size_t i = per == 3 ? 1 : 0; i < jt.rotation.values.size(); i += per) {
      glm::quat& q = jt.rotation.values[i];
      if (!isFinite(q)) continue;  // reported as non-finite later
      const float len2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
      if (!(len2 > 1e-30f)) {
        ++r.zeroQuaternions;
      } else if (std::fabs(len2 - 1.0f) > 1e-4f) {
        ++r.nonUnitQuaternions;
      }
      q = safeNormalize(q);  // also rounds near-unit ones: the validator's tolerance is tight
    }
  }
  for (MorphTrack& m : c.morphTracks) {
    const std::size_t per = m.interpolation == Interpolation::CubicSpline ? 3 : 1;
    const std::size_t dropped = dropDuplicateTimes(m.times, m.weights, per * m.targets.size());
    if (dropped > 0 && r.firstDuplicate.empty()) r.firstDuplicate = "a morph-weight track";
    r.duplicateKeys += dropped;
  }
  c.updateDuration();
  return c;
}

std::string clipDataProblem(const Clip& c) {
  for (const JointTrack& jt : c.tracks) {
    const bool ok = allFinite(jt.translation.values) && allFinite(jt.scale.values) &&
                    allFinite(jt.rotation.values);
    if (!ok) return "joint " + std::to_string(jt.joint) + " has non-finite key values";
    for (const auto* times : {&jt.translation.times, &jt.rotation.times, &jt.scale.times})
      if (!times->empty() && times->front() < 0.0f)
        return "joint " + std::to_string(jt.joint) + " has a negative key time (" + std::to_string(times->front()) +
               "); glTF animation times must be >= 0";
  }
  for (const MorphTrack& m : c.morphTracks) {
    if (!allFinite(m.weights)) return "a morph-weight track has non-finite weights";
    if (!m.times.empty() && m.times.front() < 0.0f) return "a morph-weight track has a negative key time";
  }
  return {};
}

// ---- textures ---------------------------------------------------------------------------------

struct ImageBytes {
  std::vector<unsigned char> bytes;
  std::string mimeType;
};

std::string imageMimeType(const std::vector<unsigned char>& b) {
  static const unsigned char kPng[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (b.size() >= 8 && std::memcmp(b.data(), kPng, 8) == 0) return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  return {};
}

std::optional<std::vector<unsigned char>> readBytes(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) return std::nullopt;
  return b;
}

// A relative URI: unreserved characters and '/' as they are, everything else %XX.
std::string uriEncoded(const std::string& path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char ch : path) {
    if (std::isalnum(ch) || ch == '-' || ch == '_' || ch == '.' || ch == '~' || ch == '/') {
      out += static_cast<char>(ch);
    } else {
      out += '%';
      out += kHex[ch >> 4];
      out += kHex[ch & 15];
    }
  }
  return out;
}

// ---- files --------------------------------------------------------------------------------------

void appendU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>(v >> (8 * i));  // GLB is little-endian
}

// GLB: 12-byte header, the JSON chunk padded with spaces, the BIN chunk with zeros.
std::string glbContainer(std::string json, std::vector<unsigned char> bin) {
  json.resize((json.size() + 3) & ~std::size_t{3}, ' ');
  bin.resize((bin.size() + 3) & ~std::size_t{3}, 0);
  const std::size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
  std::string out = "glTF";
  out.reserve(total);
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(total));
  appendU32(out, static_cast<std::uint32_t>(json.size()));
  appendU32(out, 0x4E4F534Au);  // "JSON"
  out += json;
  if (!bin.empty()) {
    appendU32(out, static_cast<std::uint32_t>(bin.size()));
    appendU32(out, 0x004E4942u);  // "BIN\0"
    out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
  }
  return out;
}

// ---- the writer -----------------------------------------------------------------------------------

class Writer {
 public:
  Writer(const std::string& path, const Asset& asset, std::span<const Clip> clips, const GltfWriteOptions& options,
         Diagnostics& diag)
      : path_(path), asset_(asset), skeleton_(asset.skeleton), clips_(clips), options_(options), diag_(diag),
        images_(asset.sourcePath) {}

  void run() {
    const std::string ext = detail::lowerExtension(path_);
    if (ext != ".glb" && ext != ".gltf") {
      error("cannot write glTF: the extension must be .glb or .gltf, got '" + ext + "'");
      return;
    }
    binary_ = ext == ".glb";
    if (!checkSkeleton() || !prepareClips()) return;
    doc_["asset"] = {{"version", "2.0"}, {"generator", options_.generator}};
    writeNodes();
    writeSkin();
    writeMaterials();
    writeMeshes();
    writeAnimations();
    if (!ok_) return;
    finishDocument();
    save();
  }

 private:
  const std::string& path_;
  const Asset& asset_;
  const Skeleton& skeleton_;
  std::span<const Clip> clips_;
  const GltfWriteOptions& options_;
  Diagnostics& diag_;
  EmbeddedImages images_;
  bool ok_ = true;
  bool binary_ = true;

  Json doc_ = Json::object();
  Json nodes_ = Json::array();
  Json sceneNodes_ = Json::array();
  BinaryBuffer buffer_;
  std::vector<Clip> cleanClips_;
  std::vector<int> meshNode_;  // per Asset mesh: its node, or -1 when not written
  std::vector<int> materialIndex_;  // Asset material -> glTF material (all written, same order)
  int skin_ = -1;

  void error(std::string message) {
    diag_.error(path_, std::move(message));
    ok_ = false;
  }
  void warning(std::string message) { diag_.warning(path_, std::move(message)); }

  // ---- inputs

  bool checkSkeleton() {
    if (std::string e = skeleton_.validate(); !e.empty()) {
      error("cannot write the skeleton: " + e);
      return false;
    }
    if (!isFinite(skeleton_.rootTransform)) {
      error("cannot write the skeleton: its root transform is not finite");
      return false;
    }
    if (skeleton_.jointCount() > 65535) {
      error("the skeleton has " + std::to_string(skeleton_.jointCount()) +
            " joints; JOINTS_0 (unsigned short) can address at most 65535");
      return false;
    }
    return true;
  }

  bool prepareClips() {
    for (const Clip& in : clips_) {
      ClipRepairs r;
      Clip c = cleanClip(in, skeleton_, r);
      if (std::string e = c.validate(skeleton_.jointCount()); !e.empty()) {
        error("cannot write clip '" + in.name + "': " + e);
        continue;
      }
      if (std::string e = clipDataProblem(c); !e.empty()) {
        error("cannot write clip '" + in.name + "': " + e);
        continue;
      }
      if (r.duplicateKeys > 0)
        warning("clip '" + in.name + "': merged " + std::to_string(r.duplicateKeys) +
                " key(s) with the same time as the key before (first in the " + r.firstDuplicate +
                " track); the first key of each time is kept");
      if (r.zeroQuaternions > 0)
        warning("clip '" + in.name + "': " + std::to_string(r.zeroQuaternions) +
                " zero rotation key(s) written as the identity rotation");
      if (r.nonUnitQuaternions > 0)
        warning("clip '" + in.name + "': " + std::to_string(r.nonUnitQuaternions) +
                " non-unit rotation key(s) normalized");
      cleanClips_.push_back(std::move(c));
    }
    return ok_;
  }

  // ---- nodes

  // One node per joint, same index; the root space as a parent node when it is
  // not the identity. Mesh nodes come after.
  void writeNodes() {
    const std::size_t n = skeleton_.jointCount();
    std::vector<Json> children(n, Json::array());
    Json roots = Json::array();
    for (std::size_t j = 0; j < n; ++j) {
      if (skeleton_.parents[j] < 0)
        roots.push_back(j);
      else
        children[static_cast<std::size_t>(skeleton_.parents[j])].push_back(j);
    }
    for (std::size_t j = 0; j < n; ++j) {
      const Transform& t = skeleton_.restPose[j];
      Json node = {{"name", skeleton_.names[j]}};
      if (t.translation != glm::vec3(0.0f)) node["translation"] = vec3Json(t.translation);
      const glm::quat q = safeNormalize(t.rotation);
      if (q != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) node["rotation"] = quatJson(q);
      if (t.scale != glm::vec3(1.0f)) node["scale"] = vec3Json(t.scale);
      if (!children[j].empty()) node["children"] = children[j];
      nodes_.push_back(std::move(node));
    }
    if (n == 0) return;
    if (maxDifference(skeleton_.rootTransform, glm::mat4(1.0f)) < 1e-7f) {
      for (const Json& r : roots) sceneNodes_.push_back(r);
      return;
    }
    nodes_.push_back(rootSpaceNode(std::move(roots)));
    sceneNodes_.push_back(nodes_.size() - 1);
  }

  Json rootSpaceNode(Json roots) {
    const glm::mat4& m = skeleton_.rootTransform;
    Json node = {{"name", "skeleton_space"}, {"children", std::move(roots)}};
    const Transform t = decompose(m);
    float size = 1.0f;
    for (int c = 0; c < 3; ++c) size = std::max(size, glm::length(glm::vec3(m[c])));
    if (maxDifference(t.matrix(), m) <= 1e-5f * size) {
      node["translation"] = vec3Json(t.translation);
      node["rotation"] = quatJson(t.rotation);
      node["scale"] = vec3Json(t.scale);
      return node;
    }
    warning("the skeleton's root transform has shear or projection and cannot be written as translation, rotation "
            "and scale; it is written as a matrix, which glTF validators report as not decomposable");
    Json mat = Json::array();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) mat.push_back(m[c][r]);
    node["matrix"] = std::move(mat);
    return node;
  }

  // A skin over every joint (skin joint k = skeleton joint k), so that a reader
  // that builds its skeleton from the skin (ours does) gets every joint back,
  // also leaf joints no vertex uses, and the root space above them.
  void writeSkin() {
    const std::size_t n = skeleton_.jointCount();
    if (n == 0) return;
    const std::vector<glm::mat4> rest = skeleton_.restModelMatrices();
    std::vector<glm::mat4> ibm(n);
    std::size_t projective = 0;
    for (std::size_t j = 0; j < n; ++j) {
      glm::mat4 m = skeleton_.inverseBind[j];
      // A joint no mesh is bound to has no real bind matrix; its rest pose is the
      // bind pose a viewer would show.
      if (!skeleton_.skinned[j]) {
        const glm::mat4 inv = glm::inverse(rest[j]);
        m = isFinite(inv) ? inv : glm::mat4(1.0f);
      }
      // glTF requires the last row to be exactly 0 0 0 1; float noise is cleaned.
      if (std::fabs(m[0][3]) + std::fabs(m[1][3]) + std::fabs(m[2][3]) + std::fabs(m[3][3] - 1.0f) > 1e-4f)
        ++projective;
      m[0][3] = m[1][3] = m[2][3] = 0.0f;
      m[3][3] = 1.0f;
      ibm[j] = m;
    }
    if (projective > 0)
      warning(std::to_string(projective) +
              " inverse bind matrices had a last row other than 0 0 0 1; it was replaced by 0 0 0 1");
    const int accessor =
        buffer_.floats(reinterpret_cast<const float*>(ibm.data()), ibm.size(), 16, "MAT4", 0, false);
    Json joints = Json::array();
    for (std::size_t j = 0; j < n; ++j) joints.push_back(j);
    Json skin = {{"name", "skeleton"}, {"joints", std::move(joints)}, {"inverseBindMatrices", accessor}};
    if (sceneNodes_.size() == 1) skin["skeleton"] = sceneNodes_[0];
    doc_["skins"] = Json::array({std::move(skin)});
    skin_ = 0;
  }

  // ---- materials and images

  // Materials whose texture some primitive cannot use (no TEXCOORD_0): the
  // validator rejects a textured material on such a primitive.
  std::vector<char> materialsWithoutUvUse() const {
    std::vector<char> bad(asset_.materials.size(), 0);
    for (const Mesh& mesh : asset_.meshes)
      for (const MeshPrimitive& p : mesh.primitives)
        if (p.material >= 0 && static_cast<std::size_t>(p.material) < bad.size() &&
            p.uvs.size() != p.positions.size())
          bad[static_cast<std::size_t>(p.material)] = 1;
    return bad;
  }

  std::optional<ImageBytes> embeddedImage(const Material& m) {
    const std::vector<unsigned char>* image = images_.find(EmbeddedImages::indexOf(m.baseColorTexture));
    if (!image) {
      warning("material '" + m.name + "': texture '" + m.baseColorTexture + "' is inside " +
              (asset_.sourcePath.empty() ? std::string("the source file") : "'" + asset_.sourcePath + "'") +
              " and its bytes cannot be read from there; the texture is dropped");
      return std::nullopt;
    }
    ImageBytes out{*image, imageMimeType(*image)};
    if (out.mimeType.empty()) {
      warning("material '" + m.name + "': texture '" + m.baseColorTexture +
              "' is neither PNG nor JPEG (what glTF allows); the texture is dropped");
      return std::nullopt;
    }
    return out;
  }

  std::optional<ImageBytes> fileImage(const Material& m) {
    auto bytes = readBytes(m.baseColorTexture);
    if (!bytes) {
      warning("material '" + m.name + "': texture file '" + m.baseColorTexture +
              "' cannot be read; the texture is dropped");
      return std::nullopt;
    }
    ImageBytes out{std::move(*bytes), {}};
    out.mimeType = imageMimeType(out.bytes);
    if (out.mimeType.empty()) {
      warning("material '" + m.name + "': texture file '" + m.baseColorTexture +
              "' is neither PNG nor JPEG (what glTF allows); the texture is dropped");
      return std::nullopt;
    }
    return out;
  }

  // The glTF image for a material's texture, shared by materials using the same
  // one; -1 when dropped.
  int image(const Material& m, Json& images, std::map<std::string, int>& known) {
    if (auto it = known.find(m.baseColorTexture); it != known.end()) return it->second;
    const bool embedded = m.baseColorTexture.rfind("embedded:", 0) == 0;
    std::optional<ImageBytes> bytes = embedded ? embeddedImage(m) : fileImage(m);
    int index = -1;
    if (bytes) {
      Json img = {{"mimeType", bytes->mimeType}};
      if (embedded || options_.embedTextures) {
        img["bufferView"] = buffer_.view(bytes->bytes.data(), bytes->bytes.size(), 0);
      } else {
        const fs::path dir = fs::absolute(fs::path(path_)).parent_path();
        img["uri"] = uriEncoded(fs::absolute(m.baseColorTexture).lexically_relative(dir).generic_string());
        img.erase("mimeType");
      }
      images.push_back(std::move(img));
      index = static_cast<int>(images.size()) - 1;
    }
    known[m.baseColorTexture] = index;
    return index;
  }

  void writeMaterials() {
    if (asset_.materials.empty()) return;
    const std::vector<char> noUvs = materialsWithoutUvUse();
    Json materials = Json::array(), images = Json::array(), textures = Json::array();
    std::map<std::string, int> known;
    for (std::size_t i = 0; i < asset_.materials.size(); ++i) {
      const Material& m = asset_.materials[i];
      glm::vec4 color = m.baseColor;
      if (!isFinite(color)) {
        warning("material '" + m.name + "': base colour is not finite; white is written");
        color = glm::vec4(1.0f);
      }
      const glm::vec4 clamped = glm::clamp(color, 0.0f, 1.0f);
      if (clamped != color) warning("material '" + m.name + "': base colour clamped to [0, 1] as glTF requires");
      // Material has no metallic value; a dielectric is the neutral choice (glTF's default is metal).
      Json pbr = {{"baseColorFactor", {clamped.r, clamped.g, clamped.b, clamped.a}}, {"metallicFactor", 0.0}};
      if (!m.baseColorTexture.empty()) {
        if (noUvs[i]) {
          warning("material '" + m.name + "': texture dropped, a primitive using it has no texture coordinates");
        } else if (const int img = image(m, images, known); img >= 0) {
          textures.push_back({{"source", img}});
          pbr["baseColorTexture"] = {{"index", textures.size() - 1}};
        }
      }
      Json mat = {{"pbrMetallicRoughness", std::move(pbr)}};
      if (!m.name.empty()) mat["name"] = m.name;
      materials.push_back(std::move(mat));
    }
    doc_["materials"] = std::move(materials);
    if (!images.empty()) doc_["images"] = std::move(images);
    if (!textures.empty()) doc_["textures"] = std::move(textures);
  }

  // ---- meshes

  // Unit normals; zero or non-finite ones get the area-weighted normal of the
  // triangles around the vertex (or +Y for an isolated vertex). Returns how many.
  static std::size_t repairNormals(const MeshPrimitive& p, std::vector<glm::vec3>& normals) {
    std::vector<std::size_t> broken;
    for (std::size_t v = 0; v < normals.size(); ++v) {
      const float len = glm::length(normals[v]);
      if (len > 1e-12f && std::isfinite(len))
        normals[v] /= len;
      else
        broken.push_back(v);
    }
    if (broken.empty()) return 0;
    std::vector<glm::vec3> face(normals.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
      const std::uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
      const glm::vec3 n = glm::cross(p.positions[b] - p.positions[a], p.positions[c] - p.positions[a]);
      face[a] += n, face[b] += n, face[c] += n;
    }
    for (std::size_t v : broken) {
      const float len = glm::length(face[v]);
      normals[v] = len > 1e-20f && std::isfinite(len) ? face[v] / len : glm::vec3(0, 1, 0);
    }
    return broken.size();
  }

  // Skin attributes for a skinned primitive: joints as skin indices (skin joint
  // k is skeleton joint k), weights renormalized to sum 1, a joint listed twice
  // merged, unused slots joint 0 weight 0. Returns how many vertices were repaired.
  std::size_t skinAttributes(const Mesh& mesh, const MeshPrimitive& p, std::vector<glm::u16vec4>& joints,
                             std::vector<glm::vec4>& weights) const {
    const std::size_t count = p.positions.size();
    const bool have = p.joints.size() == count && p.weights.size() == count;
    const auto fallback = static_cast<std::uint16_t>(mesh.joint >= 0 ? mesh.joint : 0);
    joints.assign(count, glm::u16vec4(0));
    weights.assign(count, glm::vec4(0.0f));
    std::size_t repaired = 0;
    for (std::size_t v = 0; v < count; ++v) {
      glm::u16vec4 j(0);
      glm::vec4 w(0.0f);
      int used = 0;
      for (int c = 0; have && c < 4; ++c) {
        const float wc = p.weights[v][c];
        if (!(wc > 0.0f) || !std::isfinite(wc) || p.joints[v][c] >= skeleton_.jointCount()) continue;
        int slot = 0;
        while (slot < used && j[slot] != p.joints[v][c]) ++slot;
        if (slot == used) j[used++] = p.joints[v][c];
        w[slot] += wc;
      }
      const float sum = w.x + w.y + w.z + w.w;
      if (!(sum > 0.0f)) {
        j = glm::u16vec4(fallback, 0, 0, 0);
        w = glm::vec4(1, 0, 0, 0);
        ++repaired;
      } else {
        w /= sum;
      }
      joints[v] = j;
      weights[v] = w;
    }
    return repaired;
  }

  struct PrimitiveIssues {
    std::size_t normals = 0, skin = 0;
    bool droppedUvs = false, droppedNormals = false;
  };

  bool primitiveData(const std::string& where, const MeshPrimitive& p) {
    const std::size_t count = p.positions.size();
    if (!allFinite(p.positions) || !allFinite(p.uvs) || !allFinite(p.weights)) {
      error(where + " has non-finite vertex data (positions, texture coordinates or weights)");
      return false;
    }
    for (const MorphTargetDelta& d : p.morphTargets)
      if (!allFinite(d.positions) || !allFinite(d.normals)) {
        error(where + " has a morph target with non-finite deltas");
        return false;
      }
    for (std::size_t i = 0; i < p.indices.size(); ++i)
      if (p.indices[i] >= count) {
        error(where + ": index " + std::to_string(p.indices[i]) + " (at position " + std::to_string(i) +
              ") is out of range; the primitive has " + std::to_string(count) + " vertices");
        return false;
      }
    return true;
  }

  std::optional<Json> primitive(const Mesh& mesh, std::size_t pi, bool skinned) {
    const MeshPrimitive& p = mesh.primitives[pi];
    const std::string where = "mesh '" + mesh.name + "' primitive " + std::to_string(pi);
    const std::size_t count = p.positions.size();
    if (count == 0 || p.indices.empty() || p.indices.size() % 3 != 0) {
      warning(where + " has no vertices or no whole triangles (" + std::to_string(p.indices.size()) +
              " indices); skipped");
      return std::nullopt;
    }
    if (!primitiveData(where, p)) return std::nullopt;
    Json attributes = {{"POSITION", buffer_.vec3s(p.positions, kArrayBuffer, true)}};
    if (p.normals.size() == count) {
      std::vector<glm::vec3> normals = p.normals;
      if (const std::size_t fixed = repairNormals(p, normals); fixed > 0)
        warning(where + ": " + std::to_string(fixed) + " zero or non-finite normal(s) replaced by face normals");
      attributes["NORMAL"] = buffer_.vec3s(normals, kArrayBuffer, false);
    } else if (!p.normals.empty()) {
      warning(where + " has " + std::to_string(p.normals.size()) + " normals for " + std::to_string(count) +
              " vertices; normals dropped");
    }
    if (p.uvs.size() == count)
      attributes["TEXCOORD_0"] =
          buffer_.floats(reinterpret_cast<const float*>(p.uvs.data()), count, 2, "VEC2", kArrayBuffer, false);
    else if (!p.uvs.empty())
      warning(where + " has " + std::to_string(p.uvs.size()) + " texture coordinates for " + std::to_string(count) +
              " vertices; dropped");
    if (skinned) {
      std::vector<glm::u16vec4> joints;
      std::vector<glm::vec4> weights;
      if (const std::size_t repaired = skinAttributes(mesh, p, joints, weights); repaired > 0)
        warning(where + ": " + std::to_string(repaired) +
                " vertices without usable skin weights bound to one joint with weight 1");
      attributes["JOINTS_0"] = buffer_.joints(joints);
      attributes["WEIGHTS_0"] =
          buffer_.floats(reinterpret_cast<const float*>(weights.data()), count, 4, "VEC4", kArrayBuffer, false);
    }
    const std::uint32_t maxIndex = *std::max_element(p.indices.begin(), p.indices.end());
    Json out = {{"attributes", std::move(attributes)}, {"indices", buffer_.indices(p.indices, maxIndex)}, {"mode", 4}};
    if (p.material >= 0 && static_cast<std::size_t>(p.material) < asset_.materials.size())
      out["material"] = p.material;
    if (!mesh.morphTargets.empty()) out["targets"] = morphTargets(where, mesh, p);
    return out;
  }

  // One target per entry of Mesh::morphTargets, in that order, on every
  // primitive (glTF requires the same count); a target without deltas in this
  // primitive is written as zero offsets.
  Json morphTargets(const std::string& where, const Mesh& mesh, const MeshPrimitive& p) {
    const std::size_t count = p.positions.size();
    Json targets = Json::array();
    std::size_t misfit = 0;
    for (std::size_t k = 0; k < mesh.morphTargets.size(); ++k) {
      const MorphTargetDelta* d = k < p.morphTargets.size() ? &p.morphTargets[k] : nullptr;
      Json t = Json::object();
      if (d && d->positions.size() == count) {
        t["POSITION"] = buffer_.vec3s(d->positions, kArrayBuffer, true);
      } else {
        misfit += d && !d->positions.empty() ? 1 : 0;
        t["POSITION"] = buffer_.vec3s(std::vector<glm::vec3>(count, glm::vec3(0.0f)), kArrayBuffer, true);
      }
      if (d && d->normals.size() == count) t["NORMAL"] = buffer_.vec3s(d->normals, kArrayBuffer, false);
      targets.push_back(std::move(t));
    }
    if (misfit > 0)
      warning(where + ": " + std::to_string(misfit) +
              " morph target(s) have a delta count other than the vertex count; written as zero offsets");
    return targets;
  }

  void writeMeshes() {
    Json meshes = Json::array();
    meshNode_.assign(asset_.meshes.size(), -1);
    for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
      const Mesh& mesh = asset_.meshes[m];
      const bool skinned = mesh.skinned && skin_ >= 0;
      if (mesh.skinned && !skinned)
        warning("mesh '" + mesh.name + "' is skinned but the skeleton has no joints; written unskinned");
      Json prims = Json::array();
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
        if (auto prim = primitive(mesh, p, skinned)) prims.push_back(std::move(*prim));
      if (!ok_) return;
      if (prims.empty()) {
        warning("mesh '" + mesh.name + "' has no primitive with triangles; not written");
        continue;
      }
      Json out = {{"primitives", std::move(prims)}};
      if (!mesh.name.empty()) out["name"] = mesh.name;
      if (!mesh.morphTargets.empty()) out["extras"] = {{"targetNames", morphNames(mesh)}};
      meshes.push_back(std::move(out));
      Json node = {{"name", mesh.name}, {"mesh", meshes.size() - 1}};
      if (skinned) node["skin"] = skin_;
      nodes_.push_back(std::move(node));
      const int index = static_cast<int>(nodes_.size()) - 1;
      meshNode_[m] = index;
      attachMeshNode(mesh, skinned, index);
    }
    if (!meshes.empty()) doc_["meshes"] = std::move(meshes);
  }

  // Skinned meshes sit at the scene root: glTF ignores their node's transform and
  // the validator warns about any parent. A rigid mesh follows its joint.
  void attachMeshNode(const Mesh& mesh, bool skinned, int index) {
    if (!skinned && mesh.joint >= 0 && static_cast<std::size_t>(mesh.joint) < skeleton_.jointCount()) {
      Json& parent = nodes_[static_cast<std::size_t>(mesh.joint)];
      if (!parent.contains("children")) parent["children"] = Json::array();
      parent["children"].push_back(index);
    } else {
      sceneNodes_.push_back(index);
    }
  }

  std::vector<std::string> morphNames(const Mesh& mesh) const {
    std::vector<std::string> names;
    for (int t : mesh.morphTargets)
      names.push_back(t >= 0 && static_cast<std::size_t>(t) < asset_.morphTargets.size()
                          ? asset_.morphTargets[static_cast<std::size_t>(t)]
                          : "morph_" + std::to_string(t));
    return names;
  }

  // ---- animations

  static const char* interpolationName(Interpolation i) {
    switch (i) {
      case Interpolation::Step:
        return "STEP";
      case Interpolation::CubicSpline:
        return "CUBICSPLINE";
      default:
        return "LINEAR";
    }
  }

  struct Channels {
    Json samplers = Json::array();
    Json channels = Json::array();
    void add(int node, const char* path, int input, int output, Interpolation interp) {
      samplers.push_back({{"input", input}, {"output", output}, {"interpolation", interpolationName(interp)}});
      channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", node}, {"path", path}}}});
    }
  };

  // A cubic spline needs two keys; a single key is written as STEP with its value.
  template <class T>
  static Track<T> writable(const Track<T>& t) {
    if (t.interpolation != Interpolation::CubicSpline || t.keyCount() != 1) return t;
    Track<T> out;
    out.interpolation = Interpolation::Step;
    out.times = t.times;
    out.values = {t.values[1]};
    return out;
  }

  void vec3Channel(Channels& ch, int node, const char* path, const Track<glm::vec3>& track) {
    if (track.empty()) return;
    const Track<glm::vec3> t = writable(track);
    ch.add(node, path, buffer_.scalars(t.times, true), buffer_.vec3s(t.values, 0, false), t.interpolation);
  }

  void rotationChannel(Channels& ch, int node, const Track<glm::quat>& track) {
    if (track.empty()) return;
    const Track<glm::quat> t = writable(track);
    std::vector<float> xyzw;
    xyzw.reserve(t.values.size() * 4);
    for (const glm::quat& q : t.values) xyzw.insert(xyzw.end(), {q.x, q.y, q.z, q.w});
    ch.add(node, "rotation", buffer_.scalars(t.times, true),
           buffer_.floats(xyzw.data(), t.values.size(), 4, "VEC4", 0, false), t.interpolation);
  }

  // Morph weights: a glTF weights channel drives one node's mesh and lists a
  // weight for each of that mesh's targets. Each mesh with targets gets the
  // weights of the track(s) covering them; targets no track covers are 0.
  void morphChannels(Channels& ch, const Clip& clip) {
    std::vector<char> used(clip.morphTracks.size(), 0);
    for (std::size_t m = 0; m < asset_.meshes.size(); ++m) {
      const Mesh& mesh = asset_.meshes[m];
      if (meshNode_[m] < 0 || mesh.morphTargets.empty()) continue;
      std::vector<std::size_t> covering;
      for (std::size_t k = 0; k < clip.morphTracks.size(); ++k)
        for (int t : clip.morphTracks[k].targets)
          if (std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), t) != mesh.morphTargets.end()) {
            covering.push_back(k);
            break;
          }
      if (covering.empty()) continue;
      // Several tracks on one mesh merge when they share their keys; otherwise the first wins.
      const MorphTrack& first = clip.morphTracks[covering[0]];
      std::vector<std::size_t> merged;
      for (std::size_t k : covering) {
        used[k] = 1;
        const MorphTrack& t = clip.morphTracks[k];
        if (t.times == first.times && t.interpolation == first.interpolation)
          merged.push_back(k);
        else
          warning("clip '" + clip.name + "': mesh '" + mesh.name +
                  "' is driven by morph-weight tracks with different key times; only the first is written for it");
      }
      const std::size_t per = first.interpolation == Interpolation::CubicSpline ? 3 : 1;
      const std::size_t targets = mesh.morphTargets.size();
      std::vector<float> out(first.times.size() * per * targets, 0.0f);
      for (std::size_t k : merged) {
        const MorphTrack& t = clip.morphTracks[k];
        for (std::size_t s = 0; s < t.targets.size(); ++s) {
          auto it = std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), t.targets[s]);
          if (it == mesh.morphTargets.end()) continue;
          const auto slot = static_cast<std::size_t>(it - mesh.morphTargets.begin());
          // Values are key-major (and in/value/out-major within a cubic key), then target.
          for (std::size_t e = 0; e < first.times.size() * per; ++e)
            out[e * targets + slot] = t.weights[e * t.targets.size() + s];
        }
      }
      ch.add(meshNode_[m], "weights", buffer_.scalars(first.times, true), buffer_.scalars(out, false),
             first.interpolation);
    }
    const auto unused = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
    if (unused > 0)
      warning("clip '" + clip.name + "': " + std::to_string(unused) +
              " morph-weight track(s) drive no written mesh; dropped");
  }

  void writeAnimations() {
    Json animations = Json::array();
    for (const Clip& clip : cleanClips_) {
      Channels ch;
      for (const JointTrack& jt : clip.tracks) {
        vec3Channel(ch, jt.joint, "translation", jt.translation);
        rotationChannel(ch, jt.joint, jt.rotation);
        vec3Channel(ch, jt.joint, "scale", jt.scale);
      }
      morphChannels(ch, clip);
      if (ch.channels.empty()) {
        warning("clip '" + clip.name + "' has no keys; not written (a glTF animation needs a channel)");
        continue;
      }
      animations.push_back({{"name", clip.name}, {"samplers", std::move(ch.samplers)}, {"channels", std::move(ch.channels)}});
    }
    if (!animations.empty()) doc_["animations"] = std::move(animations);
  }

  // ---- output

  std::string binPath() const { return fs::path(path_).replace_extension(".bin").string(); }

  void finishDocument() {
    if (!nodes_.empty()) {
      doc_["nodes"] = std::move(nodes_);
      doc_["scenes"] = Json::array({{{"nodes", std::move(sceneNodes_)}}});
      doc_["scene"] = 0;
    }
    if (buffer_.bytes.empty()) return;
    buffer_.bytes.resize((buffer_.bytes.size() + 3) & ~std::size_t{3}, 0);
    Json buffer = {{"byteLength", buffer_.bytes.size()}};
    if (!binary_) buffer["uri"] = uriEncoded(fs::path(binPath()).filename().string());
    doc_["buffers"] = Json::array({std::move(buffer)});
    doc_["bufferViews"] = std::move(buffer_.views);
    doc_["accessors"] = std::move(buffer_.accessors);
  }

  void save() {
    // Names from other formats may hold invalid UTF-8; JSON must not.
    const std::string json = doc_.dump(binary_ ? -1 : 1, ' ', false, Json::error_handler_t::replace);
    if (binary_) {
      if (buffer_.bytes.size() + json.size() > 0xFFFFFF00ull) {
        error("the GLB would be larger than 4 GB, which the container cannot address");
        return;
      }
      detail::writeFileReplacing(path_, glbContainer(json, std::move(buffer_.bytes)), "a .glb file path", diag_);
      return;
    }
    const std::string_view bin(reinterpret_cast<const char*>(buffer_.bytes.data()), buffer_.bytes.size());
    if (!bin.empty() && !detail::writeFileReplacing(binPath(), bin, "a .bin file path", diag_)) return;
    detail::writeFileReplacing(path_, json, "a .gltf file path", diag_);
  }
};

}  // namespace

Diagnostics writeGltf(const std::string& path, const Asset& character, std::span<const Clip> clips,
                      const GltfWriteOptions& options) {
  Diagnostics diag;
  try {
    Writer(path, character, clips, options, diag).run();
  } catch (const std::bad_alloc&) {
    diag.error(path, "out of memory while writing glTF");
  } catch (const std::exception& e) {
    diag.error(path, std::string("unexpected failure while writing glTF: ") + e.what());
  } catch (...) {
    diag.error(path, "unexpected failure while writing glTF");
  }
  return diag;
}

}  // namespace marionette
