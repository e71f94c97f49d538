// The bind-pose mesh shadowed transfer traces against, and the per-vertex ray data.
#include "marionette/prt/transfer_mesh.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

#include "marionette/io/import.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::prt;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance, const char* what) {
  EXPECT_LE(glm::length(a - b), tolerance) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x
                                           << ", " << b.y << ", " << b.z << ")";
}

// One triangle in the plane x + y = 1, with its normal.
MeshPrimitive slantedTriangle() {
  MeshPrimitive p;
  p.positions = {{1, 0, 0}, {0, 1, 0}, {1, 0, 1}};
  const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
  p.normals = {n, n, n};
  p.indices = {0, 1, 2};
  return p;
}

// A cube of side 2 centred at the origin with per-face (split) vertices: 24 vertices, as an
// exporter writes a flat-shaded cube.
TransferMesh splitCube() {
  TransferMesh m;
  const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 3; ++a)
    for (float side : {-1.0f, 1.0f}) {
      const glm::vec3 n = side * axes[a], u = axes[(a + 1) % 3], v = axes[(a + 2) % 3];
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        m.positions.push_back(n + c.x * u + c.y * v);
        m.normals.push_back(n);
      }
      // Counter-clockwise seen from outside: u x v = +axis, so flip the winding on the - side.
      if (side > 0)
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
      else
        m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    }
  m.primitiveVertexOffset = {0};
  return m;
}

}  // namespace

TEST(TransferMesh, RobotExpressiveBindPose) {
  const std::string path = marionette::test::sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult imported = importAsset(path);
  ASSERT_TRUE(imported.ok()) << imported.diagnostics.format();
  const Asset& asset = *imported.asset;

  Diagnostics d;
  const TransferMesh mesh = bindPoseMesh(asset, d, {.skinnedSpace = SkinnedSpace::AsStored, .poseModel = {}});
  EXPECT_TRUE(d.ok()) << d.format();
  // Its bind space is Z-up at 1/100 of model space: said, since transfer computed there is not
  // in the frame the lighting is in.
  std::printf("%s", d.format().c_str());
  EXPECT_NE(d.format().find("bind space"), std::string::npos);
  std::size_t primitives = 0, skinned = 0;
  for (const Mesh& m : asset.meshes) {
    primitives += m.primitives.size();
    skinned += m.skinned ? 1 : 0;
  }
  std::printf("RobotExpressive: %zu meshes (%zu skinned), %zu primitives, %zu vertices, %zu triangles\n",
              asset.meshes.size(), skinned, primitives, mesh.positions.size(), mesh.indices.size() / 3);
  // The file's 19 primitives (14 meshes) have POSITION accessors of 7,214 vertices in all, every
  // one referenced by a triangle. ASSETS.md's 7,070 (21 meshes) is Assimp's count after its
  // post-processing, not the file's.
  EXPECT_EQ(mesh.positions.size(), 7214u);
  EXPECT_EQ(primitives, 19u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  EXPECT_EQ(mesh.primitiveVertexOffset.size(), primitives);
  EXPECT_GT(mesh.indices.size(), 0u);
  EXPECT_EQ(mesh.indices.size() % 3, 0u);

  std::size_t notUnit = 0, outOfRange = 0, notFinite = 0;
  for (const glm::vec3& n : mesh.normals)
    if (!(std::abs(glm::length(n) - 1.0f) < 1e-4f)) ++notUnit;
  for (std::uint32_t i : mesh.indices)
    if (i >= mesh.positions.size()) ++outOfRange;
  for (const glm::vec3& p : mesh.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++notFinite;
  EXPECT_EQ(notUnit, 0u);
  EXPECT_EQ(outOfRange, 0u);
  EXPECT_EQ(notFinite, 0u);
  for (std::size_t k = 1; k < mesh.primitiveVertexOffset.size(); ++k)
    EXPECT_LE(mesh.primitiveVertexOffset[k - 1], mesh.primitiveVertexOffset[k]);

  const float offset = rayOriginOffset(mesh);
  std::printf("RobotExpressive as stored: ray origin offset %.3g (1e-4 of the box diagonal)\n", static_cast<double>(offset));
  EXPECT_GT(offset, 0.0f);
}

// Skinned with the rest pose: the model space the runtime draws, Y-up and metres (the robot is
// about 4.4 m tall in it: ASSETS.md's "scaled FBX2glTF space").
TEST(TransferMesh, RobotExpressiveRestPose) {
  const std::string path = marionette::test::sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult imported = importAsset(path);
  ASSERT_TRUE(imported.ok()) << imported.diagnostics.format();
  Diagnostics d;
  const TransferMesh stored = bindPoseMesh(*imported.asset, d, {.skinnedSpace = SkinnedSpace::AsStored, .poseModel = {}});
  Diagnostics restDiagnostics;
  const TransferMesh mesh = bindPoseMesh(*imported.asset, restDiagnostics, {.skinnedSpace = SkinnedSpace::RestPose, .poseModel = {}});
  EXPECT_TRUE(restDiagnostics.items.empty()) << restDiagnostics.format();
  ASSERT_EQ(mesh.positions.size(), stored.positions.size());
  EXPECT_EQ(mesh.indices, stored.indices);
  EXPECT_EQ(mesh.primitiveVertexOffset, stored.primitiveVertexOffset);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  std::printf("RobotExpressive rest pose: box (%.2f %.2f %.2f) - (%.2f %.2f %.2f)\n", static_cast<double>(lo.x), static_cast<double>(lo.y),
              static_cast<double>(lo.z), static_cast<double>(hi.x), static_cast<double>(hi.y), static_cast<double>(hi.z));
  EXPECT_NEAR(lo.y, 0.0f, 0.1f) << "feet on the ground";
  EXPECT_NEAR(hi.y, 4.4f, 0.2f) << "head top";
  for (const glm::vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
}

// Rest-pose skinning blends the palette by the weights; a vertex without weights stays put.
TEST(TransferMesh, RestPoseSkinsWithTheWeights) {
  Asset asset;
  asset.sourcePath = "synthetic-skin";
  Transform up, side;
  up.translation = {0, 2, 0};
  side.translation = {4, 0, 0};
  asset.skeleton.addJoint("up", -1, up, glm::mat4(1.0f), true);
  asset.skeleton.addJoint("side", -1, side, glm::mat4(1.0f), true);
  Mesh m;
  m.name = "skin";
  m.skinned = true;
  MeshPrimitive p = slantedTriangle();
  p.joints = {{0, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}};
  p.weights = {{1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {0, 0, 0, 0}};
  m.primitives.push_back(p);
  asset.meshes.push_back(m);

  Diagnostics stored;
  const TransferMesh asStored = bindPoseMesh(asset, stored, {.skinnedSpace = SkinnedSpace::AsStored, .poseModel = {}});
  EXPECT_TRUE(stored.ok()) << stored.format();
  EXPECT_NE(stored.format().find("bind space"), std::string::npos) << "identity inverse binds, moved joints";
  expectNear(asStored.positions[0], p.positions[0], 0.0f, "as stored");

  Diagnostics d;
  const TransferMesh mesh = bindPoseMesh(asset, d, {.skinnedSpace = SkinnedSpace::RestPose, .poseModel = {}});
  EXPECT_TRUE(d.ok()) << d.format();
  expectNear(mesh.positions[0], p.positions[0] + glm::vec3(0, 2, 0), 1e-6f, "one joint");
  expectNear(mesh.positions[1], p.positions[1] + glm::vec3(2, 1, 0), 1e-6f, "half and half");
  expectNear(mesh.positions[2], p.positions[2], 0.0f, "no weights: kept");
  EXPECT_NE(d.format().find("without usable skin weights"), std::string::npos) << d.format();

  // Posed: the given model matrices instead of the rest pose (joint "up" raised by 3 more).
  std::vector<glm::mat4> pose = asset.skeleton.restModelMatrices();
  pose[0] = glm::translate(glm::mat4(1.0f), glm::vec3(0, 5, 0));
  Diagnostics posedDiagnostics;
  const TransferMesh posed = bindPoseMesh(asset, posedDiagnostics, {.skinnedSpace = SkinnedSpace::Posed, .poseModel = pose});
  expectNear(posed.positions[0], p.positions[0] + glm::vec3(0, 5, 0), 1e-6f, "posed, one joint");
  expectNear(posed.positions[1], p.positions[1] + glm::vec3(2, 2.5f, 0), 1e-6f, "posed, half and half");
  // A pose of the wrong size: an error naming the counts, and the rest pose instead.
  Diagnostics wrong;
  const TransferMesh fallback = bindPoseMesh(asset, wrong, {.skinnedSpace = SkinnedSpace::Posed, .poseModel = {pose[0]}});
  EXPECT_FALSE(wrong.ok());
  EXPECT_NE(wrong.format().find("1 joint matrices but the skeleton has 2"), std::string::npos) << wrong.format();
  expectNear(fallback.positions[0], mesh.positions[0], 0.0f, "rest pose instead");
}

// A rigid part on a joint goes through the joint's rest model matrix; normals through its
// inverse transpose. Skinned and unattached meshes stay as stored.
TEST(TransferMesh, RigidMeshFollowsItsJoint) {
  Asset asset;
  asset.sourcePath = "synthetic-rigid";
  Transform root;
  root.translation = {1, 2, 3};
  Transform child;
  child.translation = {0, 1, 0};
  child.rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  Transform stretched;
  stretched.scale = {2, 1, 1};
  asset.skeleton.addJoint("root", -1, root);
  asset.skeleton.addJoint("child", 0, child);
  asset.skeleton.addJoint("stretched", -1, stretched);

  Mesh onChild;
  onChild.name = "rigid";
  onChild.joint = 1;
  onChild.primitives.push_back(slantedTriangle());
  Mesh onStretched = onChild;
  onStretched.joint = 2;
  Mesh skinnedMesh = onChild;
  skinnedMesh.skinned = true;
  skinnedMesh.joint = -1;
  Mesh loose = onChild;
  loose.joint = -1;
  asset.meshes = {onChild, onStretched, skinnedMesh, loose};

  Diagnostics d;
  const TransferMesh mesh = bindPoseMesh(asset, d);
  EXPECT_TRUE(d.ok()) << d.format();
  ASSERT_EQ(mesh.positions.size(), 12u);
  ASSERT_EQ(mesh.primitiveVertexOffset, (std::vector<std::size_t>{0, 3, 6, 9}));
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));

  // Model = T(1,2,3) T(0,1,0) Ry(90): (x, y, z) -> (z, y, -x) + (1, 3, 3).
  expectNear(mesh.positions[0], {1, 3, 2}, 1e-5f, "rigid vertex 0");
  expectNear(mesh.positions[1], {1, 4, 3}, 1e-5f, "rigid vertex 1");
  expectNear(mesh.positions[2], {2, 3, 2}, 1e-5f, "rigid vertex 2");
  expectNear(mesh.normals[0], glm::normalize(glm::vec3(0, 1, -1)), 1e-5f, "rigid normal");

  // Scale (2, 1, 1): the plane x + y = 1 becomes x / 2 + y = 1, normal along (1/2, 1, 0), not
  // the naively scaled (2, 1, 0).
  expectNear(mesh.positions[3], {2, 0, 0}, 1e-5f, "stretched vertex 0");
  expectNear(mesh.normals[3], glm::normalize(glm::vec3(0.5f, 1, 0)), 1e-5f, "stretched normal");

  for (std::size_t v = 6; v < 12; ++v) {
    expectNear(mesh.positions[v], slantedTriangle().positions[v % 3], 0.0f, "stored vertex");
    expectNear(mesh.normals[v], slantedTriangle().normals[v % 3], 1e-6f, "stored normal");
  }
}

TEST(TransferMesh, MissingNormalsAreComputed) {
  Asset asset;
  Mesh m;
  MeshPrimitive p = slantedTriangle();
  p.normals.clear();
  m.primitives.push_back(p);
  p.normals = {glm::vec3(0.0f), glm::vec3(kNaN), glm::vec3(0, 0, 3)};  // two unusable, one unnormalized
  m.primitives.push_back(p);
  asset.meshes.push_back(m);
  Diagnostics d;
  const TransferMesh mesh = bindPoseMesh(asset, d);
  EXPECT_TRUE(d.ok()) << d.format();
  EXPECT_TRUE(d.hasWarnings()) << "unusable normals should be reported";
  ASSERT_EQ(mesh.normals.size(), 6u);
  // Winding (1,0,0) (0,1,0) (1,0,1): cross((-1,1,0), (0,0,1)) = (1, 1, 0).
  for (int v : {0, 1, 2, 3, 4}) expectNear(mesh.normals[static_cast<std::size_t>(v)], glm::normalize(glm::vec3(1, 1, 0)), 1e-5f, "computed");
  expectNear(mesh.normals[5], {0, 0, 1}, 1e-6f, "kept, normalized");
}

TEST(TransferMesh, BadInputIsReportedNotFatal) {
  {  // empty asset
    Diagnostics d;
    const TransferMesh mesh = bindPoseMesh(Asset{}, d);
    EXPECT_TRUE(mesh.positions.empty());
    EXPECT_TRUE(d.hasWarnings()) << "an asset with nothing to trace deserves a word";
    EXPECT_TRUE(geometricVertexNormals(mesh).empty());
    EXPECT_EQ(rayOriginOffset(mesh), 0.0f);
  }
  Asset asset;
  asset.sourcePath = "bad.glb";
  Mesh m;
  m.name = "body";
  MeshPrimitive nan = slantedTriangle();
  nan.positions[1].y = kNaN;
  MeshPrimitive range = slantedTriangle();
  range.indices = {0, 1, 2, 0, 1, 7, 2, 1};  // one good triangle, one out of range, 2 stray indices
  m.primitives = {nan, range};
  Mesh lost;
  lost.name = "hat";
  lost.joint = 5;  // the skeleton is empty
  lost.primitives.push_back(slantedTriangle());
  asset.meshes = {m, lost};

  Diagnostics d;
  const TransferMesh mesh = bindPoseMesh(asset, d);
  EXPECT_FALSE(d.ok());
  std::printf("%s", d.format().c_str());
  const std::string text = d.format();
  EXPECT_NE(text.find("bad.glb"), std::string::npos);
  EXPECT_NE(text.find("non-finite"), std::string::npos);
  EXPECT_NE(text.find("mesh 'body' primitive 1"), std::string::npos);
  EXPECT_NE(text.find("'hat'"), std::string::npos);
  EXPECT_EQ(mesh.primitiveVertexOffset, (std::vector<std::size_t>{0, 0, 3}));  // NaN one and hat skipped
  EXPECT_EQ(mesh.positions.size(), 3u);
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2}));
}

// Split per-face vertices weld by position: each corner gets the diagonal, as the cube's
// normal cone there demands, not its own face's normal.
TEST(TransferMesh, GeometricNormalsWeldSplitCorners) {
  const TransferMesh cube = splitCube();
  const std::vector<glm::vec3> n = geometricVertexNormals(cube);
  ASSERT_EQ(n.size(), 24u);
  for (std::size_t v = 0; v < n.size(); ++v) {
    const glm::vec3 p = cube.positions[v];
    expectNear(n[v], glm::normalize(p), 1e-5f, "corner normal");  // corners are (+-1, +-1, +-1)
  }
  // Without the weld (each face its own primitive) a vertex sees only its face.
  TransferMesh apart = cube;
  apart.primitiveVertexOffset = {0, 4, 8, 12, 16, 20};
  const std::vector<glm::vec3> faces = geometricVertexNormals(apart);
  for (std::size_t v = 0; v < faces.size(); ++v) expectNear(faces[v], cube.normals[v], 1e-5f, "face normal");

  EXPECT_NEAR(rayOriginOffset(cube), 1e-4f * 2.0f * std::sqrt(3.0f), 1e-9f);
  EXPECT_NEAR(rayOriginOffset(cube, 0.5f), std::sqrt(3.0f), 1e-6f);
}

TEST(TransferMesh, GeometricNormalsSurviveBadTriangles) {
  TransferMesh m = splitCube();
  m.indices.insert(m.indices.end(), {0, 1, 99, 2, 2, 2});  // out of range; degenerate
  m.positions.push_back({kNaN, 0, 0});                      // a stray vertex with no face
  m.normals.push_back({0, 0, 1});
  const std::vector<glm::vec3> n = geometricVertexNormals(m);
  ASSERT_EQ(n.size(), 25u);
  expectNear(n[0], glm::normalize(m.positions[0]), 1e-5f, "corner still diagonal");
  expectNear(n[24], {0, 0, 1}, 0.0f, "no face: the shading normal");
}
