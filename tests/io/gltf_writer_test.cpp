// glTF writer: real characters (glTF, VRM, FBX, X) written as .glb / .gltf, checked
// by the Khronos glTF-Validator (scripts/validate-gltf; a missing validator is a
// failure, never a skip) and re-imported: same joints, rest pose, mesh sizes,
// morph targets and sampled clips. Plus hand-made edge cases.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "marionette/animation/sampling.hpp"
#include "marionette/io/embedded_images.hpp"
#include "marionette/io/gltf_writer.hpp"
#include "marionette/io/import.hpp"
#include "synthetic.hpp"
#include "test_data.hpp"

namespace marionette {
namespace {

namespace fs = std::filesystem;
using test::assimpModel;
using test::sharedAsset;

// ---- helpers --------------------------------------------------------------------------

// A fresh folder per test for the written files.
std::string outputPath(const std::string& file) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / "marionette_gltf_writer" / info->name();
  fs::create_directories(dir);
  return (dir / file).string();
}

struct Validation {
  int exitCode = -1;
  int errors = -1, warnings = -1, infos = -1;
  std::string output;
};

Validation runValidator(const std::string& file, const std::string& environment = "") {
  Validation v;
  const std::string command =
      environment + " '" + test::sourceFile("scripts/validate-gltf") + "' '" + file + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return v;
  char chunk[4096];
  for (std::size_t n; (n = std::fread(chunk, 1, sizeof chunk, pipe)) > 0;) v.output.append(chunk, n);
  const int status = pclose(pipe);
  v.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::smatch m;
  if (std::regex_search(v.output, m, std::regex(R"((\d+) errors, (\d+) warnings, (\d+) infos)"))) {
    v.errors = std::stoi(m[1]);
    v.warnings = std::stoi(m[2]);
    v.infos = std::stoi(m[3]);
  }
  return v;
}

// The validator must be installed and find no error.
void expectValid(const std::string& file) {
  const Validation v = runValidator(file);
  ASSERT_NE(v.exitCode, 2) << "the glTF validator is not installed (run scripts/setup):\n" << v.output;
  EXPECT_EQ(v.exitCode, 0) << v.output;
  EXPECT_EQ(v.errors, 0) << v.output;
  // Recorded for docs/gltf-export.md.
  std::printf("validator: %s: %d errors, %d warnings, %d infos\n", fs::path(file).filename().c_str(), v.errors,
              v.warnings, v.infos);
}

Asset importOk(const std::string& path) {
  ImportResult r = importAsset(path);
  EXPECT_TRUE(r.ok()) << path << "\n" << r.diagnostics.format();
  return r.asset ? std::move(*r.asset) : Asset{};
}

void writeOk(const std::string& path, const Asset& asset, std::span<const Clip> clips) {
  const Diagnostics d = writeGltf(path, asset, clips);
  ASSERT_TRUE(d.ok()) << d.format();
  ASSERT_TRUE(fs::exists(path)) << path;
  if (d.hasWarnings()) std::printf("writer warnings:\n%s\n", d.format().c_str());
}

// Rotation angle between two unit quaternions, accurate near zero (acos is not).
double angleBetween(const glm::quat& a, const glm::quat& b) {
  const glm::dquat d = glm::inverse(glm::dquat(a)) * glm::dquat(b);
  return 2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::fabs(d.w));
}

// Size of the character: the diagonal of its rest joints' bounding box (at least 1 mm).
double characterSize(const Skeleton& s) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::mat4& m : s.restModelMatrices()) {
    lo = glm::min(lo, glm::vec3(m[3]));
    hi = glm::max(hi, glm::vec3(m[3]));
  }
  return s.jointCount() == 0 ? 1.0 : std::max(1e-3, static_cast<double>(glm::length(hi - lo)));
}

std::size_t vertexCount(const Asset& a) {
  std::size_t n = 0;
  for (const Mesh& m : a.meshes)
    for (const MeshPrimitive& p : m.primitives) n += p.positions.size();
  return n;
}
std::size_t triangleCount(const Asset& a) {
  std::size_t n = 0;
  for (const Mesh& m : a.meshes)
    for (const MeshPrimitive& p : m.primitives) n += p.indices.size() / 3;
  return n;
}

void expectSameSkeleton(const Skeleton& a, const Skeleton& b) {
  ASSERT_EQ(a.jointCount(), b.jointCount());
  EXPECT_EQ(a.names, b.names);
  const double tol = 1e-5 * characterSize(a);
  const auto ma = a.restModelMatrices(), mb = b.restModelMatrices();
  for (std::size_t j = 0; j < ma.size(); ++j)
    for (int c = 0; c < 4; ++c) {
      // Columns 0-2 carry rotation and scale (scale-relative), column 3 position (size-relative).
      const double scale = c < 3 ? std::max(1.0, static_cast<double>(glm::length(glm::vec3(ma[j][c])))) : 1.0;
      for (int r = 0; r < 3; ++r)
        ASSERT_NEAR(ma[j][c][r], mb[j][c][r], c < 3 ? 1e-5 * scale : tol) << a.names[j] << " column " << c;
    }
}

// Both clips sampled at 20 times agree: rotations within 1e-4 rad, translations
// within 1e-5 of the character's size, scales within 1e-5 relative, morph weights within 1e-5.
void expectSameMotion(const Asset& a, const Clip& ca, const Asset& b, const Clip& cb) {
  EXPECT_EQ(ca.name, cb.name);
  EXPECT_NEAR(ca.duration, cb.duration, 1e-6f) << ca.name;
  const std::size_t n = a.skeleton.jointCount();
  std::vector<Transform> pa(n), pb(n);
  std::vector<float> wa(a.morphTargets.size(), 0.0f), wb(b.morphTargets.size(), 0.0f);
  const double tol = 1e-5 * characterSize(a.skeleton);
  for (int i = 0; i < 20; ++i) {
    const float t = ca.duration * static_cast<float>(i) / 19.0f;
    sampleClip(ca, t, a.skeleton.restPose, pa);
    sampleClip(cb, t, b.skeleton.restPose, pb);
    for (std::size_t j = 0; j < n; ++j) {
      ASSERT_LT(angleBetween(pa[j].rotation, pb[j].rotation), 1e-4) << ca.name << " t=" << t << " " << a.skeleton.names[j];
      ASSERT_LT(glm::length(glm::dvec3(pa[j].translation - pb[j].translation)), tol)
          << ca.name << " t=" << t << " " << a.skeleton.names[j];
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(pa[j].scale[c], pb[j].scale[c], 1e-5 * std::max(1.0f, std::fabs(pa[j].scale[c])))
            << ca.name << " t=" << t << " " << a.skeleton.names[j];
    }
    sampleMorphWeights(ca, t, wa);
    sampleMorphWeights(cb, t, wb);
    for (std::size_t k = 0; k < wa.size(); ++k) {  // matched by name: the order is the reader's
      const auto it = std::find(b.morphTargets.begin(), b.morphTargets.end(), a.morphTargets[k]);
      ASSERT_NE(it, b.morphTargets.end()) << a.morphTargets[k];
      ASSERT_NEAR(wa[k], wb[static_cast<std::size_t>(it - b.morphTargets.begin())], 1e-5f)
          << ca.name << " t=" << t << " " << a.morphTargets[k];
    }
  }
}

// Write, validate, re-import and compare.
void roundTrip(const std::string& source, const std::string& outputName) {
  MARIONETTE_REQUIRE_FILE(source);
  const Asset original = importOk(source);
  ASSERT_GT(original.skeleton.jointCount(), 0u) << source;
  const std::string out = outputPath(outputName);
  writeOk(out, original, original.clips);
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const Asset& copy = *back.asset;
  expectSameSkeleton(original.skeleton, copy.skeleton);
  EXPECT_EQ(vertexCount(copy), vertexCount(original));
  EXPECT_EQ(triangleCount(copy), triangleCount(original));
  EXPECT_GT(vertexCount(copy), 0u);
  EXPECT_EQ(copy.morphTargets.size(), original.morphTargets.size());
  ASSERT_EQ(copy.clips.size(), original.clips.size());
  std::printf("round trip %s: %zu joints, %zu vertices, %zu triangles, %zu morph targets, %zu materials, %zu clips\n",
              outputName.c_str(), copy.skeleton.jointCount(), vertexCount(copy), triangleCount(copy),
              copy.morphTargets.size(), copy.materials.size(), copy.clips.size());
  for (std::size_t c = 0; c < original.clips.size(); ++c) expectSameMotion(original, original.clips[c], copy, copy.clips[c]);
}

// ---- real characters ------------------------------------------------------------------

TEST(GltfWriter, RobotExpressiveRoundTrip) { roundTrip(sharedAsset("characters/RobotExpressive.glb"), "robot.glb"); }

TEST(GltfWriter, CesiumManRoundTripAsGltfWithBinBeside) {
  roundTrip(sharedAsset("characters/CesiumMan.glb"), "cesium.gltf");
  EXPECT_TRUE(fs::exists(outputPath("cesium.bin")));
}

TEST(GltfWriter, GodetteVrmRoundTrip) { roundTrip(sharedAsset("characters/Godette_vrm_v4.vrm"), "godette.glb"); }

#ifdef MARIONETTE_HAS_ASSIMP
TEST(GltfWriter, PabFbxRoundTrip) { roundTrip(sharedAsset("characters/pab_arnaud.fbx"), "pab.glb"); }
TEST(GltfWriter, EpilepticXRoundTrip) { roundTrip(assimpModel("X/BCN_Epileptic.X"), "bcn.glb"); }

// Textures embedded in an Assimp format (a .zae's, an FBX's) survive into the written glTF,
// byte for byte (issue 41: they were dropped as unreadable from the source file).
TEST(GltfWriter, EmbeddedTexturesOfAssimpFormatsSurvive) {
  for (const std::string& source : {assimpModel("Collada/human.zae"), assimpModel("FBX/embedded_ascii/box.FBX")}) {
    MARIONETTE_REQUIRE_FILE(source);
    const Asset original = importOk(source);
    EmbeddedImages originalImages(original);
    std::size_t embedded = 0;
    for (const Material& m : original.materials)
      if (EmbeddedImages::indexOf(m.baseColorTexture) >= 0) {
        ++embedded;
        const std::vector<unsigned char>* bytes = originalImages.find(EmbeddedImages::indexOf(m.baseColorTexture));
        ASSERT_NE(bytes, nullptr) << source << " " << m.baseColorTexture;
      }
    ASSERT_GT(embedded, 0u) << source << ": no embedded texture to carry";
    const std::string out = outputPath(fs::path(source).stem().string() + "_textured.glb");
    const Diagnostics d = writeGltf(out, original, {});
    ASSERT_TRUE(d.ok()) << d.format();
    EXPECT_EQ(d.format().find("dropped"), std::string::npos) << d.format();
    expectValid(out);
    const ImportResult back = importGltf(out, {});
    ASSERT_TRUE(back.ok()) << back.diagnostics.format();
    EmbeddedImages written(*back.asset);
    std::size_t carried = 0;
    for (std::size_t i = 0; i < original.materials.size() && i < back.asset->materials.size(); ++i) {
      const int a = EmbeddedImages::indexOf(original.materials[i].baseColorTexture);
      const int b = EmbeddedImages::indexOf(back.asset->materials[i].baseColorTexture);
      if (a < 0) continue;
      ASSERT_GE(b, 0) << source << " material " << i;
      const std::vector<unsigned char>* was = originalImages.find(a);
      const std::vector<unsigned char>* now = written.find(b);
      ASSERT_NE(now, nullptr) << source << " material " << i;
      EXPECT_EQ(*now, *was) << source << " material " << i;
      ++carried;
    }
    EXPECT_EQ(carried, embedded) << source;
  }
}
#endif

// Morph-weight tracks over every target of the character (VRM face parts share
// targets, so one track drives several mesh nodes), with a joint track beside them.
void morphRoundTrip(const std::string& source, const std::string& outputName, Interpolation mode) {
  MARIONETTE_REQUIRE_FILE(source);
  Asset a = importOk(source);
  ASSERT_GT(a.morphTargets.size(), 0u) << source;
  Clip clip;
  clip.name = "expressions";
  MorphTrack m;
  m.interpolation = mode;
  m.times = {0.0f, 0.4f, 1.0f};
  const std::size_t per = mode == Interpolation::CubicSpline ? 3 : 1;
  for (std::size_t k = 0; k < a.morphTargets.size(); ++k) m.targets.push_back(static_cast<int>(k));
  for (std::size_t e = 0; e < m.times.size() * per; ++e)
    for (std::size_t k = 0; k < m.targets.size(); ++k)
      m.weights.push_back(std::fmod(0.13f * static_cast<float>(k + 1) + 0.29f * static_cast<float>(e), 1.0f));
  clip.morphTracks.push_back(m);
  clip.tracks.push_back(test::rotationTrack(1, {0.0f, 1.0f}, {0.0f, 0.7f}, {0, 1, 0}, Interpolation::Linear));
  clip.updateDuration();
  a.clips = {clip};
  const std::string out = outputPath(outputName);
  writeOk(out, a, a.clips);
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  ASSERT_EQ(back.asset->clips.size(), 1u);
  EXPECT_FALSE(back.asset->clips[0].morphTracks.empty());
  expectSameMotion(a, a.clips[0], *back.asset, back.asset->clips[0]);
}

TEST(GltfWriter, MorphWeightsRobotExpressive) {
  morphRoundTrip(sharedAsset("characters/RobotExpressive.glb"), "robot_face.glb", Interpolation::Linear);
}
TEST(GltfWriter, MorphWeightsGodetteSharedTargetsCubic) {
  morphRoundTrip(sharedAsset("characters/Godette_vrm_v4.vrm"), "godette_face.glb", Interpolation::CubicSpline);
}

// Two meshes sharing a target: one track drives both nodes; a second track with
// other key times on the same mesh cannot be expressed and is reported.
TEST(GltfWriter, MorphTargetsSharedBetweenMeshes) {
  Asset a;
  a.skeleton = test::makeChain(2);
  a.morphTargets = {"smile", "blink", "frown"};
  for (int m = 0; m < 2; ++m) {
    Mesh mesh;
    mesh.name = m == 0 ? "face" : "brows";
    mesh.morphTargets = m == 0 ? std::vector<int>{0, 1} : std::vector<int>{1, 2};
    MeshPrimitive p;
    p.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};
    p.indices = {0, 1, 2};
    p.joints.assign(3, glm::u16vec4(1, 0, 0, 0));
    p.weights.assign(3, glm::vec4(1, 0, 0, 0));
    p.morphTargets.resize(2);
    p.morphTargets[0].positions.assign(3, glm::vec3(0, 0, 0.1f));
    p.morphTargets[1].positions.assign(3, glm::vec3(0.2f, 0, 0));
    mesh.skinned = true;
    mesh.primitives.push_back(p);
    a.meshes.push_back(mesh);
  }
  Clip clip;
  clip.name = "face";
  MorphTrack all;
  all.targets = {0, 1, 2};
  all.times = {0.0f, 1.0f};
  all.weights = {0.0f, 0.2f, 0.4f, 1.0f, 0.8f, 0.6f};
  clip.morphTracks.push_back(all);
  MorphTrack late;
  late.targets = {0};
  late.times = {0.5f, 2.0f};
  late.weights = {0.3f, 0.9f};
  clip.morphTracks.push_back(late);
  clip.updateDuration();
  const std::string out = outputPath("shared.glb");
  const Diagnostics d = writeGltf(out, a, std::span<const Clip>(&clip, 1));
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(d.format().find("mesh 'face' is driven by morph-weight tracks with different key times"),
            std::string::npos)
      << d.format();
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  EXPECT_EQ(back.asset->morphTargets, a.morphTargets);
  ASSERT_EQ(back.asset->clips.size(), 1u);
  EXPECT_EQ(back.asset->clips[0].morphTracks.size(), 2u);  // one weights channel per mesh node
  clip.morphTracks.pop_back();                             // what could be written
  clip.updateDuration();
  expectSameMotion(a, clip, *back.asset, back.asset->clips[0]);
}

// The textures of a glTF character come along (read from the source file).
TEST(GltfWriter, EmbeddedTexturesAreKept) {
  const std::string source = sharedAsset("characters/CesiumMan.glb");
  MARIONETTE_REQUIRE_FILE(source);
  const Asset original = importOk(source);
  ASSERT_FALSE(original.materials.empty());
  ASSERT_FALSE(original.materials[0].baseColorTexture.empty());
  const std::string out = outputPath("textured.glb");
  writeOk(out, original, original.clips);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  ASSERT_EQ(back.asset->materials.size(), original.materials.size());
  EXPECT_EQ(back.asset->materials[0].baseColorTexture.rfind("embedded:", 0), 0u);
}

// ---- hand-made edge cases ----------------------------------------------------------------

Asset chainCharacter() {
  Asset a;
  a.skeleton = test::makeChain(3, 0.5f);
  a.skeleton.restPose[1].scale = glm::vec3(1.0f, 2.0f, 1.0f);  // non-unit scale is kept
  return a;
}

TEST(GltfWriter, DuplicateKeyTimesAreMerged) {
  Asset a = chainCharacter();
  Clip clip;
  clip.name = "dup";
  clip.tracks.push_back(test::rotationTrack(1, {0.0f, 0.5f, 0.5f, 1.0f}, {0.0f, 0.4f, 0.9f, 1.2f}));
  clip.updateDuration();
  const std::string out = outputPath("dup.glb");
  const Diagnostics d = writeGltf(out, a, std::span<const Clip>(&clip, 1));
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(d.format().find("merged 1 key(s)"), std::string::npos) << d.format();
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  ASSERT_EQ(back.asset->clips.size(), 1u);
  const Track<glm::quat>& r = back.asset->clips[0].tracks.at(0).rotation;
  EXPECT_EQ(r.times, (std::vector<float>{0.0f, 0.5f, 1.0f}));
  EXPECT_LT(angleBetween(r.values[1], glm::angleAxis(0.4f, glm::vec3(0, 0, 1))), 1e-6);  // the first key of a time wins
}

TEST(GltfWriter, NonUnitAndZeroQuaternionsAreRepaired) {
  Asset a = chainCharacter();
  Clip clip;
  clip.name = "scaled quaternions";
  clip.tracks.push_back(test::rotationTrack(2, {0.0f, 1.0f, 2.0f}, {0.3f, 0.6f, 0.9f}));
  clip.tracks[0].rotation.values[0] *= 3.0f;
  clip.tracks[0].rotation.values[2] = glm::quat(0.0f, 0.0f, 0.0f, 0.0f);
  clip.updateDuration();
  const std::string out = outputPath("quats.glb");
  const Diagnostics d = writeGltf(out, a, std::span<const Clip>(&clip, 1));
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(d.format().find("1 non-unit rotation key(s) normalized"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("1 zero rotation key(s) written as the identity"), std::string::npos) << d.format();
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const auto& values = back.asset->clips.at(0).tracks.at(0).rotation.values;
  ASSERT_EQ(values.size(), 3u);
  EXPECT_LT(angleBetween(values[0], glm::angleAxis(0.3f, glm::vec3(0, 0, 1))), 1e-6);
  EXPECT_LT(angleBetween(values[2], glm::quat(1, 0, 0, 0)), 1e-6);
}

// No meshes: nodes, skin and animation only; the root space survives as a node.
TEST(GltfWriter, SkeletonWithoutMeshes) {
  Asset a = chainCharacter();
  a.skeleton.rootTransform = Transform{glm::vec3(1, 2, 3), glm::angleAxis(-1.5707964f, glm::vec3(1, 0, 0)),
                                       glm::vec3(0.01f)}
                                 .matrix();
  Clip clip;
  clip.name = "wave";
  clip.tracks.push_back(test::rotationTrack(0, {0.0f, 1.0f}, {0.0f, 1.0f}, {0, 1, 0}, Interpolation::Step));
  clip.tracks.push_back(test::rotationTrack(1, {0.0f, 0.5f, 1.0f}, {0.0f, 0.5f, -0.5f}));
  clip.tracks[1].translation.times = {0.0f, 1.0f};
  clip.tracks[1].translation.values = {glm::vec3(0, 0.5f, 0), glm::vec3(0.1f, 0.5f, 0)};
  clip.updateDuration();
  a.clips = {clip};
  const std::string out = outputPath("bones_only.glb");
  writeOk(out, a, a.clips);
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  expectSameSkeleton(a.skeleton, back.asset->skeleton);
  EXPECT_TRUE(back.asset->meshes.empty());
  ASSERT_EQ(back.asset->clips.size(), 1u);
  expectSameMotion(a, a.clips[0], *back.asset, back.asset->clips[0]);
  EXPECT_EQ(back.asset->clips[0].tracks[0].rotation.interpolation, Interpolation::Step);
}

// Cubic-spline keys (tangents kept as they are) and a one-key cubic track, which
// glTF cannot hold and which is written as STEP with the same value.
TEST(GltfWriter, CubicSplineTracks) {
  Asset a = chainCharacter();
  Clip clip;
  clip.name = "cubic";
  JointTrack jt;
  jt.joint = 1;
  jt.rotation.interpolation = Interpolation::CubicSpline;
  jt.rotation.times = {0.0f, 1.0f};
  const glm::quat q0 = glm::angleAxis(0.2f, glm::vec3(1, 0, 0)), q1 = glm::angleAxis(1.1f, glm::vec3(1, 0, 0));
  jt.rotation.values = {glm::quat(0, 0.1f, 0, 0), q0, glm::quat(0, 0.3f, 0, 0),
                        glm::quat(0, -0.2f, 0, 0), q1, glm::quat(0, 0, 0, 0)};
  jt.translation.interpolation = Interpolation::CubicSpline;
  jt.translation.times = {0.5f};
  jt.translation.values = {glm::vec3(1), glm::vec3(0, 0.7f, 0), glm::vec3(2)};
  clip.tracks.push_back(jt);
  clip.updateDuration();
  const std::string out = outputPath("cubic.glb");
  writeOk(out, a, std::span<const Clip>(&clip, 1));
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const JointTrack& r = back.asset->clips.at(0).tracks.at(0);
  EXPECT_EQ(r.rotation.interpolation, Interpolation::CubicSpline);
  EXPECT_EQ(r.translation.interpolation, Interpolation::Step);
  expectSameMotion(a, clip, *back.asset, back.asset->clips[0]);
}

// An unskinned mesh attached to a joint is written under that joint's node; a
// reader (ours) then binds it rigidly to the joint at its rest place.
TEST(GltfWriter, RigidMeshFollowsItsJoint) {
  Asset a = chainCharacter();
  Mesh mesh;
  mesh.name = "hat";
  mesh.joint = 2;
  MeshPrimitive p;
  p.positions = {glm::vec3(0), glm::vec3(0.1f, 0, 0), glm::vec3(0, 0, 0.1f)};
  p.indices = {0, 1, 2};
  mesh.primitives.push_back(p);
  a.meshes.push_back(mesh);
  const std::string out = outputPath("hat.glb");
  writeOk(out, a, {});
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const Mesh& m = back.asset->meshes.at(0);
  ASSERT_EQ(m.primitives.at(0).positions.size(), 3u);
  // Skinned at rest (joint rest model * inverse bind * vertex) it sits where the joint puts it.
  const glm::mat4 jointRest = back.asset->skeleton.restModelMatrices()[2];
  const glm::mat4 skinning = jointRest * back.asset->skeleton.inverseBind[2];
  for (std::size_t v = 0; v < 3; ++v) {
    EXPECT_EQ(m.primitives[0].joints[v][0], 2);
    const glm::vec3 placed = glm::vec3(skinning * glm::vec4(m.primitives[0].positions[v], 1.0f));
    const glm::vec3 expected = glm::vec3(jointRest * glm::vec4(p.positions[v], 1.0f));
    EXPECT_LT(glm::length(placed - expected), 1e-5f) << v;
  }
}

// A texture file: copied into the file by default, referenced by a relative URI
// with embedTextures = false (the validator then reads it from there).
TEST(GltfWriter, TextureFileEmbeddedOrReferenced) {
  const std::string png = test::sourceFile("docs/scaling_joints.png");
  MARIONETTE_REQUIRE_FILE(png);
  Asset a = chainCharacter();
  Mesh mesh;
  mesh.name = "card";
  MeshPrimitive p;
  p.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};
  p.uvs = {glm::vec2(0), glm::vec2(1, 0), glm::vec2(0, 1)};
  p.indices = {0, 1, 2};
  p.material = 0;
  mesh.primitives.push_back(p);
  a.meshes.push_back(mesh);
  Material m;
  m.name = "picture";
  m.baseColor = glm::vec4(1.0f, 0.5f, 0.25f, 1.0f);
  m.baseColorTexture = png;
  a.materials.push_back(m);
  for (const bool embed : {true, false}) {
    const std::string out = outputPath(embed ? "embedded.gltf" : "referenced.gltf");
    GltfWriteOptions options;
    options.embedTextures = embed;
    const Diagnostics d = writeGltf(out, a, {}, options);
    ASSERT_TRUE(d.ok()) << d.format();
    EXPECT_FALSE(d.hasWarnings()) << d.format();
    expectValid(out);
    ImportOptions trusted;  // the texture lies outside the output's folder: our own file, allowed
    trusted.allowFilesOutsideModelFolder = true;
    const ImportResult back = importGltf(out, trusted);
    ASSERT_TRUE(back.ok()) << back.diagnostics.format();
    const Material& r = back.asset->materials.at(0);
    EXPECT_EQ(r.baseColor, m.baseColor);
    if (embed)
      EXPECT_EQ(r.baseColorTexture, "embedded:0");
    else
      EXPECT_TRUE(fs::equivalent(r.baseColorTexture, png)) << r.baseColorTexture;
  }
}

TEST(GltfWriter, UnwritablePathIsAnErrorNamingIt) {
  const Asset a = chainCharacter();
  const std::string path = "/nonexistent-marionette-dir/out.glb";
  const Diagnostics d = writeGltf(path, a, {});
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.format().find(path), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("cannot open for writing"), std::string::npos) << d.format();
}

TEST(GltfWriter, OtherExtensionIsAnError) {
  const Asset a = chainCharacter();
  const std::string path = outputPath("character.fbx");
  const Diagnostics d = writeGltf(path, a, {});
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.format().find(path), std::string::npos) << d.format();
  EXPECT_NE(d.format().find(".glb or .gltf"), std::string::npos) << d.format();
  EXPECT_FALSE(fs::exists(path));
}

TEST(GltfWriter, InvalidClipIsAnErrorAndNothingIsWritten) {
  const Asset a = chainCharacter();
  Clip clip;
  clip.name = "broken";
  clip.tracks.push_back(test::rotationTrack(7, {0.0f, 1.0f}, {0.0f, 1.0f}));  // the chain has 3 joints
  const std::string path = outputPath("broken.glb");
  const Diagnostics d = writeGltf(path, a, std::span<const Clip>(&clip, 1));
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.format().find("clip 'broken'"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find(path), std::string::npos) << d.format();
  EXPECT_FALSE(fs::exists(path));
}

TEST(GltfWriter, NonFiniteDataIsAnError) {
  Asset a = chainCharacter();
  Mesh mesh;
  mesh.name = "tri";
  MeshPrimitive p;
  p.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, NAN, 0)};
  p.indices = {0, 1, 2};
  mesh.primitives.push_back(p);
  a.meshes.push_back(mesh);
  const std::string path = outputPath("nan.glb");
  const Diagnostics d = writeGltf(path, a, {});
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.format().find("mesh 'tri' primitive 0 has non-finite"), std::string::npos) << d.format();
  EXPECT_FALSE(fs::exists(path));
}

// Weights that do not sum to 1, a repeated joint, zero normals and a texture that
// is not an image: repaired or dropped with warnings, and the file is valid.
TEST(GltfWriter, MeshDataIsRepairedForTheValidator) {
  Asset a = chainCharacter();
  Mesh mesh;
  mesh.name = "quad";
  mesh.skinned = true;
  MeshPrimitive p;
  p.positions = {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(0, 1, 0)};
  p.normals = {glm::vec3(0, 0, 2), glm::vec3(0), glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)};
  p.uvs = {glm::vec2(0), glm::vec2(1, 0), glm::vec2(1), glm::vec2(0, 1)};
  p.joints = {glm::u16vec4(0, 1, 0, 0), glm::u16vec4(1, 1, 2, 0), glm::u16vec4(2, 0, 0, 0), glm::u16vec4(0)};
  p.weights = {glm::vec4(0.3f, 0.3f, 0, 0), glm::vec4(0.2f, 0.2f, 0.1f, 0), glm::vec4(1, 0, 0, 0), glm::vec4(0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = 0;
  mesh.primitives.push_back(p);
  a.meshes.push_back(mesh);
  Material m;
  m.name = "paper";
  m.baseColorTexture = test::sourceFile("CMakeLists.txt");  // not a PNG
  a.materials.push_back(m);
  const std::string out = outputPath("repaired.glb");
  const Diagnostics d = writeGltf(out, a, {});
  ASSERT_TRUE(d.ok()) << d.format();
  EXPECT_NE(d.format().find("1 zero or non-finite normal(s)"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("1 vertices without usable skin weights"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("neither PNG nor JPEG"), std::string::npos) << d.format();
  expectValid(out);
  const ImportResult back = importGltf(out, {});
  ASSERT_TRUE(back.ok()) << back.diagnostics.format();
  const MeshPrimitive& q = back.asset->meshes.at(0).primitives.at(0);
  EXPECT_NEAR(q.weights[1][0], 0.8f, 1e-6f);  // joint 1 twice (0.2 + 0.2) of 0.5
  EXPECT_NEAR(glm::length(q.normals[0]), 1.0f, 1e-6f);
  EXPECT_NEAR(q.normals[1].z, 1.0f, 1e-6f);  // the face normal
}

TEST(GltfWriter, ValidatorScriptReportsMissingInstall) {
  const Validation v = runValidator(outputPath("none.glb"), "MARIONETTE_TOOLS_DIR=/nonexistent-marionette-tools");
  EXPECT_EQ(v.exitCode, 2) << v.output;
  EXPECT_NE(v.output.find("run scripts/setup"), std::string::npos) << v.output;
}

}  // namespace
}  // namespace marionette
