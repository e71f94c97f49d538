// What an importer produces: a skeleton, its clips, meshes and materials.
// Plain data; the runtime only needs the skeleton and the clips.
#pragma once
#include <charconv>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "marionette/animation/clip.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct MorphTargetDelta {
  std::vector<glm::vec3> positions;  // per vertex; may be empty
  std::vector<glm::vec3> normals;    // per vertex; may be empty
};

struct MeshPrimitive {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;         // glTF convention: origin at the top-left of the image
  std::vector<glm::u16vec4> joints;  // indices into the Skeleton (not the file's skin order)
  std::vector<glm::vec4> weights;
  std::vector<std::uint32_t> indices;  // triangles
  int material = -1;
  std::vector<MorphTargetDelta> morphTargets;  // in the order of Mesh::morphTargets
};

struct Mesh {
  std::string name;
  std::vector<MeshPrimitive> primitives;  // one per sub-mesh / material
  std::vector<int> morphTargets;          // indices into Asset::morphTargets
  bool skinned = false;
  int joint = -1;  // for an unskinned mesh: the joint it is attached to (rigid parts), or -1
};

struct Material {
  std::string name;
  glm::vec4 baseColor{1.0f};
  std::string baseColorTexture;  // file path (resolved against the asset) or "embedded:N"; empty if none
};

// VRM humanoid data, when the file has it.
struct Humanoid {
  std::map<std::string, std::string> bones;  // VRM bone name (e.g. "leftUpperArm") -> joint name
  // Expression / blend-shape groups (e.g. "A" -> {{morph index, weight 0..1}}).
  std::map<std::string, std::vector<std::pair<int, float>>> expressions;
};

struct Asset {
  std::string sourcePath;
  Skeleton skeleton;
  std::vector<Clip> clips;          // bound to `skeleton`
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<std::string> morphTargets;  // the character's morph-target order (unique names)
  bool hasHumanoid = false;
  Humanoid humanoid;
  float unitScale = 1.0f;  // metres per file unit, including ImportOptions::extraScale
  // The encoded bytes (PNG, JPEG, ...) of the "embedded:N" textures (Material::baseColorTexture),
  // index N: images inside the file (a GLB's buffer views, data URIs, a .zae's or FBX's
  // embedded textures). Kept when the asset was imported with meshes (ImportOptions::loadMeshes);
  // an entry is empty for an image that is a file of its own (the material names its path).
  std::vector<std::vector<unsigned char>> embeddedImages;
};

// The image index N of an "embedded:N" texture reference, or -1 for anything else.
[[nodiscard]] inline int embeddedImageIndex(std::string_view reference) noexcept {
  constexpr std::string_view prefix = "embedded:";
  if (reference.substr(0, prefix.size()) != prefix) return -1;
  int index = -1;
  const char* first = reference.data() + prefix.size();
  const char* last = reference.data() + reference.size();
  auto [end, ec] = std::from_chars(first, last, index);
  return ec == std::errc{} && end == last && index >= 0 ? index : -1;
}

}  // namespace marionette
