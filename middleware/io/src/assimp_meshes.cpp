// Assimp importer: materials and meshes. One Mesh per node that carries
// meshes, a primitive per aiMesh: vertices, triangles, skin weights (four per
// vertex) and morph targets; base colours and texture paths for materials.
#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "assimp_conversion.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/core/limits.hpp"
#include "marionette/core/text.hpp"
#include "model_folder.hpp"

namespace marionette::assimp_detail {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- materials

std::string texturePath(Importing& im, const std::string& raw) {
  if (raw.empty()) return {};
  const auto [texture, index] = im.scene.GetEmbeddedTextureAndIndex(raw.c_str());
  if (texture) {
    // Compressed (mHeight 0): the file's bytes, kept for a writer or renderer. Raw texels are
    // not encoded here.
    if (texture->mHeight != 0 || !texture->pcData || index < 0) {
      im.warning("texture '" + raw + "' is stored as raw texels, which are not kept; the texture is dropped");
      return {};
    }
    auto& images = im.asset.embeddedImages;
    if (images.size() <= static_cast<std::size_t>(index)) images.resize(static_cast<std::size_t>(index) + 1);
    if (images[static_cast<std::size_t>(index)].empty()) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(texture->pcData);
      images[static_cast<std::size_t>(index)].assign(bytes, bytes + texture->mWidth);
    }
    return "embedded:" + std::to_string(index);
  }
  if (raw[0] == '*') {
    im.warning("texture '" + raw + "' refers to an embedded texture the file does not have");
    return {};
  }
  std::string portable = raw;
  std::replace(portable.begin(), portable.end(), '\\', '/');
  const fs::path written = fs::path(portable).lexically_normal();
  const fs::path folder = fs::path(im.path).parent_path();
  // Exporters often store the absolute path on the artist's machine ("D:/art/x.png"),
  // which is not absolute here; the texture then usually sits beside the asset.
  const bool windowsAbsolute = portable.size() > 2 && std::isalpha(static_cast<unsigned char>(portable[0])) &&
                               portable[1] == ':' && portable[2] == '/';
  const bool anywhere = im.options.allowFilesOutsideModelFolder;
  auto outside = [&] {
    im.warning("texture '" + raw +
               "' is outside the model's folder: no texture (ImportOptions::allowFilesOutsideModelFolder allows it)");
    return std::string();
  };
  if (!written.is_absolute() && !windowsAbsolute) {
    const fs::path file = (folder / written).lexically_normal();
    return anywhere || io_detail::insideFolder(file, folder) ? file.string() : outside();
  }
  std::error_code ec;
  const bool allowed = anywhere || io_detail::insideFolder(written, folder);
  if (allowed && !windowsAbsolute && fs::exists(written, ec)) return written.string();
  const fs::path beside = folder / written.filename();
  if (fs::exists(beside, ec)) return beside.string();
  return allowed ? written.string() : outside();
}

void convertMaterials(Importing& im) {
  for (unsigned i = 0; i < im.scene.mNumMaterials; ++i) {
    const aiMaterial& source = *im.scene.mMaterials[i];
    Material material;
    aiString name;
    if (source.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) material.name = str(name);
    aiColor4D color(1.0f, 1.0f, 1.0f, 1.0f);
    if (source.Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
        source.Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) {
      material.baseColor = {color.r, color.g, color.b, color.a};
      float opacity = 1.0f;
      if (source.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) material.baseColor.a *= opacity;
    }
    if (!isFinite(material.baseColor)) {
      im.error("material '" + material.name + "' has a non-finite colour");
      return;
    }
    aiString texture;
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      if (source.GetTextureCount(type) > 0 && source.GetTexture(type, 0, &texture) == AI_SUCCESS) {
        material.baseColorTexture = texturePath(im, str(texture));
        break;
      }
    }
    im.asset.materials.push_back(std::move(material));
  }
}

// ---------------------------------------------------------------- meshes

bool readVertices(Importing& im, const aiMesh& mesh, const std::string& where, MeshPrimitive& p) {
  const unsigned n = mesh.mNumVertices;
  p.positions.resize(n);
  for (unsigned v = 0; v < n; ++v) {
    p.positions[v] = toGlm(mesh.mVertices[v]) * im.scale;
    if (!isFinite(p.positions[v])) {
      im.error(where + ": vertex " + std::to_string(v) + " has a non-finite position");
      return false;
    }
  }
  if (mesh.HasNormals()) {
    // Assimp writes NaN normals for degenerate triangles it had to generate normals
    // for; such a vertex gets an arbitrary unit normal rather than failing the file.
    std::size_t replaced = 0;
    p.normals.resize(n);
    for (unsigned v = 0; v < n; ++v) {
      p.normals[v] = toGlm(mesh.mNormals[v]);
      if (!isFinite(p.normals[v])) {
        p.normals[v] = {0.0f, 1.0f, 0.0f};
        ++replaced;
      }
    }
    if (replaced) im.warning(where + ": " + std::to_string(replaced) + " non-finite normals replaced by +Y");
  }
  if (mesh.HasTextureCoords(0)) {
    p.uvs.resize(n);
    for (unsigned v = 0; v < n; ++v) {
      // Assimp puts the texture origin bottom-left; glTF (and Marionette's assets)
      // top-left.
      p.uvs[v] = {mesh.mTextureCoords[0][v].x, 1.0f - mesh.mTextureCoords[0][v].y};
      if (!isFinite(p.uvs[v])) {
        im.error(where + ": vertex " + std::to_string(v) + " has a non-finite texture coordinate");
        return false;
      }
    }
  }
  return true;
}

bool readTriangles(Importing& im, const aiMesh& mesh, const std::string& where, MeshPrimitive& p) {
  std::size_t skipped = 0;
  p.indices.reserve(std::size_t{mesh.mNumFaces} * 3);
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) {  // points and lines survive triangulation
      ++skipped;
      continue;
    }
    for (unsigned k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= mesh.mNumVertices) {
        im.error(where + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(face.mIndices[k]) +
                 " of " + std::to_string(mesh.mNumVertices));
        return false;
      }
      p.indices.push_back(face.mIndices[k]);
    }
  }
  if (skipped)
    im.warning(where + ": " + std::to_string(skipped) + " point / line faces skipped (only triangles are kept)");
  return true;
}

struct Influences {
  std::array<int, 4> joint{};
  std::array<float, 4> weight{};
  void add(int j, float w) {
    auto smallest = std::min_element(weight.begin(), weight.end());
    if (w <= *smallest) return;
    joint[static_cast<std::size_t>(smallest - weight.begin())] = j;
    *smallest = w;
  }
};

bool readSkin(Importing& im, const aiMesh& mesh, int nodeJoint, const std::string& where, MeshPrimitive& p) {
  std::vector<Influences> influences(mesh.mNumVertices);
  std::vector<std::string> unbound;
  for (unsigned b = 0; b < mesh.mNumBones; ++b) {
    const aiBone& bone = *mesh.mBones[b];
    auto it = im.jointOfName.find(str(bone.mName));
    if (it == im.jointOfName.end()) {
      unbound.push_back(str(bone.mName));
      continue;
    }
    for (unsigned w = 0; w < bone.mNumWeights; ++w) {
      const aiVertexWeight& vw = bone.mWeights[w];
      if (vw.mVertexId >= mesh.mNumVertices || !isFinite(vw.mWeight)) {
        im.error(where + ": bone '" + it->first + "' has an invalid weight (vertex " + std::to_string(vw.mVertexId) +
                 ", weight " + std::to_string(vw.mWeight) + ")");
        return false;
      }
      if (vw.mWeight > 0.0f) influences[vw.mVertexId].add(it->second, vw.mWeight);
    }
  }
  if (!unbound.empty())
    im.warning(where + ": bones " + quotedNameList(unbound) + " match no node; their weights were dropped");
  p.joints.resize(mesh.mNumVertices);
  p.weights.resize(mesh.mNumVertices);
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    Influences& in = influences[v];
    float sum = in.weight[0] + in.weight[1] + in.weight[2] + in.weight[3];
    if (!(sum > 0.0f)) {  // unweighted: follows the mesh's own node
      in = Influences{};
      in.joint[0] = nodeJoint;
      in.weight[0] = sum = 1.0f;
    }
    p.joints[v] = glm::u16vec4(in.joint[0], in.joint[1], in.joint[2], in.joint[3]);
    p.weights[v] = glm::vec4(in.weight[0], in.weight[1], in.weight[2], in.weight[3]) / sum;
  }
  return true;
}

int internMorphTarget(Asset& asset, Mesh& mesh, const std::string& name) {
  auto global = std::find(asset.morphTargets.begin(), asset.morphTargets.end(), name);
  const int index = static_cast<int>(global - asset.morphTargets.begin());
  if (global == asset.morphTargets.end()) asset.morphTargets.push_back(name);
  auto local = std::find(mesh.morphTargets.begin(), mesh.morphTargets.end(), index);
  if (local == mesh.morphTargets.end()) {
    mesh.morphTargets.push_back(index);
    return static_cast<int>(mesh.morphTargets.size()) - 1;
  }
  return static_cast<int>(local - mesh.morphTargets.begin());
}

void readMorphTargets(Importing& im, const aiMesh& source, const std::string& where, Mesh& mesh, MeshPrimitive& p) {
  for (unsigned k = 0; k < source.mNumAnimMeshes; ++k) {
    const aiAnimMesh& target = *source.mAnimMeshes[k];
    if (target.mNumVertices != source.mNumVertices) {
      im.warning(where + ": morph target " + std::to_string(k) + " has a different vertex count; skipped");
      continue;
    }
    std::string name = str(target.mName);
    if (name.empty()) name = str(source.mName) + "_morph_" + std::to_string(k);
    const std::size_t slot = static_cast<std::size_t>(internMorphTarget(im.asset, mesh, name));
    if (p.morphTargets.size() <= slot) p.morphTargets.resize(slot + 1);
    MorphTargetDelta& delta = p.morphTargets[slot];
    delta = {};
    for (unsigned v = 0; target.mVertices && v < source.mNumVertices; ++v)
      delta.positions.push_back((toGlm(target.mVertices[v]) - toGlm(source.mVertices[v])) * im.scale);
    for (unsigned v = 0; target.mNormals && source.mNormals && v < source.mNumVertices; ++v)
      delta.normals.push_back(toGlm(target.mNormals[v]) - toGlm(source.mNormals[v]));
    const bool ok = std::all_of(delta.positions.begin(), delta.positions.end(), [](auto d) { return isFinite(d); }) &&
                    std::all_of(delta.normals.begin(), delta.normals.end(), [](auto d) { return isFinite(d); });
    if (!ok) im.error(where + ": morph target '" + name + "' has non-finite values");
  }
}

bool convertPrimitive(Importing& im, const aiMesh& source, bool skinned, int nodeJoint, Mesh& mesh) {
  const std::string where = "mesh '" + mesh.name + "' (" + (source.mName.length ? str(source.mName) : "unnamed") + ")";
  MeshPrimitive p;
  if (!readVertices(im, source, where, p) || !readTriangles(im, source, where, p)) return false;
  if (p.indices.empty()) {
    im.warning(where + ": no triangles; skipped");
    return true;
  }
  if (skinned && !readSkin(im, source, nodeJoint, where, p)) return false;
  readMorphTargets(im, source, where, mesh, p);
  p.material = source.mMaterialIndex < im.asset.materials.size() ? static_cast<int>(source.mMaterialIndex) : -1;
  mesh.primitives.push_back(std::move(p));
  return true;
}

// Vertices stay in the mesh's own space: a node transform on an unskinned mesh is
// not applied (the skeleton has the node; a renderer can attach the mesh to it).
bool convertNodeMeshes(Importing& im, const aiNode& node) {
  Mesh mesh;
  mesh.name = str(node.mName);
  if (mesh.name.empty() && node.mMeshes[0] < im.scene.mNumMeshes)
    mesh.name = str(im.scene.mMeshes[node.mMeshes[0]]->mName);
  if (mesh.name.empty()) mesh.name = "mesh_" + std::to_string(im.asset.meshes.size());
  for (unsigned i = 0; i < node.mNumMeshes; ++i)
    if (node.mMeshes[i] < im.scene.mNumMeshes && im.scene.mMeshes[node.mMeshes[i]]->HasBones()) mesh.skinned = true;
  auto joint = im.jointOfNode.find(&node);
  const int nodeJoint = joint != im.jointOfNode.end() ? joint->second : 0;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    if (node.mMeshes[i] >= im.scene.mNumMeshes) {
      im.error("node '" + mesh.name + "' refers to mesh " + std::to_string(node.mMeshes[i]) + " of " +
               std::to_string(im.scene.mNumMeshes));
      return false;
    }
    if (!convertPrimitive(im, *im.scene.mMeshes[node.mMeshes[i]], mesh.skinned, nodeJoint, mesh)) return false;
  }
  // Every primitive lists the mesh's morph targets in the same order.
  for (MeshPrimitive& p : mesh.primitives) p.morphTargets.resize(mesh.morphTargets.size());
  if (!mesh.primitives.empty()) im.asset.meshes.push_back(std::move(mesh));
  return true;
}

bool convertMeshTree(Importing& im, const aiNode& node) {
  if (node.mNumMeshes > 0 && !convertNodeMeshes(im, node)) return false;
  for (unsigned i = 0; i < node.mNumChildren; ++i)
    if (!convertMeshTree(im, *node.mChildren[i])) return false;
  return true;
}

}  // namespace

void convertMeshes(Importing& im) {
  if (im.asset.skeleton.jointCount() > limits::kMaxJoints) {
    im.error("skeleton has " + std::to_string(im.asset.skeleton.jointCount()) +
             " joints, more than the 65535 a skeleton may have (limits::kMaxJoints)");
    return;
  }
  convertMaterials(im);
  convertMeshTree(im, *im.scene.mRootNode);
}

}  // namespace marionette::assimp_detail
