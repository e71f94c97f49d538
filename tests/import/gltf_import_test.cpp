// glTF / GLB / VRM / VRMA import: real characters and motions from ../shared/assets,
// Debian's assimp glTF2 test models (good and deliberately broken), and small
// hand-written files generated below. Missing data fails, never skips.
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

namespace marionette {
namespace {

using test::assimpModel;
using test::sharedAsset;

// ---- helpers ---------------------------------------------------------------------------

ImportResult importOk(const std::string& path, const ImportOptions& options = {}) {
  ImportResult r = importGltf(path, options);
  EXPECT_TRUE(r.ok()) << path << "\n" << r.diagnostics.format();
  return r;
}

int jointOf(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  EXPECT_GE(j, 0) << "joint '" << name << "' not found";
  return j;
}

std::string parentName(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  if (j < 0 || s.parents[static_cast<std::size_t>(j)] < 0) return "";
  return s.names[static_cast<std::size_t>(s.parents[static_cast<std::size_t>(j)])];
}

glm::vec3 restPosition(const Skeleton& s, const std::string& name) {
  const auto model = s.restModelMatrices();
  const int j = s.findJoint(name);
  return j < 0 ? glm::vec3(NAN) : glm::vec3(model[static_cast<std::size_t>(j)][3]);
}

// Degrees below the horizontal plane of the bone from joint a to joint b.
double degreesBelowHorizontal(glm::vec3 a, glm::vec3 b) {
  const glm::vec3 d = b - a;
  return glm::degrees(std::asin(-d.y / glm::length(d)));
}

// Model position of a joint in the bind pose: inverse of its inverse bind matrix.
glm::vec3 bindPosition(const Skeleton& s, const std::string& name) {
  const int j = s.findJoint(name);
  return j < 0 ? glm::vec3(NAN) : glm::vec3(glm::inverse(s.inverseBind[static_cast<std::size_t>(j)])[3]);
}

bool finite(float f) { return std::isfinite(f); }
template <class V>
bool finite(const std::vector<V>& values) {
  for (const V& v : values)
    for (int c = 0; c < V::length(); ++c)
      if (!std::isfinite(static_cast<float>(v[c]))) return false;
  return true;
}
bool finite(const std::vector<float>& values) {
  for (float f : values)
    if (!std::isfinite(f)) return false;
  return true;
}
bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    if (!finite(std::vector<glm::vec4>{m[c]})) return false;
  return true;
}

// Every float the importer produced is finite.
void expectAllFinite(const Asset& a) {
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
void expectMeshesConsistent(const Asset& a) {
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
std::vector<glm::vec3> skinnedRestVertices(const Asset& a) {
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

void expectValid(const Asset& a) {
  EXPECT_EQ(a.skeleton.validate(), "");
  for (const Clip& c : a.clips) EXPECT_EQ(c.validate(a.skeleton.jointCount()), "") << c.name;
}

// Expects a failed import with an error that names the file and says something.
void expectRejected(const std::string& path, const std::string& mustMention, const ImportOptions& options = {}) {
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

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("marionette_gltf_test_" + name)).string();
}

// ---- RobotExpressive ------------------------------------------------------------------------

TEST(GltfImport, RobotExpressiveSkeletonUnitesBothSkins) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Skeleton& s = r.asset->skeleton;
  ASSERT_EQ(s.jointCount(), 43u);  // 2 skins over the same 43 joints
  // Skin order kept where the hierarchy allows it: Foot.L before Body.
  EXPECT_EQ(s.names[0], "Bone");
  EXPECT_EQ(s.names[1], "Foot.L");
  EXPECT_EQ(s.names[2], "Body");
  EXPECT_EQ(s.names[42], "PoleTarget.R");
  EXPECT_EQ(parentName(s, "Foot.L"), "Bone");
  EXPECT_EQ(parentName(s, "Hips"), "Body");
  EXPECT_EQ(parentName(s, "LowerArm.L"), "UpperArm.L");
  EXPECT_EQ(parentName(s, "UpperLeg.R"), "Body");
  EXPECT_EQ(s.parents[0], -1);
  for (std::size_t j = 0; j < s.jointCount(); ++j) EXPECT_EQ(s.skinned[j], 1) << s.names[j];
  // RootNode and RobotArmature (rotation -90 deg about X, scale 100) sit above Bone.
  EXPECT_NEAR(glm::length(glm::vec3(s.rootTransform[0])), 100.0f, 1e-3f);
  EXPECT_NEAR(s.rootTransform[2][1], 100.0f, 1e-3f);  // Z axis maps to +Y
  expectValid(*r.asset);
  expectAllFinite(*r.asset);
}

TEST(GltfImport, RobotExpressiveClips) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const std::vector<std::pair<std::string, float>> expected = {
      {"Dance", 3.333f},   {"Death", 0.958f},    {"Idle", 3.333f},    {"Jump", 0.708f},     {"No", 1.667f},
      {"Punch", 0.833f},   {"Running", 0.958f},  {"Sitting", 0.417f}, {"Standing", 0.417f}, {"ThumbsUp", 1.583f},
      {"Walking", 0.958f}, {"WalkJump", 0.833f}, {"Wave", 1.833f},    {"Yes", 1.667f}};
  ASSERT_EQ(r.asset->clips.size(), expected.size());  // named clips: no "merged" clip
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Clip& c = r.asset->clips[i];
    EXPECT_EQ(c.name, expected[i].first);
    EXPECT_NEAR(c.duration, expected[i].second, 0.002f) << c.name;
    EXPECT_FALSE(c.tracks.empty()) << c.name;
    for (std::size_t t = 1; t < c.tracks.size(); ++t) EXPECT_LT(c.tracks[t - 1].joint, c.tracks[t].joint);
    for (const JointTrack& t : c.tracks)
      for (const glm::quat& q : t.rotation.values) ASSERT_NEAR(glm::length(q), 1.0f, 1e-4f) << c.name;
    // Each clip also drives the face morph targets (Angry, Surprised, Sad).
    ASSERT_EQ(c.morphTracks.size(), 1u) << c.name;
    EXPECT_EQ(c.morphTracks[0].targets, (std::vector<int>{0, 1, 2}));
  }
}

TEST(GltfImport, RobotExpressiveMeshesAndMorphTargets) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  EXPECT_EQ(a.morphTargets, (std::vector<std::string>{"Angry", "Surprised", "Sad"}));
  ASSERT_EQ(a.meshes.size(), 14u);
  std::size_t primitives = 0, vertices = 0, triangles = 0;
  for (const Mesh& m : a.meshes) {
    primitives += m.primitives.size();
    for (const MeshPrimitive& p : m.primitives) {
      vertices += p.positions.size();
      triangles += p.indices.size() / 3;
    }
  }
  // As the file stores them (Assimp reports 21 meshes / 7,070 vertices after its own splitting and welding).
  EXPECT_EQ(primitives, 19u);
  EXPECT_EQ(vertices, 7214u);
  EXPECT_EQ(triangles, 3237u);
  const auto head = std::find_if(a.meshes.begin(), a.meshes.end(), [](const Mesh& m) { return m.name == "Head"; });
  ASSERT_NE(head, a.meshes.end());
  EXPECT_EQ(head->morphTargets, (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(a.materials.size(), 3u);
  expectMeshesConsistent(a);
}

// The file's node transforms are not its bind pose: the bind pose (inverse bind
// matrices) is a T-pose, the nodes hold the arms about 62 degrees down.
// Skeleton::restPose follows the nodes; the T-pose is checked on the bind pose.
TEST(GltfImport, RobotExpressiveBindPoseIsTPoseAndMeshesFollowTheirJoints) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Skeleton& s = r.asset->skeleton;
  const double bindAngle = degreesBelowHorizontal(bindPosition(s, "UpperArm.L"), bindPosition(s, "LowerArm.L"));
  EXPECT_NEAR(bindAngle, 3.3, 1.0);
  EXPECT_LT(std::fabs(bindAngle), 10.0);
  const double restAngle = degreesBelowHorizontal(restPosition(s, "UpperArm.L"), restPosition(s, "LowerArm.L"));
  EXPECT_NEAR(restAngle, 62.6, 1.0);
  // Most robot parts are rigid meshes under joint nodes, bound to those joints
  // on import. Skinned by the rest pose they must stand on the ground and
  // enclose the skeleton (head top above the head joint).
  const auto verts = skinnedRestVertices(*r.asset);
  float low = INFINITY, high = -INFINITY;
  for (const glm::vec3& v : verts) low = std::min(low, v.y), high = std::max(high, v.y);
  const float headY = restPosition(s, "Head").y;
  EXPECT_NEAR(low, 0.0f, 0.1f);
  EXPECT_GT(high, headY);
  EXPECT_LT(high, 2.0f * headY);
}

// ---- Godette (VRM 0.0) --------------------------------------------------------------------

TEST(GltfImport, GodetteSkeletonAndHumanoid) {
  const std::string path = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  const Skeleton& s = a.skeleton;
  ASSERT_EQ(s.jointCount(), 68u);
  EXPECT_EQ(s.names[0], "Armature_rootJoint");
  EXPECT_EQ(s.names[1], "pelvis_Armature");
  EXPECT_EQ(parentName(s, "pelvis_Armature"), "Armature_rootJoint");
  EXPECT_EQ(parentName(s, "head_Armature"), "neck_Armature");
  EXPECT_EQ(parentName(s, "upper_arm.l_Armature"), "shoulder.l_Armature");
  EXPECT_EQ(s.rootTransform, glm::mat4(1.0f));
  EXPECT_NEAR(restPosition(s, "head_Armature").y, 0.98f, 0.02f);
  EXPECT_NEAR(degreesBelowHorizontal(restPosition(s, "upper_arm.l_Armature"), restPosition(s, "lowerarm.l_Armature")),
              4.0, 1.0);
  expectValid(a);
  expectAllFinite(a);

  ASSERT_TRUE(a.hasHumanoid);
  const auto& bones = a.humanoid.bones;
  EXPECT_EQ(bones.size(), 45u);
  const std::map<std::string, std::string> expected = {{"hips", "pelvis_Armature"},
                                                       {"spine", "tummy_Armature"},
                                                       {"chest", "chest_Armature"},
                                                       {"neck", "neck_Armature"},
                                                       {"head", "head_Armature"},
                                                       {"leftShoulder", "shoulder.l_Armature"},
                                                       {"leftUpperArm", "upper_arm.l_Armature"},
                                                       {"leftLowerArm", "lowerarm.l_Armature"},
                                                       {"leftHand", "hand.l_Armature"},
                                                       {"leftUpperLeg", "thigh.l_Armature"},
                                                       {"leftLowerLeg", "shin.l_Armature"},
                                                       {"leftFoot", "foot.l_Armature"},
                                                       {"leftToes", "toes.l_Armature"}};
  for (const auto& [bone, joint] : expected) {
    ASSERT_TRUE(bones.count(bone)) << bone;
    EXPECT_EQ(bones.at(bone), joint) << bone;
  }
  for (const auto& [bone, joint] : bones) EXPECT_GE(s.findJoint(joint), 0) << bone << " -> " << joint;
}

TEST(GltfImport, GodetteVisemesAndMorphTargets) {
  const std::string path = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  const std::vector<std::string> face = {
      "HideHairBalls", "HdieEarRings", "HideBlush", "blink_left", "blink_right",    "ah", "ih", "uu", "ee", "oh",
      "look_up",       "look_down",    "look_left", "look_right", "angled_eyebrows"};
  const auto mesh = std::find_if(a.meshes.begin(), a.meshes.end(), [](const Mesh& m) { return m.name == "FaceMesh"; });
  ASSERT_NE(mesh, a.meshes.end());
  ASSERT_EQ(mesh->morphTargets.size(), 15u);
  for (std::size_t k = 0; k < face.size(); ++k)
    EXPECT_EQ(a.morphTargets[static_cast<std::size_t>(mesh->morphTargets[k])], face[k]);
  expectMeshesConsistent(a);

  auto morphIndex = [&](const std::string& name) {
    return static_cast<int>(std::find(a.morphTargets.begin(), a.morphTargets.end(), name) - a.morphTargets.begin());
  };
  const auto& ex = a.humanoid.expressions;
  // Upper-case viseme aliases and the VRM preset names as written ("a" ... "o").
  const std::vector<std::pair<std::string, std::string>> visemes = {
      {"A", "ah"}, {"I", "ih"}, {"U", "uu"}, {"E", "ee"}, {"O", "oh"}};
  for (const auto& [key, target] : visemes) {
    for (const std::string& k : {key, std::string(1, static_cast<char>(std::tolower(key[0])))}) {
      ASSERT_TRUE(ex.count(k)) << k;
      ASSERT_EQ(ex.at(k).size(), 1u) << k;
      EXPECT_EQ(ex.at(k)[0].first, morphIndex(target)) << k;
      EXPECT_FLOAT_EQ(ex.at(k)[0].second, 1.0f) << k;
    }
  }
  ASSERT_TRUE(ex.count("blink"));
  EXPECT_EQ(ex.at("blink").size(), 2u);
  ASSERT_TRUE(ex.count("joy"));
  ASSERT_EQ(ex.at("joy").size(), 2u);
  EXPECT_FLOAT_EQ(ex.at("joy")[0].second, 0.5f);
  EXPECT_FLOAT_EQ(ex.at("joy")[1].second, 0.25f);
}

// ---- CesiumMan ----------------------------------------------------------------------------

TEST(GltfImport, CesiumManSkeletonIsZUpInANodeTransform) {
  const std::string path = sharedAsset("characters/CesiumMan.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Skeleton& s = r.asset->skeleton;
  ASSERT_EQ(s.jointCount(), 19u);
  EXPECT_EQ(s.names[0], "node_2");  // no names in the file: synthesized from node indices
  EXPECT_EQ(parentName(s, "node_11"), "node_2");
  EXPECT_EQ(parentName(s, "node_20"), "node_19");
  EXPECT_EQ(parentName(s, "node_17"), "node_16");
  EXPECT_EQ(parentName(s, "node_3"), "node_2");
  EXPECT_NE(s.rootTransform, glm::mat4(1.0f));
  const glm::vec3 up = glm::vec3(s.rootTransform * glm::vec4(0, 0, 1, 0));
  EXPECT_NEAR(up.y, 1.0f, 1e-5f);  // the Z-up bind space is turned Y-up above the skeleton
  // The head is the highest joint, about 1.19 m up.
  const auto model = s.restModelMatrices();
  std::size_t top = 0;
  for (std::size_t j = 1; j < model.size(); ++j)
    if (model[j][3].y > model[top][3].y) top = j;
  EXPECT_EQ(s.names[top], "node_20");
  EXPECT_NEAR(model[top][3].y, 1.19f, 0.02f);
  // A-pose: upper arm about 27 degrees below horizontal.
  EXPECT_NEAR(degreesBelowHorizontal(restPosition(s, "node_13"), restPosition(s, "node_14")), 27.0, 2.0);
  expectValid(*r.asset);
  expectAllFinite(*r.asset);
  expectMeshesConsistent(*r.asset);
  EXPECT_EQ(r.asset->materials.size(), 1u);
  EXPECT_EQ(r.asset->materials[0].baseColorTexture, "embedded:0");
  // The image inside the GLB is kept, encoded, for a renderer (asset/asset.hpp); not without meshes.
  ASSERT_EQ(r.asset->embeddedImages.size(), 1u);
  const std::vector<unsigned char>& image = r.asset->embeddedImages[0];
  ASSERT_GT(image.size(), 1000u);
  const bool png = image[1] == 'P' && image[2] == 'N' && image[3] == 'G';
  const bool jpeg = image[0] == 0xFF && image[1] == 0xD8;
  EXPECT_TRUE(png || jpeg);
  EXPECT_EQ(embeddedImageIndex(r.asset->materials[0].baseColorTexture), 0);
  EXPECT_EQ(embeddedImageIndex("embedded:x"), -1);
  EXPECT_EQ(embeddedImageIndex("textures/skin.png"), -1);
  ImportOptions noMeshes;
  noMeshes.loadMeshes = false;
  const ImportResult bare = importOk(path, noMeshes);
  ASSERT_TRUE(bare.asset);
  EXPECT_TRUE(bare.asset->embeddedImages.empty());
}

TEST(GltfImport, CesiumManPerJointAnimationsAndMergedClip) {
  const std::string path = sharedAsset("characters/CesiumMan.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const auto& clips = r.asset->clips;
  ASSERT_EQ(clips.size(), 20u);  // 19 per-joint animations + "merged"
  std::set<int> joints;
  for (std::size_t i = 0; i < 19; ++i) {
    EXPECT_EQ(clips[i].name, "animation_" + std::to_string(i));
    EXPECT_NEAR(clips[i].duration, 2.0f, 1e-4f);
    ASSERT_EQ(clips[i].tracks.size(), 1u);
    joints.insert(clips[i].tracks[0].joint);
  }
  EXPECT_EQ(joints.size(), 19u);
  const Clip& merged = clips[19];
  EXPECT_EQ(merged.name, "merged");
  EXPECT_NEAR(merged.duration, 2.0f, 1e-4f);
  ASSERT_EQ(merged.tracks.size(), 19u);
  for (std::size_t t = 0; t < 19; ++t) {
    EXPECT_EQ(merged.tracks[t].joint, static_cast<int>(t));
    EXPECT_FALSE(merged.tracks[t].rotation.empty());
  }
  expectValid(*r.asset);
}

// ---- VRM Animation -------------------------------------------------------------------------

TEST(GltfImport, VrmaClipAndHumanoidMap) {
  const std::string path = sharedAsset("motions/gltf/three-vrm_test.vrma");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  const Skeleton& s = a.skeleton;
  EXPECT_EQ(s.jointCount(), 53u);  // 51 bone nodes + the `happy` and `lookAt` proxies
  EXPECT_EQ(s.names[0], "hips");
  EXPECT_EQ(parentName(s, "rightLowerArm"), "rightUpperArm");
  for (std::size_t j = 0; j < s.jointCount(); ++j) EXPECT_EQ(s.skinned[j], 0);
  EXPECT_TRUE(a.meshes.empty());
  ASSERT_EQ(a.clips.size(), 1u);
  const Clip& c = a.clips[0];
  EXPECT_NEAR(c.duration, 3.0f, 1e-4f);
  ASSERT_EQ(c.tracks.size(), 3u);
  EXPECT_EQ(c.tracks[0].joint, jointOf(s, "rightUpperArm"));
  EXPECT_EQ(c.tracks[0].rotation.keyCount(), 7u);
  EXPECT_EQ(c.tracks[1].joint, jointOf(s, "happy"));
  EXPECT_EQ(c.tracks[1].translation.keyCount(), 7u);
  EXPECT_EQ(c.tracks[2].joint, jointOf(s, "lookAt"));
  EXPECT_EQ(c.tracks[2].rotation.keyCount(), 7u);
  ASSERT_TRUE(a.hasHumanoid);
  EXPECT_EQ(a.humanoid.bones.size(), 51u);
  EXPECT_EQ(a.humanoid.bones.at("hips"), "hips");
  EXPECT_EQ(a.humanoid.bones.at("rightUpperArm"), "rightUpperArm");
  EXPECT_EQ(a.humanoid.bones.at("leftToes"), "leftToes");
  expectValid(a);
  expectAllFinite(a);
}

// ---- options ---------------------------------------------------------------------------------

TEST(GltfImport, OptionsSkipMeshesOrAnimations) {
  const std::string path = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportOptions noMeshes;
  noMeshes.loadMeshes = false;
  ImportResult r = importOk(path, noMeshes);
  ASSERT_TRUE(r.asset);
  EXPECT_TRUE(r.asset->meshes.empty());
  EXPECT_TRUE(r.asset->materials.empty());
  EXPECT_EQ(r.asset->clips.size(), 14u);
  EXPECT_EQ(r.asset->morphTargets.size(), 3u);  // weight tracks still refer to them
  ImportOptions noClips;
  noClips.loadAnimations = false;
  r = importOk(path, noClips);
  ASSERT_TRUE(r.asset);
  EXPECT_TRUE(r.asset->clips.empty());
  EXPECT_EQ(r.asset->meshes.size(), 14u);
}

TEST(GltfImport, ExtraScaleScalesEveryLength) {
  const std::string path = sharedAsset("characters/CesiumMan.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult one = importOk(path);
  ImportOptions twice;
  twice.extraScale = 2.0f;
  ImportResult two = importOk(path, twice);
  ASSERT_TRUE(one.asset && two.asset);
  EXPECT_NEAR(restPosition(two.asset->skeleton, "node_20").y, 2.0f * restPosition(one.asset->skeleton, "node_20").y,
              1e-4f);
  const auto v1 = skinnedRestVertices(*one.asset), v2 = skinnedRestVertices(*two.asset);
  ASSERT_EQ(v1.size(), v2.size());
  for (std::size_t i = 0; i < v1.size(); i += 97) EXPECT_NEAR(glm::length(v2[i] - 2.0f * v1[i]), 0.0f, 1e-4f);
  const auto& t1 = one.asset->clips.back().tracks[0].translation.values;
  const auto& t2 = two.asset->clips.back().tracks[0].translation.values;
  ASSERT_EQ(t1.size(), t2.size());
  ASSERT_FALSE(t1.empty());
  EXPECT_NEAR(glm::length(t2[0] - 2.0f * t1[0]), 0.0f, 1e-5f);
  ImportOptions bad;
  bad.extraScale = NAN;
  expectRejected(path, "extraScale", bad);
}

// ---- Debian assimp test models -----------------------------------------------------------------

TEST(GltfImport, SimpleSkinLoads) {
  const std::string path = assimpModel("glTF2/simple_skin/simple_skin.gltf");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  ASSERT_EQ(a.skeleton.jointCount(), 2u);
  EXPECT_EQ(a.skeleton.names[0], "node_1");
  EXPECT_EQ(a.skeleton.parents[1], 0);
  ASSERT_EQ(a.clips.size(), 1u);
  EXPECT_EQ(a.clips[0].name, "animation_0");
  EXPECT_NEAR(a.clips[0].duration, 5.5f, 1e-5f);
  ASSERT_EQ(a.clips[0].tracks.size(), 1u);
  EXPECT_EQ(a.clips[0].tracks[0].joint, 1);
  EXPECT_EQ(a.clips[0].tracks[0].rotation.keyCount(), 12u);
  expectMeshesConsistent(a);
  expectValid(a);
  expectAllFinite(a);
}

struct BadFile {
  const char* path;
  const char* mentions;
};

class GltfBadFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(GltfBadFile, IsRejectedWithADiagnostic) {
  const std::string path = assimpModel(GetParam().path);
  MARIONETTE_REQUIRE_FILE(path);
  expectRejected(path, GetParam().mentions);
}

INSTANTIATE_TEST_SUITE_P(
    AssimpModels, GltfBadFile,
    ::testing::Values(
        BadFile{"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", "mesh 'Mesh' primitive 0: vertex index 255"},
        BadFile{"glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf", "mesh 'Mesh' primitive 0: vertex index"},
        BadFile{"glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
                "POSITION) element 0 component 0 is not finite"},
        BadFile{"glTF2/RecursiveNodes/RecursiveNodes.gltf", "cycle"},
        BadFile{"glTF2/MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
        BadFile{"glTF2/wrongTypes/badArray.gltf", "meshes[0].primitives: expected an array"},
        BadFile{"glTF2/wrongTypes/badExtension.gltf", "KHR_texture_transform: expected an object"},
        BadFile{"glTF2/wrongTypes/badNumber.gltf", "normalTexture.scale: expected a finite number"},
        BadFile{"glTF2/wrongTypes/badObject.gltf", "pbrMetallicRoughness: expected an object"},
        BadFile{"glTF2/wrongTypes/badString.gltf", "scenes[0].name: expected a string"},
        BadFile{"glTF2/wrongTypes/badUint.gltf", "baseColorTexture.index: expected a non-negative integer"},
        BadFile{"glTF2/SchemaFailures/sceneWrongType.gltf", "scene: expected a non-negative integer"}),
    [](const ::testing::TestParamInfo<BadFile>& param) {
      std::string name = std::filesystem::path(param.param.path).stem().string();
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(GltfImport, TruncatedGlbIsRejected) {
  const std::string source = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(source);
  const std::string path = tempPath("truncated.glb");
  {
    std::ifstream in(source, std::ios::binary);
    std::vector<char> head(1000);
    ASSERT_TRUE(in.read(head.data(), static_cast<std::streamsize>(head.size())));
    std::ofstream out(path, std::ios::binary);
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
  }
  expectRejected(path, "truncated");
  std::filesystem::remove(path);
}

TEST(GltfImport, MissingFileIsRejected) {
  expectRejected("/nonexistent/marionette/nothing_here.glb", "does not exist");
  expectRejected(std::filesystem::temp_directory_path().string(), "not a regular file");
}

// ---- hand-written files ---------------------------------------------------------------------------

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned v = (bytes[i] << 16u) | ((i + 1 < bytes.size() ? bytes[i + 1] : 0u) << 8u) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0u);
    out += kDigits[(v >> 18u) & 63u];
    out += kDigits[(v >> 12u) & 63u];
    out += i + 1 < bytes.size() ? kDigits[(v >> 6u) & 63u] : '=';
    out += i + 2 < bytes.size() ? kDigits[v & 63u] : '=';
  }
  return out;
}

// A small animated file: STEP and CUBICSPLINE translations, a rotation stored
// as normalized shorts (KHR_mesh_quantization), morph weights on a one-triangle
// mesh. Each data block has its own buffer view and accessor (same index).
struct Synthetic {
  std::vector<unsigned char> buffer;
  nlohmann::json doc;

  // Appends values; returns the index of the new view/accessor.
  template <class T>
  int block(const std::vector<T>& values, int componentType, const char* type, std::size_t count,
            bool normalized = false) {
    const std::size_t offset = buffer.size();
    const auto* p = reinterpret_cast<const unsigned char*>(values.data());
    buffer.insert(buffer.end(), p, p + values.size() * sizeof(T));
    const std::size_t length = buffer.size() - offset;
    while (buffer.size() % 4) buffer.push_back(0);
    const int index = static_cast<int>(doc["accessors"].size());
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
    nlohmann::json acc = {{"bufferView", index}, {"componentType", componentType}, {"count", count}, {"type", type}};
    if (normalized) acc["normalized"] = true;
    doc["accessors"].push_back(acc);
    return index;
  }

  std::string write(const std::string& name) {
    if (doc.is_object())
      doc["buffers"] = nlohmann::json::array(
          {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(buffer)}}});
    const std::string path = tempPath(name);
    std::ofstream(path) << doc.dump(1);
    return path;
  }
};

constexpr int kFloat = 5126, kShort = 5122, kUShort = 5123;

Synthetic makeSynthetic(std::vector<float> times = {0.0f, 1.0f, 2.0f}) {
  Synthetic s;
  s.doc = {{"asset", {{"version", "2.0"}}},
           {"extensionsUsed", {"KHR_mesh_quantization"}},
           {"extensionsRequired", {"KHR_mesh_quantization"}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0}}}}},
           {"nodes",
            {{{"name", "root"}, {"children", {1, 3}}},
             {{"name", "arm"}, {"children", {2}}, {"translation", {0.0, 1.0, 0.0}}},
             {{"name", "hand"}, {"translation", {0.0, 0.5, 0.0}}},
             {{"name", "face"}, {"mesh", 0}}}},
           {"accessors", nlohmann::json::array()},
           {"bufferViews", nlohmann::json::array()}};
  const int t = s.block(times, kFloat, "SCALAR", 3);
  const int step = s.block(std::vector<float>{1, 0, 0, 2, 0, 0, 3, 0, 0}, kFloat, "VEC3", 3);
  std::vector<float> cubic;  // key k: in-tangent 10k+1, value 10k+2, out-tangent 10k+3 (in x)
  for (int k = 0; k < 3; ++k)
    for (int part = 1; part <= 3; ++part) cubic.insert(cubic.end(), {static_cast<float>(10 * k + part), 0.0f, 0.0f});
  const int cub = s.block(cubic, kFloat, "VEC3", 9);
  // x, y, z, w: identity, 90 degrees about Y, 180 degrees about Y.
  const int rot =
      s.block(std::vector<std::int16_t>{0, 0, 0, 32767, 0, 23170, 0, 23170, 0, 32767, 0, 0}, kShort, "VEC4", 3, true);
  const int weights = s.block(std::vector<float>{0.0f, 1.0f, 0.5f}, kFloat, "SCALAR", 3);
  const int pos = s.block(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kFloat, "VEC3", 3);
  const int delta = s.block(std::vector<float>{0, 0, 0.5f, 0, 0, 0, 0, 0, 0}, kFloat, "VEC3", 3);
  const int idx = s.block(std::vector<std::uint16_t>{0, 1, 2}, kUShort, "SCALAR", 3);
  s.doc["meshes"] = {
      {{"name", "tri"},
       {"extras", {{"targetNames", {"smile"}}}},
       {"primitives",
        {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"targets", {{{"POSITION", delta}}}}}}}}};
  s.doc["animations"] = {{{"name", "Synthetic"},
                          {"samplers",
                           {{{"input", t}, {"output", step}, {"interpolation", "STEP"}},
                            {{"input", t}, {"output", cub}, {"interpolation", "CUBICSPLINE"}},
                            {{"input", t}, {"output", rot}},
                            {{"input", t}, {"output", weights}, {"interpolation", "LINEAR"}}}},
                          {"channels",
                           {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                            {{"sampler", 1}, {"target", {{"node", 2}, {"path", "translation"}}}},
                            {{"sampler", 2}, {"target", {{"node", 1}, {"path", "rotation"}}}},
                            {{"sampler", 3}, {"target", {{"node", 3}, {"path", "weights"}}}}}}}};
  return s;
}

TEST(GltfImport, HandWrittenStepCubicQuantizedAndWeights) {
  const std::string path = makeSynthetic().write("synthetic.gltf");
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  const Skeleton& s = a.skeleton;
  ASSERT_EQ(s.jointCount(), 4u);  // no skin: every node of the scene
  EXPECT_EQ(s.names, (std::vector<std::string>{"root", "arm", "hand", "face"}));
  EXPECT_EQ(s.parents, (std::vector<int>{-1, 0, 1, 0}));
  EXPECT_NEAR(s.restPose[2].translation.y, 0.5f, 1e-6f);
  ASSERT_EQ(a.clips.size(), 1u);
  const Clip& c = a.clips[0];
  EXPECT_EQ(c.name, "Synthetic");
  EXPECT_FLOAT_EQ(c.duration, 2.0f);
  ASSERT_EQ(c.tracks.size(), 2u);
  const JointTrack& arm = c.tracks[0];
  EXPECT_EQ(arm.joint, 1);
  EXPECT_EQ(arm.translation.interpolation, Interpolation::Step);
  ASSERT_EQ(arm.translation.values.size(), 3u);
  EXPECT_FLOAT_EQ(arm.translation.values[2].x, 3.0f);
  ASSERT_EQ(arm.rotation.values.size(), 3u);
  EXPECT_EQ(arm.rotation.interpolation, Interpolation::Linear);
  const glm::quat q1 = arm.rotation.values[1];  // stored x,y,z,w = 0, .7071, 0, .7071
  EXPECT_NEAR(q1.w, 0.70711f, 1e-4f);
  EXPECT_NEAR(q1.y, 0.70711f, 1e-4f);
  EXPECT_NEAR(q1.x, 0.0f, 1e-6f);
  EXPECT_NEAR(arm.rotation.values[2].y, 1.0f, 1e-4f);
  EXPECT_NEAR(arm.rotation.values[2].w, 0.0f, 1e-4f);
  const JointTrack& hand = c.tracks[1];
  EXPECT_EQ(hand.joint, 2);
  EXPECT_EQ(hand.translation.interpolation, Interpolation::CubicSpline);
  ASSERT_EQ(hand.translation.times.size(), 3u);
  ASSERT_EQ(hand.translation.values.size(), 9u);  // in-tangent, value, out-tangent per key, as stored
  for (int k = 0; k < 3; ++k)
    for (int part = 0; part < 3; ++part)
      EXPECT_FLOAT_EQ(hand.translation.values[static_cast<std::size_t>(k * 3 + part)].x,
                      static_cast<float>(10 * k + part + 1));
  ASSERT_EQ(c.morphTracks.size(), 1u);
  EXPECT_EQ(c.morphTracks[0].targets, std::vector<int>{0});
  EXPECT_EQ(c.morphTracks[0].weights, (std::vector<float>{0.0f, 1.0f, 0.5f}));
  EXPECT_EQ(a.morphTargets, std::vector<std::string>{"smile"});
  ASSERT_EQ(a.meshes.size(), 1u);
  const MeshPrimitive& p = a.meshes[0].primitives.at(0);
  EXPECT_TRUE(a.meshes[0].skinned);  // rigid mesh bound to its own node's joint
  EXPECT_EQ(p.joints.at(0).x, 3);
  EXPECT_FLOAT_EQ(p.positions.at(1).x, 1.0f);
  EXPECT_FLOAT_EQ(p.morphTargets.at(0).positions.at(0).z, 0.5f);
  expectMeshesConsistent(a);
  expectValid(a);
  expectAllFinite(a);

  ImportOptions twice;
  twice.extraScale = 2.0f;
  ImportResult r2 = importOk(path, twice);
  ASSERT_TRUE(r2.asset);
  const Asset& b = *r2.asset;
  EXPECT_FLOAT_EQ(b.skeleton.restPose[2].translation.y, 1.0f);
  EXPECT_FLOAT_EQ(b.clips[0].tracks[0].translation.values[2].x, 6.0f);
  EXPECT_FLOAT_EQ(b.clips[0].tracks[1].translation.values[0].x, 2.0f);  // cubic tangents scale too
  EXPECT_FLOAT_EQ(b.clips[0].tracks[1].translation.values[2].x, 6.0f);
  EXPECT_FLOAT_EQ(b.meshes[0].primitives[0].positions[1].x, 2.0f);
  EXPECT_FLOAT_EQ(b.meshes[0].primitives[0].morphTargets[0].positions[0].z, 1.0f);
  EXPECT_FLOAT_EQ(b.clips[0].morphTracks[0].weights[1], 1.0f);  // weights are not lengths
  std::filesystem::remove(path);
}

// Replaces the morph target's deltas by a sparse accessor (no buffer view: zeros)
// that sets vertex `vertex` to (0, 0, 0.25).
void makeSparseDelta(Synthetic& s, std::uint16_t vertex) {
  const int indices = s.block(std::vector<std::uint16_t>{vertex}, kUShort, "SCALAR", 1);
  const int values = s.block(std::vector<float>{0.0f, 0.0f, 0.25f}, kFloat, "VEC3", 1);
  s.doc["accessors"][6] = {{"componentType", kFloat},
                           {"count", 3},
                           {"type", "VEC3"},
                           {"sparse",
                            {{"count", 1},
                             {"indices", {{"bufferView", indices}, {"componentType", kUShort}}},
                             {"values", {{"bufferView", values}}}}}};
}

TEST(GltfImport, HandWrittenSparseMorphTarget) {
  Synthetic s = makeSynthetic();
  makeSparseDelta(s, 2);
  const std::string path = s.write("sparse.gltf");
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const auto& deltas = r.asset->meshes.at(0).primitives.at(0).morphTargets.at(0).positions;
  ASSERT_EQ(deltas.size(), 3u);
  EXPECT_EQ(deltas[0], glm::vec3(0.0f));
  EXPECT_EQ(deltas[1], glm::vec3(0.0f));
  EXPECT_EQ(deltas[2], glm::vec3(0.0f, 0.0f, 0.25f));
  std::filesystem::remove(path);
}

TEST(GltfImport, HandWrittenMaterialAndVrm1Humanoid) {
  Synthetic s = makeSynthetic();
  s.doc["images"] = {{{"uri", "skin%20texture.png"}}};
  s.doc["textures"] = {{{"source", 0}}};
  s.doc["materials"] = {
      {{"name", "skin"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.5, 0.25, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}}};
  s.doc["meshes"][0]["primitives"][0]["material"] = 0;
  s.doc["extensionsUsed"].push_back("VRMC_vrm");
  s.doc["extensions"] = {
      {"VRMC_vrm",
       {{"specVersion", "1.0"},
        {"humanoid", {{"humanBones", {{"hips", {{"node", 0}}}, {"leftUpperArm", {{"node", 1}}}}}}},
        {"expressions",
         {{"preset", {{"aa", {{"morphTargetBinds", {{{"node", 3}, {"index", 0}, {"weight", 0.8}}}}}}}},
          {"custom", {{"grin", {{"morphTargetBinds", {{{"node", 3}, {"index", 0}, {"weight", 1.0}}}}}}}}}}}}};
  const std::string path = s.write("vrm1.gltf");
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Asset& a = *r.asset;
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(a.materials[0].name, "skin");
  EXPECT_EQ(a.materials[0].baseColor, glm::vec4(1.0f, 0.5f, 0.25f, 1.0f));
  EXPECT_EQ(a.materials[0].baseColorTexture, (std::filesystem::path(path).parent_path() / "skin texture.png").string());
  EXPECT_EQ(a.meshes[0].primitives[0].material, 0);
  ASSERT_TRUE(a.hasHumanoid);
  EXPECT_EQ(a.humanoid.bones, (std::map<std::string, std::string>{{"hips", "root"}, {"leftUpperArm", "arm"}}));
  const auto& ex = a.humanoid.expressions;
  for (const char* key : {"aa", "A"}) {
    ASSERT_TRUE(ex.count(key)) << key;
    ASSERT_EQ(ex.at(key).size(), 1u);
    EXPECT_EQ(ex.at(key)[0].first, 0);
    EXPECT_FLOAT_EQ(ex.at(key)[0].second, 0.8f);
  }
  ASSERT_TRUE(ex.count("grin"));
  std::filesystem::remove(path);
}

// Skin joints `b` (listed first) and `a`, with the plain node `mid` between
// them and `root` above; no inverseBindMatrices (identity, allowed by glTF).
TEST(GltfImport, HandWrittenSkinWithIntermediateNode) {
  Synthetic s;
  s.doc = {{"asset", {{"version", "2.0"}}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0, 4}}}}},
           {"nodes",
            {{{"name", "root"}, {"children", {1}}, {"translation", {0.0, 0.0, 5.0}}},
             {{"name", "a"}, {"children", {2}}, {"translation", {0.0, 1.0, 0.0}}},
             {{"name", "mid"}, {"children", {3}}, {"translation", {0.0, 1.0, 0.0}}},
             {{"name", "b"}, {"translation", {0.0, 1.0, 0.0}}},
             {{"name", "body"}, {"mesh", 0}, {"skin", 0}}}},
           {"skins", {{{"joints", {3, 1}}}}},
           {"accessors", nlohmann::json::array()},
           {"bufferViews", nlohmann::json::array()}};
  const int pos = s.block(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kFloat, "VEC3", 3);
  const int joints = s.block(std::vector<std::uint8_t>{0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}, 5121, "VEC4", 3);
  const int weights =
      s.block(std::vector<std::uint8_t>{128, 127, 0, 0, 255, 0, 0, 0, 51, 51, 0, 0}, 5121, "VEC4", 3, true);
  s.doc["meshes"] = {
      {{"name", "body"},
       {"primitives", {{{"attributes", {{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}}}}}};
  const std::string path = s.write("skin_intermediate.gltf");
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  const Skeleton& sk = r.asset->skeleton;
  EXPECT_EQ(sk.names, (std::vector<std::string>{"a", "mid", "b"}));
  EXPECT_EQ(sk.parents, (std::vector<int>{-1, 0, 1}));
  EXPECT_EQ(sk.skinned, (std::vector<std::uint8_t>{1, 0, 1}));
  EXPECT_EQ(sk.inverseBind[2], glm::mat4(1.0f));
  EXPECT_EQ(glm::vec3(sk.rootTransform[3]), glm::vec3(0.0f, 0.0f, 5.0f));  // `root` is above the skeleton
  EXPECT_NEAR(restPosition(sk, "b").y, 3.0f, 1e-6f);
  const MeshPrimitive& p = r.asset->meshes.at(0).primitives.at(0);
  EXPECT_EQ(p.joints[0], glm::u16vec4(2, 0, 2, 2));             // skin joint 0 is `b` (skeleton 2), 1 is `a` (0)
  EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{0, 1, 2}));  // generated: no index accessor
  expectMeshesConsistent(*r.asset);  // includes weights renormalized to sum 1 (0.2 + 0.2 here)
  EXPECT_NEAR(p.weights[2].x, 0.5f, 1e-6f);
  expectValid(*r.asset);
  std::filesystem::remove(path);
}

TEST(GltfImport, HandWrittenDuplicateKeyTimesAreDroppedWithAWarning) {
  const std::string path = makeSynthetic({0.0f, 1.0f, 1.0f}).write("duplicate_times.gltf");
  ImportResult r = importOk(path);
  ASSERT_TRUE(r.asset);
  EXPECT_TRUE(r.diagnostics.hasWarnings());
  EXPECT_NE(r.diagnostics.format().find("dropped 1 key"), std::string::npos) << r.diagnostics.format();
  const Clip& c = r.asset->clips.at(0);
  EXPECT_EQ(c.tracks[0].translation.times, (std::vector<float>{0.0f, 1.0f}));
  EXPECT_EQ(c.tracks[1].translation.values.size(), 6u);
  EXPECT_FLOAT_EQ(c.duration, 1.0f);
  expectValid(*r.asset);
  std::filesystem::remove(path);
}

// Each mutation breaks one thing; the import must fail naming it.
TEST(GltfImport, HandWrittenBrokenFilesAreRejected) {
  struct Case {
    const char* name;
    std::function<void(Synthetic&)> breakIt;
    const char* mentions;
  };
  const std::vector<Case> cases = {
      {"decreasing_times",
       [](Synthetic& s) {
         s = makeSynthetic({0.0f, 2.0f, 1.0f});
       },
       "animation 'Synthetic' channel 0: key 2 time"},
      {"past_view", [](Synthetic& s) { s.doc["accessors"][2]["count"] = 12; },
       "accessor 2 (animation 'Synthetic' channel 1 output) reads past the end of buffer view 2"},
      {"view_past_buffer", [](Synthetic& s) { s.doc["bufferViews"][1]["byteLength"] = 4000; },
       "extends past the end of buffer 0"},
      {"index_out_of_range",
       [](Synthetic& s) { s.buffer[s.doc["bufferViews"][7]["byteOffset"].get<std::size_t>()] = 7; },
       "mesh 'tri' primitive 0: vertex index 7"},
      {"nan_key",
       [](Synthetic& s) {
         const float nan = NAN;
         std::memcpy(&s.buffer[s.doc["bufferViews"][1]["byteOffset"].get<std::size_t>() + 4], &nan, 4);
       },
       "accessor 1 (animation 'Synthetic' channel 0 output) element 0 component 1 is not finite"},
      {"missing_child", [](Synthetic& s) { s.doc["nodes"][1]["children"] = {9}; }, "has child 9, which does not exist"},
      {"skin_joint",
       [](Synthetic& s) {
         s.doc["skins"] = {{{"joints", {1, 42}}}};
       },
       "skin 0 joint 1 refers to node 42"},
      {"bad_sampler", [](Synthetic& s) { s.doc["animations"][0]["channels"][0]["sampler"] = 7; },
       "channel 0 refers to sampler 7"},
      {"bad_translation",
       [](Synthetic& s) {
         s.doc["nodes"][2]["translation"] = {1.0, 2.0};
       },
       "node 2 'hand' translation must be 3 finite numbers"},
      {"unsupported_required",
       [](Synthetic& s) { s.doc["extensionsRequired"].push_back("KHR_draco_mesh_compression"); },
       "KHR_draco_mesh_compression"},
      {"rotation_as_vec3", [](Synthetic& s) { s.doc["animations"][0]["samplers"][2]["output"] = 1; },
       "has type VEC3, expected VEC4"},
      {"two_parents",
       [](Synthetic& s) {
         s.doc["nodes"][0]["children"] = {1, 2, 3};
       },
       "is a child of both"},
      {"not_json", [](Synthetic& s) { s.doc = "just a string"; }, "the top level must be a JSON object"},
      {"huge_zero_accessor",
       [](Synthetic& s) {
         s.doc["accessors"][6].erase("bufferView");
         s.doc["accessors"][6]["count"] = 1 << 25;
       },
       "accessor 6 (mesh 'tri' primitive 0 morph target 0 POSITION) has no buffer view and an implausible count"},
      {"sparse_index_out_of_range", [](Synthetic& s) { makeSparseDelta(s, 5); }, "sparse index 0 (5"},
      {"count_over_the_limit", [](Synthetic& s) { s.doc["accessors"][2]["count"] = (1 << 26) + 1; },
       "accessor 2 (animation 'Synthetic' channel 1 output) has 67108865 elements, more than the 67108864 one array "
       "may have (limits::kMaxArrayElements)"},
      {"nodes_over_the_limit",
       [](Synthetic& s) {
         while (s.doc["nodes"].size() <= 65535) s.doc["nodes"].push_back(nlohmann::json::object());
       },
       "the file has 65536 nodes, more than the 65535 a skeleton may have (limits::kMaxJoints)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Synthetic s = makeSynthetic();
    c.breakIt(s);
    const std::string path = s.write(std::string(c.name) + ".gltf");
    expectRejected(path, c.mentions);
    std::filesystem::remove(path);
  }
  // Not JSON at all.
  const std::string garbage = tempPath("garbage.gltf");
  std::ofstream(garbage) << "{ \"asset\": ";
  expectRejected(garbage, "invalid JSON");
  // Deep enough to overflow the stack of a recursive JSON walker (tinygltf's extras reader is one).
  std::ofstream(garbage) << R"({"asset":{"version":"2.0"},"extras":)" << std::string(200000, '[')
                         << std::string(200000, ']') << "}";
  expectRejected(garbage, "levels deep");
  std::filesystem::remove(garbage);
}

}  // namespace
}  // namespace marionette

namespace marionette {

// A model file reads nothing outside its own folder unless the caller allows it, and
// the error names the path without telling anything of the file (its size, its bytes).
TEST(GltfImport, BuffersAndImagesOutsideTheModelFolderAreNotRead) {
  const std::string cube = test::assimpModel("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  MARIONETTE_REQUIRE_FILE(cube);
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("marionette_outside_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "model");
  fs::copy_file(fs::path(cube).parent_path() / "AnimatedMorphCube.bin", dir / "AnimatedMorphCube.bin");
  const std::string text = test::readFile(cube);
  auto withUri = [&](const std::string& uri) {
    std::string t = text;
    t.replace(t.find("AnimatedMorphCube.bin"), std::strlen("AnimatedMorphCube.bin"), uri);
    const fs::path path = dir / "model" / "cube.gltf";
    std::ofstream(path) << t;
    return path.string();
  };
  const fs::path before = fs::current_path();
  for (const std::string& uri :
       {std::string("../../../../../../../../etc/passwd"), std::string("/etc/passwd"), std::string("../AnimatedMorphCube.bin")}) {
    SCOPED_TRACE(uri);
    // By an absolute path, and by a path relative to the current folder (then tinygltf
    // joins an absolute uri to nothing and asks for /etc/passwd itself).
    for (const bool relative : {false, true}) {
      const std::string path = withUri(uri);
      fs::current_path(dir / "model");
      const ImportResult r = importAsset(relative ? std::string("cube.gltf") : path);
      fs::current_path(before);
      EXPECT_FALSE(r.ok()) << relative;
      const std::string d = r.diagnostics.format();
      EXPECT_NE(d.find("cube.gltf"), std::string::npos) << d;
      if (relative || uri[0] == '.') {  // an absolute uri under an absolute folder is looked for inside it
        EXPECT_NE(d.find("is outside the model's folder"), std::string::npos) << d;
      }
      EXPECT_EQ(d.find("root:"), std::string::npos) << "the error shows the file's content: " << d;
      EXPECT_EQ(d.find("size"), std::string::npos) << "the error tells the file's size: " << d;
    }
  }
  // Allowed by the caller: the buffer beside the folder is read and the cube loads.
  ImportOptions trusted;
  trusted.allowFilesOutsideModelFolder = true;
  const ImportResult r = importAsset(withUri("../AnimatedMorphCube.bin"), trusted);
  EXPECT_TRUE(r.ok()) << r.diagnostics.format();
  // And inside the folder (a subfolder too) nothing changes.
  fs::create_directories(dir / "model" / "data");
  fs::copy_file(dir / "AnimatedMorphCube.bin", dir / "model" / "data" / "cube.bin");
  const ImportResult inside = importAsset(withUri("data/cube.bin"));
  EXPECT_TRUE(inside.ok()) << inside.diagnostics.format();
  fs::remove_all(dir);
}
}  // namespace marionette
