// What the glTF import tests share (gltf_import_real_test.cpp, gltf_import_handwritten_test.cpp):
// importing with the diagnostics checked, skeleton lookups, and the checks every imported asset passes.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "test_data.hpp"


namespace marionette::gltf_test {

using test::assimpModel;
using test::sharedAsset;


inline ImportResult importOk(const std::string& path, const ImportOptions& options = {}) {
  ImportResult r = importGltf(path, options);
  EXPECT_TRUE(r.ok()) << path << "\n" << r.diagnostics.format();
  return r;
}

inline int jointOf(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  EXPECT_GE(j, 0) << "joint '" << name << "' not found";
  return j;
}

inline std::string parentName(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  if (j < 0 || s.parents[static_cast<std::size_t>(j)] < 0) return "";
  return s.names[static_cast<std::size_t>(s.parents[static_cast<std::size_t>(j)])];
}

inline glm::vec3 restPosition(const Skeleton& s, const std::string& name) {
  const auto model = s.restModelMatrices();
  const int j = s.findJoint(name);
  return j < 0 ? glm::vec3(NAN) : glm::vec3(model[static_cast<std::size_t>(j)][3]);
}

// Degrees below the horizontal plane of the bone from joint a to joint b.
inline double degreesBelowHorizontal(glm::vec3 a, glm::vec3 b) {
  const glm::vec3 d = b - a;
  return glm::degrees(std::asin(-d.y / glm::length(d)));
}

// Model position of a joint in the bind pose: inverse of its inverse bind matrix.
inline glm::vec3 bindPosition(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  return j < 0 ? glm::vec3(NAN) : glm::vec3(glm::inverse(s.inverseBind[static_cast<std::size_t>(j)])[3]);
}

inline bool finite(float f) { return std::isfinite(f); }
template <class V>
bool finite(const std::vector<V>& values) {
  for (const V& v : values)
    for (int c = 0; c < V::length(); ++c)
      if (!std::isfinite(static_cast<float>(v[c]))) return false;
  return true;
}
inline bool finite(const std::vector<float>& values) {
  for (float f : values)
    if (!std::isfinite(f)) return false;
  return true;
}
inline bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    if (!finite(std::vector<glm::vec4>{m[c]})) return false;
  return true;
}

// Every float the importer produced is finite.
inline void expectAllFinite(const Asset& a) {
  const Skeleton& s = a.skeleton;
  EXPECT_TRUE(finite(s.rootTransform));
  for (std::size_t j = 0; j < s.jointCount(); ++j) {
    EXPECT_TRUE(finite(s.inverseBind[j])) << s.names[j];
    const Transform& t = s.restPose[j];
    EXPECT_TRUE(finite(std::vector<glm::vec3>{t.translation, t.scale}) &&
                finite(std::vector<glm::vec4>{glm::vec4(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)}))
        << s.names[j];
  }
  for (const Clip& c : a.clips) {
    EXPECT_TRUE(finite(c.duration)) << c.name;
    for (const JointTrack& t : c.tracks) {
      std::vector<glm::vec4> q;
      for (const glm::quat& r : t.rotation.values) q.emplace_back(r.x, r.y, r.z, r.w);
      EXPECT_TRUE(finite(t.translation.values) && finite(t.scale.values) && finite(q) && finite(t.translation.times) &&
                  finite(t.rotation.times) && finite(t.scale.times))
          << c.name << " joint " << t.joint;
    }
    for (const MorphTrack& m : c.morphTracks) EXPECT_TRUE(finite(m.times) && finite(m.weights)) << c.name;
  }
  for (const Mesh& m : a.meshes)
    for (const MeshPrimitive& p : m.primitives) {
      EXPECT_TRUE(finite(p.positions) && finite(p.normals) && finite(p.uvs) && finite(p.weights)) << m.name;
      for (const MorphTargetDelta& d : p.morphTargets) EXPECT_TRUE(finite(d.positions) && finite(d.normals)) << m.name;
    }
  for (const Material& m : a.materials) EXPECT_TRUE(finite(std::vector<glm::vec4>{m.baseColor})) << m.name;
}

// Meshes are usable: triangles, indices in range, joint indices inside the
// skeleton and weights that sum to 1.
inline void expectMeshesConsistent(const Asset& a) {
  ASSERT_FALSE(a.meshes.empty());
  for (const Mesh& m : a.meshes) {
    EXPECT_FALSE(m.primitives.empty()) << m.name;
    for (const MeshPrimitive& p : m.primitives) {
      const std::size_t n = p.positions.size();
      EXPECT_GT(n, 0u) << m.name;
      EXPECT_GT(p.indices.size(), 0u) << m.name;
      EXPECT_EQ(p.indices.size() % 3, 0u) << m.name;
      for (std::uint32_t i : p.indices) ASSERT_LT(i, n) << m.name;
      if (!p.normals.empty()) {
        EXPECT_EQ(p.normals.size(), n) << m.name;
      }
      if (!p.uvs.empty()) {
        EXPECT_EQ(p.uvs.size(), n) << m.name;
      }
      if (m.skinned) {
        ASSERT_EQ(p.joints.size(), n) << m.name;
        ASSERT_EQ(p.weights.size(), n) << m.name;
      }
      for (std::size_t v = 0; v < p.joints.size(); ++v) {
        for (int k = 0; k < 4; ++k) ASSERT_LT(p.joints[v][k], a.skeleton.jointCount()) << m.name;
        const glm::vec4 w = p.weights[v];
        ASSERT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-4f) << m.name << " vertex " << v;
      }
      EXPECT_EQ(p.morphTargets.size(), m.morphTargets.size()) << m.name;
      if (p.material >= 0) {
        EXPECT_LT(static_cast<std::size_t>(p.material), a.materials.size());
      }
    }
    for (int t : m.morphTargets) EXPECT_LT(static_cast<std::size_t>(t), a.morphTargets.size());
  }
}

// Vertices of every mesh skinned by the rest pose, as a renderer would place them.
inline std::vector<glm::vec3> skinnedRestVertices(const Asset& a) {
  const auto model = a.skeleton.restModelMatrices();
  std::vector<glm::vec3> out;
  for (const Mesh& m : a.meshes)
    for (const MeshPrimitive& p : m.primitives)
      for (std::size_t v = 0; v < p.positions.size(); ++v) {
        if (p.joints.empty()) {
          out.push_back(p.positions[v]);
          continue;
        }
        glm::vec3 x(0.0f);
        for (int k = 0; k < 4; ++k) {
          const std::size_t j = p.joints[v][k];
          x += p.weights[v][k] * glm::vec3(model[j] * a.skeleton.inverseBind[j] * glm::vec4(p.positions[v], 1.0f));
        }
        out.push_back(x);
      }
  return out;
}

inline void expectValid(const Asset& a) {
  EXPECT_EQ(a.skeleton.validate(), "");
  for (const Clip& c : a.clips) EXPECT_EQ(c.validate(a.skeleton.jointCount()), "") << c.name;
}

// Expects a failed import with an error that names the file and says something.
inline void expectRejected(const std::string& path, const std::string& mustMention, const ImportOptions& options = {}) {
  ImportResult r = importGltf(path, options);
  EXPECT_FALSE(r.ok()) << path;
  EXPECT_FALSE(r.asset.has_value()) << path;
  bool found = false;
  for (const Diagnostic& d : r.diagnostics.items) {
    if (d.severity != Severity::Error) continue;
    EXPECT_EQ(d.file, path);
    EXPECT_FALSE(d.message.empty());
    EXPECT_NE(d.format().find(path), std::string::npos);
    if (d.message.find(mustMention) != std::string::npos) found = true;
  }
  EXPECT_TRUE(found) << path << ": no error mentions '" << mustMention << "'; got:\n" << r.diagnostics.format();
}

inline std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("marionette_gltf_test_" + name)).string();
}

}  // namespace marionette::gltf_test
