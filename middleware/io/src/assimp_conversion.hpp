// Private to the Assimp importer: the conversion state every stage shares (the
// scene, the options, the diagnostics, the Asset being built and the joint
// lookups), Assimp-to-GLM conversions, and the stages defined in their own files.
#pragma once
#include <assimp/scene.h>

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/io/import.hpp"

namespace marionette::assimp_detail {

inline glm::mat4 toGlm(const aiMatrix4x4& m) {
  // aiMatrix4x4 is row-major (a1..a4 is the first row); glm::mat4 takes columns.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4,
                   m.c4, m.d4);
}
inline glm::vec3 toGlm(const aiVector3D& v) { return {v.x, v.y, v.z}; }
inline glm::quat toGlm(const aiQuaternion& q) { return glm::quat(q.w, q.x, q.y, q.z); }

inline std::string str(const aiString& s) { return std::string(s.C_Str()); }

struct Importing {
  const aiScene& scene;
  const std::string& path;
  const ImportOptions& options;
  Diagnostics& diag;
  Asset asset;
  float scale = 1.0f;  // applied to every length
  std::unordered_map<const aiNode*, int> jointOfNode;
  std::unordered_map<std::string, int> jointOfName;  // the first joint with each name
  std::vector<glm::mat4> foldedHelpers;             // per joint: FBX helper transforms above it

  void error(std::string message) { diag.error(path, std::move(message)); }
  void warning(std::string message) { diag.warning(path, std::move(message)); }
  void note(std::string message) { diag.items.push_back({Severity::Note, path, 0, 0, std::move(message)}); }
};

// The skeleton, joint lookups and folded FBX helpers (assimp_skeleton.cpp).
void buildSkeleton(Importing& im);
// One Clip per aiAnimation (assimp_animation.cpp).
void convertAnimations(Importing& im);
// Materials, then one Mesh per node with meshes (assimp_meshes.cpp).
void convertMeshes(Importing& im);

}  // namespace marionette::assimp_detail
