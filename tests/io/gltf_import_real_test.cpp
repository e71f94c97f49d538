// glTF / GLB / VRM / VRMA import of real files: characters and motions from ../shared/assets
// (RobotExpressive, Godette, CesiumMan, a VRM animation), the import options, and Debian's
// assimp glTF2 test models, good and deliberately broken. Missing data fails, never skips.
#include <gtest/gtest.h>

#include "gltf_import_helpers.hpp"

namespace marionette {
namespace {

using namespace gltf_test;

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

}  // namespace
}  // namespace marionette
