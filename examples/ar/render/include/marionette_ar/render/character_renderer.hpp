// Draws characters from the middleware: GPU linear-blend skinning from the
// palette the bridge fills, every sub-mesh of a multi-mesh character, base-colour
// textures (OpenImageIO) and morph targets (visemes and expressions).
//
// CharacterModel is the GPU copy of one asset (shared by every character made
// from it); CharacterPose is one character's per-frame state (its palette
// texture and morph weights), filled from its TransformBuffer. PrtIrradiance is
// one character's per-vertex PRT irradiance (one dynamic vertex buffer per primitive),
// filled each frame from the CPU relighting (docs/ar-renderer.md, "PRT lighting").
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "marionette/bridge/palette_binding.hpp"
#include "marionette/asset/asset.hpp"
#include "marionette/scene/transform_buffer.hpp"
#include "marionette_ar/render/occlusion_mask_texture.hpp"
#include "marionette_ar/render/shader_program.hpp"

namespace marionette::ar {

// What the character shader needs besides the character.
struct Lighting {
  std::array<glm::vec3, 9> irradianceSH{};  // E(n) = sum c_i Y_i(n); all zero = unlit black
  float exposure = 1.0f;
  int outputMode = 0;  // 0 lit, 1 unlit base colour, 2 normals (tests)
  bool cameraCurve = false;  // the light is in a camera's linear values: its curve, not the tone map
  // Something real in front of the target (occlusion_mask_texture.hpp): what lies over it is
  // faded out (drawn blended, as a faded character). Null: nothing hides the character.
  const OcclusionDraw* occlusion = nullptr;
};

class CharacterModel {
 public:
  CharacterModel() = default;
  ~CharacterModel();
  CharacterModel(const CharacterModel&) = delete;
  CharacterModel& operator=(const CharacterModel&) = delete;

  // Uploads every mesh primitive, its morph deltas and its material's texture.
  // Problems that leave the character drawable (a texture that cannot be read)
  // are warnings in `diagnostics`, naming the asset, material and file; returns false
  // (with an error naming the asset) only when nothing can be drawn.
  bool upload(const Asset& asset, Diagnostics& diagnostics);
  [[nodiscard]] std::size_t primitiveCount() const noexcept { return primitives_.size(); }
  [[nodiscard]] std::size_t triangleCount() const noexcept;
  [[nodiscard]] std::size_t morphTargetCount() const noexcept { return morphCount_; }

 private:
  friend class CharacterPose;
  friend class PrtIrradiance;
  friend void drawCharacter(const ShaderProgram&, const CharacterModel&, const class CharacterPose&, const glm::mat4&,
                            const glm::mat4&, const Lighting&, const class PrtIrradiance*, float);
  struct Primitive {
    std::size_t assetPrimitive = 0;  // index over the asset's primitives, mesh-major, primitive-minor
    unsigned vao = 0, vertexBuffer = 0, indexBuffer = 0;
    int indexCount = 0, vertexCount = 0;
    bool skinned = true;
    int rigidJoint = -1;  // unskinned mesh attached to a joint
    glm::vec4 baseColor{1.0f};
    int texture = -1;     // into textures_
    unsigned morphPositions = 0, morphNormals = 0;
    int morphTextureWidth = 1;
    std::vector<int> morphs;  // asset morph index of each local morph target
  };
  std::vector<Primitive> primitives_;
  std::vector<unsigned> textures_;
  std::size_t morphCount_ = 0;
  std::size_t jointCount_ = 0;
};

class CharacterPose {
 public:
  explicit CharacterPose(const Skeleton& skeleton);
  ~CharacterPose();
  CharacterPose(const CharacterPose&) = delete;
  CharacterPose& operator=(const CharacterPose&) = delete;

  // Copies the frame's palette (through the bridge, packed 3x4 with the inverse
  // bind applied) and morph weights; uploads the palette. No allocation.
  void update(const TransformBuffer& buffer);
  // Replaces the palette with explicit skinning matrices (tests: a known pose).
  void setPalette(std::span<const glm::mat4> skinning, std::span<const glm::mat4> model);

 private:
  friend void drawCharacter(const ShaderProgram&, const CharacterModel&, const CharacterPose&, const glm::mat4&,
                            const glm::mat4&, const Lighting&, const PrtIrradiance*, float);
  void upload();
  bridge::PaletteBinding binding_;
  std::vector<float> palette_;        // joints x 12 floats
  std::vector<glm::mat4> model_;      // model-space joint matrices (rigid meshes)
  std::vector<float> morphWeights_;
  unsigned paletteTexture_ = 0;
  int joints_ = 0;
};

// One character's PRT irradiance E_v (linear RGB, before albedo / pi and exposure) per
// vertex of its model, as vertex attribute 5 (aPrtIrradiance): one GL_DYNAMIC_DRAW buffer
// per drawn primitive, sized once here.
class PrtIrradiance {
 public:
  // `primitiveVertexOffset`: the first vertex of each asset primitive in the per-vertex
  // array upload() takes (prt::TransferMesh::primitiveVertexOffset, mesh-major, one entry per
  // primitive, drawn or not), `vertexCount` the array's length. A drawn primitive whose
  // slice does not have its vertex count keeps the SH9 per-fragment light (mismatches()).
  PrtIrradiance(const CharacterModel& model, std::span<const std::size_t> primitiveVertexOffset,
                std::size_t vertexCount);
  ~PrtIrradiance();
  PrtIrradiance(const PrtIrradiance&) = delete;
  PrtIrradiance& operator=(const PrtIrradiance&) = delete;

  // Copies each primitive's slice of `irradiance` (vertexCount() values) into its buffer.
  // No allocation; does nothing when the size is wrong.
  void upload(std::span<const glm::vec3> irradiance) noexcept;
  [[nodiscard]] std::size_t vertexCount() const noexcept { return vertices_; }
  [[nodiscard]] std::size_t mismatches() const noexcept { return mismatches_; }

 private:
  friend void drawCharacter(const ShaderProgram&, const CharacterModel&, const CharacterPose&, const glm::mat4&,
                            const glm::mat4&, const Lighting&, const PrtIrradiance*, float);
  struct Slice {
    unsigned buffer = 0;  // 0: this primitive is lit per fragment
    std::size_t first = 0, count = 0;
  };
  std::vector<Slice> slices_;  // one per CharacterModel primitive, in its order
  std::size_t vertices_ = 0, mismatches_ = 0;
};

// Draws one character with `program` (character.vert + character.frag): lit by
// `prt` when given (per-vertex irradiance), else by lighting.irradianceSH per fragment.
// `opacity` < 1 fades the whole character over what is behind it (a depth pass first, so it
// fades as one surface: its far side never shows through its near side); so does
// lighting.occlusion, over the mask only.
void drawCharacter(const ShaderProgram& program, const CharacterModel& model, const CharacterPose& pose,
                   const glm::mat4& world, const glm::mat4& viewProjection, const Lighting& lighting,
                   const PrtIrradiance* prt = nullptr, float opacity = 1.0f);

}  // namespace marionette::ar
