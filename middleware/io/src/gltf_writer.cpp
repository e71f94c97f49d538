// glTF 2.0 / GLB writer (see marionette/io/gltf_writer.hpp and docs/gltf-export.md).
//
// Stages: check the inputs (skeleton, clips cleaned then Clip::validate, finite
// data); lay out nodes (joints, the root space, mesh nodes), the skin, materials
// and images, meshes and animations into one JSON document and one binary
// buffer; only then write the file(s), so an error leaves nothing half written.
// The JSON is written with nlohmann::json directly rather than through
// tinygltf's writer: we need exact control over accessor types, min/max and
// image bytes, which is what the validator checks.
//
// This file: the entry point, the skeleton's check, nodes and skin, the document
// and the files. Materials, meshes and animations are written by their own files
// (gltf_writer_materials.cpp, gltf_writer_mesh.cpp, gltf_writer_animation.cpp), all
// stages of the one Writer (gltf_writer_context.hpp).
#include "marionette/io/gltf_writer.hpp"

#include "marionette/core/finite.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "file_extension.hpp"
#include "file_write.hpp"
#include "gltf_skeleton.hpp"
#include "gltf_writer_context.hpp"

namespace marionette::gltf_writer_detail {
namespace {

namespace fs = std::filesystem;
using gltf_detail::maxDifference;

// glTF stores quaternions as x, y, z, w.
Json quatJson(const glm::quat& q) { return Json::array({q.x, q.y, q.z, q.w}); }
Json vec3Json(const glm::vec3& v) { return Json::array({v.x, v.y, v.z}); }

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

}  // namespace

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

void Writer::run() {
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

bool Writer::checkSkeleton() {
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

// ---- nodes

// One node per joint, same index; the root space as a parent node when it is
// not the identity or there are several roots. Mesh nodes come after.
void Writer::writeNodes() {
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
  // Several root joints (a file of separate rigid nodes) get the root space above them even
  // where it is the identity: a skin's joints need a common root (the Khronos validator's
  // SKIN_NO_COMMON_ROOT).
  if (roots.size() == 1 && maxDifference(skeleton_.rootTransform, glm::mat4(1.0f)) < 1e-7f) {
    for (const Json& r : roots) sceneNodes_.push_back(r);
    return;
  }
  nodes_.push_back(rootSpaceNode(std::move(roots)));
  sceneNodes_.push_back(nodes_.size() - 1);
}

Json Writer::rootSpaceNode(Json roots) {
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
void Writer::writeSkin() {
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

// ---- output

std::string Writer::binPath() const { return fs::path(path_).replace_extension(".bin").string(); }

void Writer::finishDocument() {
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

void Writer::save() {
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

}  // namespace marionette::gltf_writer_detail

namespace marionette {

Diagnostics writeGltf(const std::string& path, const Asset& character, std::span<const Clip> clips,
                      const GltfWriteOptions& options) {
  Diagnostics diag;
  try {
    gltf_writer_detail::Writer(path, character, clips, options, diag).run();
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
