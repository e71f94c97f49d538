#include "marionette_ar/render/character_renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <map>

#include "marionette_ar/render/image.hpp"

namespace marionette::ar {
namespace {

// Interleaved vertex: position, normal, uv, joints (as floats), weights.
struct Vertex {
  float position[3], normal[3], uv[2], joints[4], weights[4];
};

constexpr int kMorphTextureWidth = 2048;
constexpr int kMaxActiveMorphs = 8;  // as character.vert

unsigned makeFloatTexture(int width, int height, const float* rgba) {
  unsigned t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, rgba);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

unsigned makeColorTexture(const Image8& image) {
  unsigned t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Row 0 (the image's top) at t = 0: glTF uvs have their origin at the top-left.
  glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               image.pixels.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  return t;
}

// Morph deltas of one primitive as two RGBA32F textures (texel = morph * V + vertex).
void uploadMorphs(const MeshPrimitive& p, unsigned& positions, unsigned& normals, int& width) {
  const std::size_t v = p.positions.size();
  const std::size_t texels = std::max<std::size_t>(1, v * p.morphTargets.size());
  width = static_cast<int>(std::min<std::size_t>(texels, kMorphTextureWidth));
  const std::size_t height = (texels + static_cast<std::size_t>(width) - 1) / static_cast<std::size_t>(width);
  std::vector<float> pos(static_cast<std::size_t>(width) * height * 4, 0.0f), nrm(pos.size(), 0.0f);
  for (std::size_t m = 0; m < p.morphTargets.size(); ++m) {
    const MorphTargetDelta& d = p.morphTargets[m];
    for (std::size_t i = 0; i < v; ++i) {
      const std::size_t t = (m * v + i) * 4;
      if (i < d.positions.size()) std::memcpy(&pos[t], &d.positions[i], sizeof(glm::vec3));
      if (i < d.normals.size()) std::memcpy(&nrm[t], &d.normals[i], sizeof(glm::vec3));
    }
  }
  positions = makeFloatTexture(width, static_cast<int>(height), pos.data());
  normals = makeFloatTexture(width, static_cast<int>(height), nrm.data());
}

}  // namespace

CharacterModel::~CharacterModel() {
  for (Primitive& p : primitives_) {
    glDeleteVertexArrays(1, &p.vao);
    glDeleteBuffers(1, &p.vertexBuffer);
    glDeleteBuffers(1, &p.indexBuffer);
    if (p.morphPositions) glDeleteTextures(1, &p.morphPositions);
    if (p.morphNormals) glDeleteTextures(1, &p.morphNormals);
  }
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
}

std::size_t CharacterModel::triangleCount() const noexcept {
  std::size_t n = 0;
  for (const Primitive& p : primitives_) n += static_cast<std::size_t>(p.indexCount) / 3;
  return n;
}

bool CharacterModel::upload(const Asset& asset, Diagnostics& diagnostics) {
  morphCount_ = asset.morphTargets.size();
  jointCount_ = asset.skeleton.jointCount();
  std::map<std::string, int> textureOf;  // texture reference -> textures_ index (-1: unreadable)
  auto texture = [&](const Material& m) -> int {
    if (m.baseColorTexture.empty()) return -1;
    if (auto it = textureOf.find(m.baseColorTexture); it != textureOf.end()) return it->second;
    Image8 image;
    Diagnostics unread;
    std::string why;
    bool ok = false;
    if (const int index = embeddedImageIndex(m.baseColorTexture); index >= 0) {
      const auto n = static_cast<std::size_t>(index);
      const bool have = n < asset.embeddedImages.size() && !asset.embeddedImages[n].empty();
      ok = have && readImage(asset.embeddedImages[n], asset.sourcePath + " image " + std::to_string(index), image, unread);
      if (!have) why = "the image is inside the file and the asset has no bytes for it (imported without meshes?)";
    } else {
      ok = readImage(m.baseColorTexture, image, unread);
    }
    for (const Diagnostic& d : unread.items) why += (why.empty() ? "" : "; ") + d.file + ": " + d.message;
    int slot = -1;
    if (ok) {
      slot = static_cast<int>(textures_.size());
      textures_.push_back(makeColorTexture(image));
    } else {  // still drawable, in the material's base colour
      diagnostics.warning(asset.sourcePath, "material '" + m.name + "': texture '" + m.baseColorTexture +
                                                "' not used: " + why);
    }
    textureOf[m.baseColorTexture] = slot;
    return slot;
  };

  std::size_t assetPrimitive = 0;
  for (const Mesh& mesh : asset.meshes) {
    for (const MeshPrimitive& p : mesh.primitives) {
      const std::size_t index = assetPrimitive++;
      const std::size_t n = p.positions.size();
      if (n == 0 || p.indices.empty()) continue;
      const bool skinned = mesh.skinned && p.joints.size() == n && p.weights.size() == n;
      std::vector<Vertex> vertices(n);
      for (std::size_t i = 0; i < n; ++i) {
        Vertex& v = vertices[i];
        std::memcpy(v.position, &p.positions[i], sizeof v.position);
        const glm::vec3 normal = i < p.normals.size() ? p.normals[i] : glm::vec3(0, 1, 0);
        std::memcpy(v.normal, &normal, sizeof v.normal);
        const glm::vec2 uv = i < p.uvs.size() ? p.uvs[i] : glm::vec2(0.0f);
        std::memcpy(v.uv, &uv, sizeof v.uv);
        for (int k = 0; k < 4; ++k) {
          v.joints[k] = skinned ? static_cast<float>(p.joints[i][k]) : 0.0f;
          v.weights[k] = skinned ? p.weights[i][k] : (k == 0 ? 1.0f : 0.0f);
        }
      }
      Primitive gp;
      gp.assetPrimitive = index;
      gp.vertexCount = static_cast<int>(n);
      gp.indexCount = static_cast<int>(p.indices.size());
      gp.skinned = skinned;
      gp.rigidJoint = skinned ? -1 : mesh.joint;
      if (p.material >= 0 && static_cast<std::size_t>(p.material) < asset.materials.size()) {
        const Material& m = asset.materials[static_cast<std::size_t>(p.material)];
        gp.baseColor = m.baseColor;
        if (p.uvs.size() == n) gp.texture = texture(m);
      }
      glGenVertexArrays(1, &gp.vao);
      glBindVertexArray(gp.vao);
      glGenBuffers(1, &gp.vertexBuffer);
      glBindBuffer(GL_ARRAY_BUFFER, gp.vertexBuffer);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(n * sizeof(Vertex)), vertices.data(), GL_STATIC_DRAW);
      const auto attrib = [](unsigned loc, int size, std::size_t offset) {
        glEnableVertexAttribArray(loc);
        glVertexAttribPointer(loc, size, GL_FLOAT, GL_FALSE, sizeof(Vertex), reinterpret_cast<const void*>(offset));
      };
      attrib(0, 3, offsetof(Vertex, position));
      attrib(1, 3, offsetof(Vertex, normal));
      attrib(2, 2, offsetof(Vertex, uv));
      attrib(3, 4, offsetof(Vertex, joints));
      attrib(4, 4, offsetof(Vertex, weights));
      glGenBuffers(1, &gp.indexBuffer);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gp.indexBuffer);
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(p.indices.size() * sizeof(std::uint32_t)),
                   p.indices.data(), GL_STATIC_DRAW);
      glBindVertexArray(0);
      if (!p.morphTargets.empty() && p.morphTargets.size() == mesh.morphTargets.size()) {
        gp.morphs = mesh.morphTargets;
        uploadMorphs(p, gp.morphPositions, gp.morphNormals, gp.morphTextureWidth);
      }
      primitives_.push_back(std::move(gp));
    }
  }
  if (primitives_.empty()) {
    diagnostics.error(asset.sourcePath, "no mesh to draw (the file has a skeleton and clips only)");
    return false;
  }
  return true;
}

CharacterPose::CharacterPose(const Skeleton& skeleton)
    : binding_(skeleton),
      palette_(skeleton.jointCount() * 12, 0.0f),
      model_(skeleton.jointCount(), glm::mat4(1.0f)),
      joints_(static_cast<int>(skeleton.jointCount())) {
  for (std::size_t j = 0; j < skeleton.jointCount(); ++j)  // identity until the first frame
    palette_[j * 12 + 0] = palette_[j * 12 + 5] = palette_[j * 12 + 10] = 1.0f;
  glGenTextures(1, &paletteTexture_);
  glBindTexture(GL_TEXTURE_2D, paletteTexture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 3, std::max(1, joints_), 0, GL_RGBA, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

CharacterPose::~CharacterPose() { glDeleteTextures(1, &paletteTexture_); }

void CharacterPose::update(const TransformBuffer& buffer) {
  binding_.copy(buffer, palette_, {bridge::PaletteLayout::Mat3x4RowMajor, /*inverseBind=*/true});
  const auto models = buffer.modelMatrices();
  std::copy_n(models.begin(), std::min(models.size(), model_.size()), model_.begin());
  const auto weights = buffer.morphWeights();
  morphWeights_.resize(weights.size());  // sized once: the morph count does not change
  std::copy(weights.begin(), weights.end(), morphWeights_.begin());
  upload();
}

void CharacterPose::setPalette(std::span<const glm::mat4> skinning, std::span<const glm::mat4> model) {
  for (std::size_t j = 0; j < skinning.size() && j < model_.size(); ++j) {
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) palette_[j * 12 + static_cast<std::size_t>(row * 4 + col)] = skinning[j][col][row];
    if (j < model.size()) model_[j] = model[j];
  }
  upload();
}

void CharacterPose::upload() {
  if (joints_ == 0) return;
  glBindTexture(GL_TEXTURE_2D, paletteTexture_);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 3, joints_, GL_RGBA, GL_FLOAT, palette_.data());
}

PrtIrradiance::PrtIrradiance(const CharacterModel& model, std::span<const std::size_t> primitiveVertexOffset,
                             std::size_t vertexCount)
    : slices_(model.primitives_.size()), vertices_(vertexCount) {
  for (std::size_t i = 0; i < model.primitives_.size(); ++i) {
    const CharacterModel::Primitive& p = model.primitives_[i];
    const std::size_t k = p.assetPrimitive;
    Slice& slice = slices_[i];
    if (k >= primitiveVertexOffset.size()) {
      ++mismatches_;
      continue;
    }
    const std::size_t first = primitiveVertexOffset[k];
    const std::size_t end = k + 1 < primitiveVertexOffset.size() ? primitiveVertexOffset[k + 1] : vertexCount;
    if (end < first || end > vertexCount || end - first != static_cast<std::size_t>(p.vertexCount)) {
      ++mismatches_;
      continue;
    }
    slice.first = first;
    slice.count = end - first;
    glGenBuffers(1, &slice.buffer);
    glBindBuffer(GL_ARRAY_BUFFER, slice.buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(slice.count * sizeof(glm::vec3)), nullptr, GL_DYNAMIC_DRAW);
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

PrtIrradiance::~PrtIrradiance() {
  for (Slice& s : slices_)
    if (s.buffer) glDeleteBuffers(1, &s.buffer);
}

void PrtIrradiance::upload(std::span<const glm::vec3> irradiance) noexcept {
  if (irradiance.size() != vertices_) return;
  for (const Slice& s : slices_) {
    if (!s.buffer) continue;
    glBindBuffer(GL_ARRAY_BUFFER, s.buffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(s.count * sizeof(glm::vec3)), irradiance.data() + s.first);
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void drawCharacter(const ShaderProgram& program, const CharacterModel& model, const CharacterPose& pose,
                   const glm::mat4& world, const glm::mat4& viewProjection, const Lighting& lighting,
                   const PrtIrradiance* prt, float opacity) {
  program.use();
  const float alpha = std::clamp(opacity, 0.0f, 1.0f);
  if (!(alpha > 0.0f)) return;
  program.set("uOpacity", alpha);
  program.set("uWorld", world);
  program.set("uViewProjection", viewProjection);
  program.set("uExposure", lighting.exposure);
  program.set("uOutputMode", lighting.outputMode);
  program.set("uCameraCurve", lighting.cameraCurve ? 1 : 0);
  glUniform3fv(program.location("uIrradianceSH"), 9, &lighting.irradianceSH[0].x);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, pose.paletteTexture_);
  program.set("uPalette", 0);
  program.set("uBaseColorTexture", 1);
  program.set("uMorphPositions", 2);
  program.set("uMorphNormals", 3);
  setOcclusionUniforms(program, lighting.occlusion, 4);
  // Every primitive once (twice when faded: depth, then colour).
  auto drawPrimitives = [&]() {
    const bool usePrt = prt && prt->slices_.size() == model.primitives_.size();
    for (std::size_t primitive = 0; primitive < model.primitives_.size(); ++primitive) {
      const CharacterModel::Primitive& p = model.primitives_[primitive];
      program.set("uSkinned", p.skinned ? 1 : 0);
      const bool rigid = p.rigidJoint >= 0 && static_cast<std::size_t>(p.rigidJoint) < pose.model_.size();
      program.set("uRigid", rigid ? pose.model_[static_cast<std::size_t>(p.rigidJoint)] : glm::mat4(1.0f));
      program.set("uBaseColor", p.baseColor);
      program.set("uHasTexture", p.texture >= 0 ? 1 : 0);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, p.texture >= 0 ? model.textures_[static_cast<std::size_t>(p.texture)] : 0);
      // The strongest morphs of this primitive (at most kMaxActiveMorphs).
      int indices[kMaxActiveMorphs] = {};
      float weights[kMaxActiveMorphs] = {};
      int active = 0;
      for (std::size_t local = 0; local < p.morphs.size(); ++local) {
        const auto global = static_cast<std::size_t>(p.morphs[local]);
        const float w = global < pose.morphWeights_.size() ? pose.morphWeights_[global] : 0.0f;
        if (!(std::abs(w) > 1e-4f)) continue;
        int slot = active < kMaxActiveMorphs ? active++ : -1;
        if (slot < 0) {  // full: replace the weakest if this one is stronger
          slot = static_cast<int>(std::min_element(weights, weights + kMaxActiveMorphs,
                                                   [](float a, float b) { return std::abs(a) < std::abs(b); }) - weights);
          if (std::abs(weights[slot]) >= std::abs(w)) continue;
        }
        indices[slot] = static_cast<int>(local);
        weights[slot] = w;
      }
      program.set("uActiveMorphs", active);
      glUniform1iv(program.location("uMorphIndex"), kMaxActiveMorphs, indices);
      glUniform1fv(program.location("uMorphWeight"), kMaxActiveMorphs, weights);
      program.set("uVertexCount", p.vertexCount);
      program.set("uMorphTextureWidth", p.morphTextureWidth);
      glActiveTexture(GL_TEXTURE2);
      glBindTexture(GL_TEXTURE_2D, p.morphPositions);
      glActiveTexture(GL_TEXTURE3);
      glBindTexture(GL_TEXTURE_2D, p.morphNormals);
      glBindVertexArray(p.vao);
      // Attribute 5 is this character's PRT irradiance (the VAO is shared by every character
      // of the asset, so the buffer is attached per draw); off: the per-fragment SH9 light.
      const unsigned prtBuffer = usePrt ? prt->slices_[primitive].buffer : 0u;
      program.set("uPrt", prtBuffer ? 1 : 0);
      if (prtBuffer) {
        glBindBuffer(GL_ARRAY_BUFFER, prtBuffer);
        glEnableVertexAttribArray(5);
        glVertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
      } else {
        glDisableVertexAttribArray(5);
      }
      glDrawElements(GL_TRIANGLES, p.indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0);
  };
  if (alpha >= 1.0f && !lighting.occlusion) {
    drawPrimitives();
    return;
  }
  // Faded (or partly hidden by the occlusion mask): the nearest surface's depth first, then its colour blended over the background.
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  drawPrimitives();
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthFunc(GL_LEQUAL);
  drawPrimitives();
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
}


}  // namespace marionette::ar
