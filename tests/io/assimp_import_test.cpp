// Tests of the Assimp importer (FBX, BVH, COLLADA, MD5, X) against real files:
// the shared Pab / CMU assets and Debian's assimp-testmodels. Missing data fails.
#ifdef MARIONETTE_HAS_ASSIMP

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "marionette/animation/clip_binding.hpp"
#include "marionette/io/import.hpp"
#include "test_data.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;
using test::assimpModel;
using test::sharedAsset;

// The 53 skin bones of the Pab skeleton (ASSETS.md), with its spelling quirks.
const std::vector<std::string> kPabBones = {
    "Pelvis", "Spine", "Spine1", "Spine2", "Spine3", "Neck", "Head", "LeftShoulder", "LeftArm", "LeftForeArm",
    "Lefthand", "LeftHandThumb1", "LeftHandThumb2", "LeftHandThumb3", "LeftHandIndex1", "LeftHandIndex2",
    "LeftHandIndex3", "LeftHandMiddle1", "LeftHandMiddle2", "LeftHandMiddle3", "LeftHandRing1", "LeftHandRing2",
    "LeftHandRing3", "LeftHandRingPinky1", "LeftHandRingPinky2", "LeftHandRingPinky3", "RightShoulder", "RightArm",
    "RightForeArm", "RightHand", "RightHandThumb1", "RightHandThumb2", "RightHandThumb3", "RightHandIndex1",
    "RightHandIndex2", "RightHandIndex3", "RightHandMiddle1", "RightHandMiddle2", "RightHandMiddle3",
    "RightHandRing1", "RightHandRing2", "RightHandRing3", "RightHandPinky1", "RightHandPinky2", "RightHandPinky3",
    "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftFootThumb1", "RightUpLeg", "RightLeg", "RightFoot",
    "RightFootThumb1"};

constexpr float kDurationTolerance = 0.002f;  // seconds

// ---------------------------------------------------------------- helpers

ImportResult load(const std::string& path, ImportOptions options = {}) { return importAsset(path, options); }

bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }
bool finite(const glm::quat& q) { return finite(glm::vec3(q.x, q.y, q.z)) && std::isfinite(q.w); }
bool finite(const glm::mat4& m) { return finite(m[0]) && finite(m[1]) && finite(m[2]) && finite(m[3]); }

template <class T>
void expectTrackFinite(const Track<T>& track, const std::string& where) {
  for (float t : track.times) ASSERT_TRUE(std::isfinite(t)) << where;
  for (const T& v : track.values) ASSERT_TRUE(finite(v)) << where;
}

void expectAllFinite(const Asset& asset) {
  const Skeleton& s = asset.skeleton;
  ASSERT_TRUE(finite(s.rootTransform));
  for (std::size_t j = 0; j < s.jointCount(); ++j) {
    ASSERT_TRUE(finite(s.restPose[j].translation) && finite(s.restPose[j].rotation) && finite(s.restPose[j].scale))
        << s.names[j];
    ASSERT_TRUE(finite(s.inverseBind[j])) << s.names[j];
  }
  for (const Clip& clip : asset.clips) {
    ASSERT_TRUE(std::isfinite(clip.duration)) << clip.name;
    for (const JointTrack& jt : clip.tracks) {
      const std::string where = clip.name + " joint " + std::to_string(jt.joint);
      expectTrackFinite(jt.translation, where);
      expectTrackFinite(jt.rotation, where);
      expectTrackFinite(jt.scale, where);
    }
  }
  for (const Mesh& mesh : asset.meshes)
    for (const MeshPrimitive& p : mesh.primitives) {
      for (const auto& v : p.positions) ASSERT_TRUE(finite(v)) << mesh.name;
      for (const auto& v : p.normals) ASSERT_TRUE(finite(v)) << mesh.name;
      for (const auto& v : p.uvs) ASSERT_TRUE(finite(v)) << mesh.name;
      for (const auto& v : p.weights) ASSERT_TRUE(finite(v)) << mesh.name;
      for (const MorphTargetDelta& d : p.morphTargets) {
        for (const auto& v : d.positions) ASSERT_TRUE(finite(v)) << mesh.name;
        for (const auto& v : d.normals) ASSERT_TRUE(finite(v)) << mesh.name;
      }
    }
  for (const Material& m : asset.materials) ASSERT_TRUE(finite(m.baseColor)) << m.name;
}

// Sizes agree, triangles index real vertices, skin weights are normalized and
// point into the skeleton.
void expectMeshesConsistent(const Asset& asset) {
  const std::size_t joints = asset.skeleton.jointCount();
  for (const Mesh& mesh : asset.meshes) {
    ASSERT_FALSE(mesh.primitives.empty()) << mesh.name;
    for (const MeshPrimitive& p : mesh.primitives) {
      const std::size_t n = p.positions.size();
      ASSERT_GT(n, 0u) << mesh.name;
      ASSERT_TRUE(p.normals.empty() || p.normals.size() == n) << mesh.name;
      ASSERT_TRUE(p.uvs.empty() || p.uvs.size() == n) << mesh.name;
      ASSERT_EQ(p.indices.size() % 3, 0u) << mesh.name;
      for (std::uint32_t i : p.indices) ASSERT_LT(i, n) << mesh.name;
      ASSERT_EQ(p.morphTargets.size(), mesh.morphTargets.size()) << mesh.name;
      ASSERT_LT(p.material, static_cast<int>(asset.materials.size())) << mesh.name;
      if (!mesh.skinned) continue;
      ASSERT_EQ(p.joints.size(), n) << mesh.name;
      ASSERT_EQ(p.weights.size(), n) << mesh.name;
      for (std::size_t v = 0; v < n; ++v) {
        const glm::vec4& w = p.weights[v];
        ASSERT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-4f) << mesh.name << " vertex " << v;
        for (int k = 0; k < 4; ++k) {
          ASSERT_GE(w[k], 0.0f) << mesh.name << " vertex " << v;
          ASSERT_LT(p.joints[v][k], joints) << mesh.name << " vertex " << v;
        }
      }
    }
  }
}

// What every successful import must satisfy.
void expectSound(const ImportResult& r, const std::string& path) {
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  ASSERT_TRUE(r.asset.has_value());
  const Asset& a = *r.asset;
  EXPECT_EQ(a.sourcePath, path);
  EXPECT_GT(a.skeleton.jointCount(), 0u);
  EXPECT_EQ(a.skeleton.validate(), "");
  for (const Clip& c : a.clips) EXPECT_EQ(c.validate(a.skeleton.jointCount()), "") << c.name;
  expectAllFinite(a);
  expectMeshesConsistent(a);
}

void expectErrorNamingFile(const ImportResult& r, const std::string& path) {
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(r.asset.has_value());
  ASSERT_FALSE(r.diagnostics.items.empty()) << path;
  EXPECT_FALSE(r.diagnostics.ok()) << r.diagnostics.format();
  for (const Diagnostic& d : r.diagnostics.items) EXPECT_EQ(d.file, path) << d.format();
}

glm::vec3 restPosition(const Skeleton& s, const std::string& joint) {
  const int j = s.findJoint(joint);
  EXPECT_GE(j, 0) << joint;
  return j < 0 ? glm::vec3(NAN) : glm::vec3(s.restModelMatrices()[static_cast<std::size_t>(j)][3]);
}

// Bind-pose position from the inverse bind matrix (a skinned joint only).
glm::vec3 bindPosition(const Skeleton& s, const std::string& joint) {
  const int j = s.findJoint(joint);
  EXPECT_GE(j, 0) << joint;
  return j < 0 ? glm::vec3(NAN) : glm::vec3(glm::inverse(s.inverseBind[static_cast<std::size_t>(j)])[3]);
}

float degreesBelowHorizontal(const glm::vec3& from, const glm::vec3& to) {
  const glm::vec3 d = to - from;
  return glm::degrees(std::atan2(-d.y, std::sqrt(d.x * d.x + d.z * d.z)));
}

// What a BVH file says about itself: joint names in file order, frames, frame time.
struct BvhFacts {
  std::vector<std::string> joints;
  int frames = 0;
  double frameTime = 0.0;
};

BvhFacts readBvhFacts(const std::string& path) {
  BvhFacts facts;
  std::ifstream in(path);
  std::string word;
  while (in >> word) {
    if (word == "ROOT" || word == "JOINT") {
      std::string name;
      in >> name;
      facts.joints.push_back(name);
    } else if (word == "Frames:") {
      in >> facts.frames;
    } else if (word == "Time:") {
      in >> facts.frameTime;
      break;
    }
  }
  return facts;
}

std::string tempPath(const std::string& name) {
  return (fs::temp_directory_path() / ("marionette_assimp_test_" + name)).string();
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A two-joint BVH whose motion section is given by the caller.
std::string twoJointBvh(const std::string& motion) {
  return "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"
         "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
         "  JOINT Chest\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
         "    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\n" +
         motion;
}

bool mentions(const Diagnostics& d, Severity severity, const std::string& text) {
  for (const Diagnostic& item : d.items)
    if (item.severity == severity && item.message.find(text) != std::string::npos) return true;
  return false;
}

// ---------------------------------------------------------------- Pab (FBX)

TEST(AssimpImport, PabArnaudHasAll53NamedSkinnedBones) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Skeleton& s = r.asset->skeleton;
  EXPECT_NEAR(r.asset->unitScale, 0.01f, 1e-6f);
  // 53 skin bones plus their non-skin parent Hips.
  EXPECT_EQ(s.jointCount(), 54u);
  for (const std::string& bone : kPabBones) {
    const int j = s.findJoint(bone);
    ASSERT_GE(j, 0) << bone;
    EXPECT_EQ(s.skinned[static_cast<std::size_t>(j)], 1) << bone;
  }
  EXPECT_GE(s.findJoint("Lefthand"), 0);
  EXPECT_GE(s.findJoint("LeftHandRingPinky1"), 0);
  EXPECT_EQ(s.findJoint("LeftHand"), -1);  // the file's spelling is kept
  const int hips = s.findJoint("Hips");
  ASSERT_EQ(hips, 0);
  EXPECT_EQ(s.parents[0], -1);
  EXPECT_EQ(s.skinned[0], 0);
  EXPECT_EQ(s.parents[static_cast<std::size_t>(s.findJoint("Pelvis"))], hips);
  // The file is in bind pose: rest positions match the inverse binds (within 1 mm).
  for (const std::string& bone : kPabBones)
    EXPECT_LT(glm::length(restPosition(s, bone) - bindPosition(s, bone)), 1e-3f) << bone;
}

TEST(AssimpImport, PabArnaudProportionsInMetres) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Skeleton& s = r.asset->skeleton;
  float lowest = INFINITY;
  for (const glm::mat4& m : s.restModelMatrices()) lowest = std::min(lowest, m[3].y);
  EXPECT_NEAR(restPosition(s, "Head").y - lowest, 1.65f, 0.05f);
  // Relaxed T-pose: upper arm 13.7 degrees below horizontal, from the rest pose
  // and from the inverse bind matrices.
  EXPECT_NEAR(degreesBelowHorizontal(restPosition(s, "LeftArm"), restPosition(s, "LeftForeArm")), 13.7f, 3.0f);
  EXPECT_NEAR(degreesBelowHorizontal(bindPosition(s, "LeftArm"), bindPosition(s, "LeftForeArm")), 13.7f, 3.0f);
  EXPECT_NEAR(degreesBelowHorizontal(bindPosition(s, "RightArm"), bindPosition(s, "RightForeArm")), 13.7f, 3.0f);
}

TEST(AssimpImport, PabArnaudSkinnedMesh) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  ASSERT_EQ(a.meshes.size(), 1u);
  const Mesh& mesh = a.meshes[0];
  EXPECT_EQ(mesh.name, "Generic_Man_LR_polySurface1");
  EXPECT_TRUE(mesh.skinned);
  ASSERT_EQ(mesh.primitives.size(), 1u);
  const MeshPrimitive& p = mesh.primitives[0];
  EXPECT_EQ(p.indices.size(), 6670u * 3u);
  EXPECT_EQ(p.normals.size(), p.positions.size());
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(p.material, 0);
  // Vertices are in metres: the man is about 1.7 m tall and stands on y = 0.
  float minY = INFINITY, maxY = -INFINITY;
  for (const glm::vec3& v : p.positions) {
    minY = std::min(minY, v.y);
    maxY = std::max(maxY, v.y);
  }
  EXPECT_NEAR(minY, 0.0f, 0.05f);
  EXPECT_NEAR(maxY - minY, 1.75f, 0.15f);
  // Every skin bone drives some vertex.
  std::set<int> used;
  for (std::size_t v = 0; v < p.joints.size(); ++v)
    for (int k = 0; k < 4; ++k)
      if (p.weights[v][k] > 0.0f) used.insert(p.joints[v][k]);
  EXPECT_EQ(used.size(), kPabBones.size());
}

TEST(AssimpImport, PabArnaudWithoutMeshesKeepsTheSameSkeleton) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  ImportOptions options;
  options.loadMeshes = false;
  const ImportResult bare = load(path, options);
  const ImportResult full = load(path);
  expectSound(bare, path);
  expectSound(full, path);
  EXPECT_TRUE(bare.asset->meshes.empty());
  EXPECT_TRUE(bare.asset->materials.empty());
  EXPECT_EQ(bare.asset->skeleton.names, full.asset->skeleton.names);
  EXPECT_EQ(bare.asset->skeleton.parents, full.asset->skeleton.parents);
  EXPECT_EQ(bare.asset->skeleton.skinned, full.asset->skeleton.skinned);
}

TEST(AssimpImport, ExtraScaleMultipliesTheUnitConversion) {
  const std::string path = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  ImportOptions options;
  options.extraScale = 2.0f;
  const ImportResult r = load(path, options);
  expectSound(r, path);
  EXPECT_NEAR(r.asset->unitScale, 0.02f, 1e-6f);
  EXPECT_NEAR(restPosition(r.asset->skeleton, "Head").y, 2.0f * 1.650f, 0.02f);
  EXPECT_NEAR(bindPosition(r.asset->skeleton, "Head").y, 2.0f * 1.650f, 0.02f);

  options.extraScale = 0.0f;
  expectErrorNamingFile(load(path, options), path);
  options.extraScale = NAN;
  expectErrorNamingFile(load(path, options), path);
}

struct PabMotion {
  const char* file;
  const char* clip;
  float seconds;  // frames / 30 fps, as Assimp reports them (ASSETS.md)
};

TEST(AssimpImport, PabMotionsHaveTheirDurationsAndBindOntoArnaud) {
  const std::string arnaudPath = sharedAsset("characters/pab_arnaud.fbx");
  MARIONETTE_REQUIRE_FILE(arnaudPath);
  const ImportResult arnaud = load(arnaudPath);
  expectSound(arnaud, arnaudPath);
  const Skeleton& target = arnaud.asset->skeleton;
  ImportOptions motionOnly;
  motionOnly.loadMeshes = false;
  for (const PabMotion& m : {PabMotion{"pab_walk.fbx", "walk", 40.0f / 30.0f},
                             PabMotion{"pab_jog.fbx", "jog", 24.0f / 30.0f},
                             PabMotion{"pab_crossarms.fbx", "crossarms", 258.0f / 30.0f}}) {
    SCOPED_TRACE(m.file);
    const std::string path = sharedAsset(std::string("motions/fbx/") + m.file);
    MARIONETTE_REQUIRE_FILE(path);
    const ImportResult r = load(path, motionOnly);
    expectSound(r, path);
    const Asset& a = *r.asset;
    EXPECT_NEAR(a.unitScale, 0.01f, 1e-6f);
    EXPECT_TRUE(a.meshes.empty());
    EXPECT_GE(a.skeleton.findJoint("Bip01 Footsteps"), 0);  // extra nodes come along
    ASSERT_EQ(a.clips.size(), 1u);
    const Clip& clip = a.clips[0];
    EXPECT_EQ(clip.name, m.clip);
    EXPECT_NEAR(clip.duration, m.seconds, kDurationTolerance);
    // Translations are in metres: the hips stay about a metre above the ground.
    const int hips = a.skeleton.findJoint("Hips");
    ASSERT_GE(hips, 0);
    for (const JointTrack& jt : clip.tracks) {
      if (jt.joint != hips) continue;
      for (const glm::vec3& t : jt.translation.values) EXPECT_NEAR(t.y, 1.0f, 0.3f);
    }

    int unmatched = -1;
    const Clip bound = bindClipByName(clip, a.skeleton, target, &unmatched);
    EXPECT_EQ(bound.validate(target.jointCount()), "");
    std::set<std::string> driven;
    for (const JointTrack& jt : bound.tracks) driven.insert(target.names[static_cast<std::size_t>(jt.joint)]);
    for (const std::string& bone : kPabBones) EXPECT_TRUE(driven.count(bone)) << bone;
    EXPECT_EQ(unmatched + static_cast<int>(bound.tracks.size()), static_cast<int>(clip.tracks.size()));
  }
}

TEST(AssimpImport, TruncatedFbxIsAnError) {
  const std::string source = sharedAsset("motions/fbx/pab_walk.fbx");
  MARIONETTE_REQUIRE_FILE(source);
  std::ifstream in(source, std::ios::binary);
  std::string head(4000, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  ASSERT_EQ(in.gcount(), 4000);
  const std::string path = tempPath("truncated.fbx");
  writeFile(path, head);
  const ImportResult r = load(path);
  expectErrorNamingFile(r, path);
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Error, "Assimp")) << r.diagnostics.format();
  fs::remove(path);
}

// ---------------------------------------------------------------- BVH

struct BvhCase {
  std::string path;
  std::size_t joints;  // ROOT + JOINT count (ASSETS.md)
  std::vector<std::string> firstJoints;
};

TEST(AssimpImport, BvhSkeletonsAreTheFilesJointsWithoutEndSites) {
  const std::vector<BvhCase> cases = {
      {sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), 31,
       {"Hips", "LHipJoint", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase", "RHipJoint"}},
      {sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), 31,
       {"Hips", "LHipJoint", "LeftHip", "LeftKnee", "LeftAnkle", "LeftToe", "RHipJoint"}},
      {sharedAsset("motions/bvh/pirouette.bvh"), 43, {"hip", "abdomen", "chest", "neck", "head", "leftEye"}},
      {assimpModel("BVH/01_01.bvh"), 31, {"Hips", "LHipJoint", "LeftUpLeg"}},
      {assimpModel("BVH/Boxing_Toes.bvh"), 21, {"Hips", "Ab", "Chest", "Neck", "Head"}},
  };
  for (const BvhCase& c : cases) {
    SCOPED_TRACE(c.path);
    MARIONETTE_REQUIRE_FILE(c.path);
    const BvhFacts facts = readBvhFacts(c.path);
    ASSERT_EQ(facts.joints.size(), c.joints);
    const ImportResult r = load(c.path);
    expectSound(r, c.path);
    const Asset& a = *r.asset;
    EXPECT_EQ(a.unitScale, 1.0f);
    EXPECT_TRUE(a.meshes.empty());  // no generated stick-figure mesh
    const Skeleton& s = a.skeleton;
    EXPECT_EQ(s.jointCount(), c.joints);
    EXPECT_EQ(s.names, facts.joints);  // same names, same (depth-first) order
    for (std::size_t i = 0; i < c.firstJoints.size(); ++i) EXPECT_EQ(s.names[i], c.firstJoints[i]);
    EXPECT_EQ(s.parents[0], -1);
    for (std::size_t j = 1; j < s.jointCount(); ++j) EXPECT_GE(s.parents[j], 0) << s.names[j];

    // One key per frame; the last key at (frames - 1) * frame time.
    ASSERT_EQ(a.clips.size(), 1u);
    const Clip& clip = a.clips[0];
    EXPECT_EQ(clip.tracks.size(), c.joints);
    EXPECT_NEAR(clip.duration, (facts.frames - 1) * facts.frameTime, kDurationTolerance);
    for (const JointTrack& jt : clip.tracks) {
      EXPECT_EQ(jt.rotation.keyCount(), static_cast<std::size_t>(facts.frames)) << s.names[jt.joint];
      EXPECT_TRUE(jt.scale.empty()) << "BVH has no scale; the constant track is dropped";
    }
  }
}

TEST(AssimpImport, BvhDurationsMatchAssetsTable) {
  // (frames - 1) * frame time: 2752, 994 and 592 frames at 120 fps.
  const std::vector<std::pair<std::string, float>> cases = {
      {sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), 2751 * 0.0083333f},
      {sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), 993 * 0.0083333f},
      {sharedAsset("motions/bvh/pirouette.bvh"), 591 * 0.00833333f},
  };
  for (const auto& [path, seconds] : cases) {
    MARIONETTE_REQUIRE_FILE(path);
    ImportOptions options;
    options.loadMeshes = false;
    const ImportResult r = load(path, options);
    ASSERT_TRUE(r.ok()) << r.diagnostics.format();
    ASSERT_EQ(r.asset->clips.size(), 1u);
    EXPECT_NEAR(r.asset->clips[0].duration, seconds, kDurationTolerance) << path;
  }
}

TEST(AssimpImport, Cmu131ArmsHangDownAtRest) {
  const std::string path = sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Skeleton& s = r.asset->skeleton;
  const glm::vec3 dir = glm::normalize(restPosition(s, "LeftElbow") - restPosition(s, "LeftShoulder"));
  EXPECT_LT(dir.y, -0.99f);
  EXPECT_NEAR(degreesBelowHorizontal(restPosition(s, "LeftShoulder"), restPosition(s, "LeftElbow")), 90.0f, 1.0f);
}

TEST(AssimpImport, Cmu0101IsTPoseAndScalesWithExtraScale) {
  const std::string path = sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult plain = load(path);
  expectSound(plain, path);
  const Skeleton& s = plain.asset->skeleton;
  EXPECT_NEAR(degreesBelowHorizontal(restPosition(s, "LeftArm"), restPosition(s, "LeftForeArm")), 0.0f, 1.0f);
  // LeftArm -> LeftForeArm OFFSET is 4.983 units along +X.
  const auto leftForeArm = static_cast<std::size_t>(s.findJoint("LeftForeArm"));
  EXPECT_NEAR(s.restPose[leftForeArm].translation.x, 4.983f, 1e-3f);

  ImportOptions options;
  options.extraScale = 0.056f;  // CMU units to metres, roughly
  const ImportResult scaled = load(path, options);
  expectSound(scaled, path);
  EXPECT_NEAR(scaled.asset->unitScale, 0.056f, 1e-6f);
  EXPECT_NEAR(scaled.asset->skeleton.restPose[leftForeArm].translation.x, 4.983f * 0.056f, 1e-4f);
  const JointTrack& hipsPlain = plain.asset->clips[0].tracks[0];
  const JointTrack& hipsScaled = scaled.asset->clips[0].tracks[0];
  ASSERT_EQ(hipsPlain.joint, 0);
  ASSERT_EQ(hipsScaled.translation.keyCount(), hipsPlain.translation.keyCount());
  EXPECT_NEAR(hipsScaled.translation.values[100].y, hipsPlain.translation.values[100].y * 0.056f, 1e-4f);
}

TEST(AssimpImport, BvhWithTooFewMotionValuesIsAnError) {
  const std::string path = tempPath("short_motion.bvh");
  // 9 channels, but the second frame has 7 values.
  writeFile(path, twoJointBvh("Frames: 2\nFrame Time: 0.1\n0 0 0 0 0 0 0 0 0\n0 0 0 0 0 0 0\n"));
  const ImportResult r = load(path);
  expectErrorNamingFile(r, path);
  fs::remove(path);
}

TEST(AssimpImport, BvhWithNanOrInfIsAnError) {
  for (const char* bad : {"nan", "inf", "-inf"}) {
    SCOPED_TRACE(bad);
    const std::string path = tempPath(std::string("bad_value_") + (bad[0] == '-' ? "neginf" : bad) + ".bvh");
    writeFile(path, twoJointBvh("Frames: 2\nFrame Time: 0.1\n0 0 0 0 0 0 0 0 0\n0 " + std::string(bad) +
                                " 0 0 0 0 0 0 0\n"));
    const ImportResult r = load(path);
    expectErrorNamingFile(r, path);
    EXPECT_TRUE(mentions(r.diagnostics, Severity::Error, "non-finite")) << r.diagnostics.format();
    EXPECT_TRUE(mentions(r.diagnostics, Severity::Error, "'Hips'")) << r.diagnostics.format();
    fs::remove(path);
  }
}

TEST(AssimpImport, WellFormedSmallBvh) {
  const std::string path = tempPath("small.bvh");
  writeFile(path, twoJointBvh("Frames: 3\nFrame Time: 0.5\n0 1 2 0 0 0 0 0 0\n0 1 2 90 0 0 0 0 0\n"
                              "0 1 2 0 0 0 0 0 0\n"));
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  ASSERT_EQ(a.skeleton.names, (std::vector<std::string>{"Hips", "Chest"}));
  EXPECT_NEAR(a.skeleton.restPose[1].translation.y, 10.0f, 1e-5f);
  ASSERT_EQ(a.clips.size(), 1u);
  EXPECT_NEAR(a.clips[0].duration, 1.0f, 1e-5f);
  const JointTrack& hips = a.clips[0].tracks[0];
  ASSERT_EQ(hips.rotation.keyCount(), 3u);
  EXPECT_NEAR(hips.rotation.times[1], 0.5f, 1e-6f);
  // Frame 1 turns 90 degrees about Z: (w, z) = (cos 45, sin 45), sign-agnostic.
  const glm::quat q = hips.rotation.values[1];
  EXPECT_NEAR(std::abs(q.w), std::sqrt(0.5f), 1e-4f);
  EXPECT_NEAR(std::abs(q.z), std::sqrt(0.5f), 1e-4f);
  EXPECT_NEAR(hips.translation.values[2].z, 2.0f, 1e-5f);
  fs::remove(path);
}

// ---------------------------------------------------------------- other formats

TEST(AssimpImport, DirectXSkinnedAnimatedCharacter) {
  const std::string path = assimpModel("X/BCN_Epileptic.X");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  EXPECT_GT(a.skeleton.jointCount(), 50u);
  EXPECT_GE(a.skeleton.findJoint("B_Hip_Left"), 0);
  ASSERT_EQ(a.meshes.size(), 3u);
  for (const Mesh& m : a.meshes) EXPECT_TRUE(m.skinned) << m.name;
  ASSERT_EQ(a.clips.size(), 1u);
  EXPECT_EQ(a.clips[0].name, "Epileptisch");
  EXPECT_NEAR(a.clips[0].duration, 15840.0f / 4800.0f, kDurationTolerance);  // ticks / ticks per second
  EXPECT_GT(a.clips[0].tracks.size(), 20u);
}

TEST(AssimpImport, ColladaSkinnedAnimatedBoxStartsAtZero) {
  const std::string path = assimpModel("Collada/box_nested_animation.dae");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  const int bone = a.skeleton.findJoint("Armature_Bone");
  ASSERT_GE(bone, 0);
  EXPECT_EQ(a.skeleton.skinned[static_cast<std::size_t>(bone)], 1);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_TRUE(a.meshes[0].skinned);
  EXPECT_EQ(a.meshes[0].primitives[0].indices.size(), 36u);
  ASSERT_EQ(a.clips.size(), 1u);
  const Clip& clip = a.clips[0];
  // Keys run from frame 1 to 40 at 24 fps; the clip is moved to start at 0.
  ASSERT_EQ(clip.tracks.size(), 1u);
  EXPECT_EQ(clip.tracks[0].joint, bone);
  EXPECT_EQ(clip.tracks[0].rotation.times.front(), 0.0f);
  EXPECT_NEAR(clip.duration, 39.0f / 24.0f, kDurationTolerance);
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Note, "shifted")) << r.diagnostics.format();
}

TEST(AssimpImport, Md5SkinnedMesh) {
  // The Debian test models have no .md5anim; the mesh's joints are still a skeleton.
  const std::string path = assimpModel("MD5/SimpleCube.md5mesh");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  for (const char* bone : {"root", "joint1"}) {
    const int j = a.skeleton.findJoint(bone);
    ASSERT_GE(j, 0) << bone;
    EXPECT_EQ(a.skeleton.skinned[static_cast<std::size_t>(j)], 1) << bone;
  }
  EXPECT_EQ(a.skeleton.parents[static_cast<std::size_t>(a.skeleton.findJoint("joint1"))],
            a.skeleton.findJoint("root"));
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_TRUE(a.meshes[0].skinned);
  EXPECT_EQ(a.meshes[0].primitives[0].indices.size(), 36u);
  EXPECT_TRUE(a.clips.empty());
}

TEST(AssimpImport, StaticModelUsesItsNodeTreeAndResolvesTextures) {
  const std::string path = assimpModel("Collada/duck.dae");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  EXPECT_GE(a.skeleton.jointCount(), 1u);
  EXPECT_GE(a.skeleton.findJoint("LOD3sp"), 0);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_FALSE(a.meshes[0].skinned);
  EXPECT_TRUE(a.meshes[0].primitives[0].joints.empty());
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(fs::path(a.materials[0].baseColorTexture), fs::path(assimpModel("Collada/duckCM.tga")));
  EXPECT_TRUE(fs::exists(a.materials[0].baseColorTexture));
}

// A texture path that leaves the model's folder ("../../etc/passwd", an absolute
// path) is not followed unless the caller allows it: a warning naming it, no texture.
// One beside the model, or below its folder, is kept.
TEST(AssimpImport, TexturesOutsideTheModelFolderAreNotFollowed) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("marionette_assimp_outside_" + std::to_string(::getpid()));
  fs::create_directories(dir / "maps");
  std::ofstream(dir / "maps" / "ok.png") << "not read here";
  std::ofstream(dir / "quad.mtl") << "newmtl up\nmap_Kd ../../../../etc/passwd\n"
                                  << "newmtl abs\nmap_Kd /etc/passwd\n"
                                  << "newmtl fine\nmap_Kd maps/ok.png\n";
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                  << "usemtl up\nf 1 2 3\nusemtl abs\nf 1 3 4\nusemtl fine\nf 2 3 4\n";
  const std::string path = (dir / "quad.obj").string();
  for (const bool allow : {false, true}) {
    SCOPED_TRACE(allow ? "allowed" : "refused");
    ImportOptions options;
    options.allowFilesOutsideModelFolder = allow;
    const ImportResult r = importWithAssimp(path, options);
    ASSERT_TRUE(r.asset) << r.diagnostics.format();
    std::map<std::string, std::string> texture;
    for (const Material& m : r.asset->materials) texture[m.name] = m.baseColorTexture;
    EXPECT_EQ(fs::path(texture["fine"]), dir / "maps" / "ok.png");
    const std::string all = r.diagnostics.format();
    if (allow) {
      EXPECT_EQ(fs::path(texture["abs"]), fs::path("/etc/passwd"));
      EXPECT_EQ(fs::path(texture["up"]).lexically_normal(), fs::path("/etc/passwd"));
    } else {
      EXPECT_EQ(texture["up"], "");
      EXPECT_EQ(texture["abs"], "");
      EXPECT_NE(all.find("texture '../../../../etc/passwd' is outside the model's folder"), std::string::npos) << all;
      EXPECT_NE(all.find("texture '/etc/passwd' is outside the model's folder"), std::string::npos) << all;
      EXPECT_EQ(all.find("root:"), std::string::npos) << "foreign content echoed: " << all;
    }
  }
  fs::remove_all(dir);
}

TEST(AssimpImport, EmbeddedFbxTextureIsReferencedByIndex) {
  const std::string path = assimpModel("FBX/box_orphant_embedded_texture.fbx");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = load(path);
  expectSound(r, path);
  ASSERT_EQ(r.asset->materials.size(), 1u);
  EXPECT_EQ(r.asset->materials[0].baseColorTexture, "embedded:0");
}

TEST(AssimpImport, MorphTargetsAreReadAndMorphAnimationIsSkippedWithAWarning) {
  // Through Assimp's own glTF reader (importAsset would route .gltf to tinygltf):
  // the only Debian test model with morph targets.
  const std::string path = assimpModel("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  MARIONETTE_REQUIRE_FILE(path);
  const ImportResult r = importWithAssimp(path, {});
  expectSound(r, path);
  const Asset& a = *r.asset;
  ASSERT_EQ(a.morphTargets.size(), 2u);
  EXPECT_NE(a.morphTargets[0], a.morphTargets[1]);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].morphTargets, (std::vector<int>{0, 1}));
  const MeshPrimitive& p = a.meshes[0].primitives[0];
  ASSERT_EQ(p.morphTargets.size(), 2u);
  for (const MorphTargetDelta& d : p.morphTargets) {
    ASSERT_EQ(d.positions.size(), p.positions.size());
    float largest = 0.0f;
    for (const glm::vec3& v : d.positions) largest = std::max(largest, glm::length(v));
    EXPECT_GT(largest, 0.01f);  // the targets move vertices by about 2 cm
    EXPECT_LT(largest, 0.1f);
  }
  ASSERT_EQ(a.clips.size(), 1u);
  EXPECT_TRUE(a.clips[0].tracks.empty());
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Warning, "morph")) << r.diagnostics.format();
}

TEST(AssimpImport, LoadAnimationsFalseKeepsTheSkeleton) {
  const std::string path = assimpModel("X/BCN_Epileptic.X");
  MARIONETTE_REQUIRE_FILE(path);
  ImportOptions options;
  options.loadAnimations = false;
  const ImportResult r = load(path, options);
  expectSound(r, path);
  EXPECT_TRUE(r.asset->clips.empty());
  EXPECT_EQ(r.asset->skeleton.jointCount(), load(path).asset->skeleton.jointCount());
  EXPECT_EQ(r.asset->meshes.size(), 3u);
}

// A hand-written DirectX file covering what the real files do not: keys that
// start late, keys sharing a time, and an FBX pivot helper node to fold away.
const char* kHelperScene = R"(xof 0303txt 0032
Frame Root {
  FrameTransformMatrix { 1.0,0.0,0.0,0.0, 0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.0,0.0,0.0,1.0;; }
  Frame Arm_$AssimpFbx$_Rotation {
    FrameTransformMatrix { 0.0,1.0,0.0,0.0, -1.0,0.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.0,2.0,0.0,1.0;; }
    Frame Arm {
      FrameTransformMatrix { 1.0,0.0,0.0,0.0, 0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 1.0,0.0,0.0,1.0;; }
      Frame Hand {
        FrameTransformMatrix { 1.0,0.0,0.0,0.0, 0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.5,0.0,0.0,1.0;; }
      }
    }
  }
}
AnimTicksPerSecond { 10; }
AnimationSet Wave {
  Animation {
    { Arm }
    AnimationKey { 2; 3; 10;3;1.0,0.0,0.0;;, 20;3;2.0,0.0,0.0;;, 20;3;3.0,0.0,0.0;;; }
    AnimationKey { 0; 2; 10;4;1.0,0.0,0.0,0.0;;, 30;4;0.0,0.0,1.0,0.0;;; }
    AnimationKey { 1; 1; 10;3;1.0,1.0,1.0;;; }
  }
  Animation {
    { Hand }
    AnimationKey { 0; 2; 10;4;1.0,0.0,0.0,0.0;;, 30;4;0.0,1.0,0.0,0.0;;; }
    AnimationKey { 2; 1; 10;3;0.5,0.0,0.0;;; }
    AnimationKey { 1; 2; 10;3;1.0,1.0,1.0;;, 30;3;2.0,2.0,2.0;;; }
  }
}
)";

TEST(AssimpImport, KeysAreShiftedDeduplicatedAndHelpersFolded) {
  const std::string path = tempPath("helper.x");
  writeFile(path, kHelperScene);
  const ImportResult r = load(path);
  expectSound(r, path);
  const Asset& a = *r.asset;
  const Skeleton& s = a.skeleton;
  // The helper is not a joint; its 90-degree turn about Z and lift of 2 move into Arm.
  ASSERT_EQ(s.names, (std::vector<std::string>{"Arm", "Hand"}));
  EXPECT_LT(glm::length(restPosition(s, "Arm") - glm::vec3(0, 3, 0)), 1e-5f);
  EXPECT_LT(glm::length(restPosition(s, "Hand") - glm::vec3(0, 3.5f, 0)), 1e-5f);

  ASSERT_EQ(a.clips.size(), 1u);
  const Clip& clip = a.clips[0];
  EXPECT_EQ(clip.name, "Wave");
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Note, "shifted")) << r.diagnostics.format();
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Warning, "share a time")) << r.diagnostics.format();
  EXPECT_NEAR(clip.duration, 2.0f, 1e-5f);  // ticks 10..30 at 10 per second
  ASSERT_EQ(clip.tracks.size(), 2u);

  const JointTrack& arm = clip.tracks[0];
  EXPECT_EQ(arm.joint, 0);
  // Ticks 10, 20, 20: the duplicate keeps the last value; the helper maps x to y, plus 2.
  ASSERT_EQ(arm.translation.times, (std::vector<float>{0.0f, 1.0f}));
  EXPECT_LT(glm::length(arm.translation.values[0] - glm::vec3(0, 3, 0)), 1e-5f);
  EXPECT_LT(glm::length(arm.translation.values[1] - glm::vec3(0, 5, 0)), 1e-5f);
  // Rotation keys get the helper's turn in front.
  ASSERT_EQ(arm.rotation.keyCount(), 2u);
  const glm::quat helperTurn = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  EXPECT_NEAR(std::abs(glm::dot(arm.rotation.values[0], helperTurn)), 1.0f, 1e-5f);
  EXPECT_TRUE(arm.scale.empty());  // constant 1

  const JointTrack& hand = clip.tracks[1];
  EXPECT_EQ(hand.joint, 1);
  ASSERT_EQ(hand.scale.keyCount(), 2u);  // not constant: kept
  EXPECT_EQ(hand.scale.values[1], glm::vec3(2.0f));
  EXPECT_NEAR(hand.rotation.times[1], 2.0f, 1e-6f);
  fs::remove(path);
}

TEST(AssimpImport, RootOnlyFileGivesOneJointAndAWarning) {
  const std::string path = tempPath("lonely.x");
  writeFile(path, "xof 0303txt 0032\nFrame Lonely {\n  FrameTransformMatrix { 1.0,0.0,0.0,0.0, "
                  "0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.0,0.5,0.0,1.0;; }\n}\n");
  const ImportResult r = load(path);
  expectSound(r, path);
  ASSERT_EQ(r.asset->skeleton.names, std::vector<std::string>{"Lonely"});
  EXPECT_NEAR(restPosition(r.asset->skeleton, "Lonely").y, 0.5f, 1e-6f);
  EXPECT_TRUE(r.diagnostics.hasWarnings());
  fs::remove(path);
}

// ---------------------------------------------------------------- failures

TEST(AssimpImport, EveryInvalidTestModelFailsCleanly) {
  const std::string folder = assimpModel("invalid");
  MARIONETTE_REQUIRE_FILE(folder);
  std::size_t files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    ++files;
    const auto start = std::chrono::steady_clock::now();
    const ImportResult r = load(path);
    // OutOfMemory.off declares 3.5e11 vertices: refused up front, not after
    // gigabytes of allocation.
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
    if (entry.path().filename() == "malformed2.obj") {
      // It names a material that does not exist and has an empty face line;
      // Assimp substitutes a material and loads the cube, which is legitimate.
      expectSound(r, path);
      ASSERT_EQ(r.asset->meshes.size(), 1u);
      EXPECT_EQ(r.asset->meshes[0].primitives[0].positions.size(), 8u);
      continue;
    }
    expectErrorNamingFile(r, path);
  }
  EXPECT_GE(files, 15u);  // the Debian package ships 15 files here
}

TEST(AssimpImport, NonexistentFileIsAnError) {
  const std::string path = tempPath("does_not_exist.fbx");
  fs::remove(path);
  expectErrorNamingFile(importAsset(path), path);
  expectErrorNamingFile(importWithAssimp(path, {}), path);
}

TEST(AssimpImport, HugeFileIsRefusedWithoutReadingIt) {
  const std::string path = tempPath("huge.fbx");
  {
    std::ofstream create(path, std::ios::binary);
  }
  fs::resize_file(path, (std::uintmax_t{512} << 20) + 1);  // sparse: costs no disk
  const ImportResult r = load(path);
  expectErrorNamingFile(r, path);
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Error, "512 MiB")) << r.diagnostics.format();
  fs::remove(path);
}

TEST(AssimpImport, ImpossibleOffHeaderIsRefused) {
  const std::string path = tempPath("impossible.off");
  writeFile(path, "# comment first\nOFF\n4000000000 1 0\n0 0 0\n3 0 0 0\n");
  const ImportResult r = load(path);
  expectErrorNamingFile(r, path);
  EXPECT_TRUE(mentions(r.diagnostics, Severity::Error, "4000000000 vertices")) << r.diagnostics.format();
  fs::remove(path);
}

}  // namespace
}  // namespace marionette

#endif  // MARIONETTE_HAS_ASSIMP
