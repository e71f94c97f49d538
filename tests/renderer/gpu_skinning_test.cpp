// GPU skinning against a CPU reference: the same posed frame skinned on the CPU
// here (linear blend skinning written out in the test) and drawn as a rigid mesh,
// then skinned on the GPU from the bridge's palette; the two pictures must agree.
// Also: every sub-mesh is drawn, textures show, morph targets move the mouth.
#include <epoxy/gl.h>

#include <cstdio>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_fixture.hpp"
#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette_ar/render/character_renderer.hpp"
#include "marionette_ar/render/render_target.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

struct Posed {
  std::shared_ptr<const Asset> asset;  // what the renderer draws; the rig keeps no meshes
  std::shared_ptr<Rig> rig;
  std::unique_ptr<Scene> scene;
  Character* character = nullptr;
};

Posed posedCharacter(const std::string& path, double seconds) {
  Posed p;
  ImportResult imported = importAsset(path);
  EXPECT_TRUE(imported.ok()) << imported.diagnostics.format();
  if (!imported.ok()) return p;
  p.asset = std::make_shared<const Asset>(std::move(*imported.asset));
  p.rig = std::make_shared<Rig>(*p.asset);
  p.scene = std::make_unique<Scene>();
  p.character = p.scene->addCharacter("c", p.rig);
  p.scene->update(0.0);
  if (seconds > 0.0) p.scene->update(seconds);
  return p;
}

// The CPU reference: each vertex = sum_k w_k * palette[j_k] * v (and normals by the
// matrices' linear part), in model space, as a rigid (unskinned) copy of the asset.
Asset cpuSkinned(const Asset& asset, const TransformBuffer& buffer) {
  Asset out = asset;
  const auto palette = buffer.skinningMatrices();
  const auto model = buffer.modelMatrices();
  for (Mesh& mesh : out.meshes) {
    for (MeshPrimitive& p : mesh.primitives) {
      for (std::size_t i = 0; i < p.positions.size(); ++i) {
        glm::mat4 m(0.0f);
        if (mesh.skinned && p.joints.size() == p.positions.size()) {
          for (int k = 0; k < 4; ++k) m += p.weights[i][k] * palette[p.joints[i][k]];
        } else {
          m = mesh.joint >= 0 ? model[std::size_t(mesh.joint)] : glm::mat4(1.0f);
        }
        p.positions[i] = glm::vec3(m * glm::vec4(p.positions[i], 1.0f));
        if (i < p.normals.size()) p.normals[i] = glm::mat3(m) * p.normals[i];
      }
      p.joints.clear();
      p.weights.clear();
    }
    mesh.skinned = false;
    mesh.joint = -1;
  }
  return out;
}

glm::mat4 framing(const Asset& asset, const TransformBuffer& buffer) {
  // Look at the posed character's bounds from the front.
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const glm::mat4& m : buffer.modelMatrices()) {
    lo = glm::min(lo, glm::vec3(m[3]));
    hi = glm::max(hi, glm::vec3(m[3]));
  }
  (void)asset;
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float size = std::max(0.5f, glm::length(hi - lo));
  const glm::mat4 view = glm::lookAt(centre + glm::vec3(0, 0, 1.6f * size), centre, glm::vec3(0, 1, 0));
  return glm::perspective(glm::radians(45.0f), 1.0f, 0.01f * size, 10.0f * size) * view;
}

ar::Image8 render(const ar::CharacterModel& model, const ar::CharacterPose& pose, const glm::mat4& viewProjection,
                  int outputMode, ar::RenderTarget& target) {
  const ar::ShaderProgram& program = GlTest::characterProgram();
  target.bind();
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  ar::Lighting lighting;
  lighting.outputMode = outputMode;
  lighting.irradianceSH[0] = glm::vec3(3.0f);
  ar::drawCharacter(program, model, pose, glm::mat4(1.0f), viewProjection, lighting);
  ar::Image8 image;
  target.read(image);
  return image;
}

class GpuSkinning : public GlTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(GpuSkinning, MatchesCpuReference) {
  const std::string path = GetParam();
  MARIONETTE_REQUIRE_FILE(path);
  Posed posed = posedCharacter(path, 0.7);  // mid-clip: joints far from their rest
  ASSERT_NE(posed.character, nullptr);
  const Asset& asset = *posed.asset;
  const TransformBuffer& buffer = posed.character->transformBuffer();

  Diagnostics error;
  ar::CharacterModel gpuModel, cpuModel;
  ASSERT_TRUE(gpuModel.upload(asset, error)) << error.format();
  const Asset reference = cpuSkinned(asset, buffer);
  ASSERT_TRUE(cpuModel.upload(reference, error)) << error.format();
  std::size_t primitives = 0;
  for (const Mesh& m : asset.meshes) primitives += m.primitives.size();
  EXPECT_EQ(gpuModel.primitiveCount(), primitives) << "every sub-mesh is drawn";

  ar::CharacterPose posedGpu(asset.skeleton), identity(asset.skeleton);
  posedGpu.update(buffer);
  ar::RenderTarget target;
  ASSERT_TRUE(target.create(256, 256, 1, error)) << error.format();  // no multisampling: compare exact coverage
  const glm::mat4 vp = framing(asset, buffer);
  for (int mode : {1, 2}) {  // base colour (positions), then normals
    const ar::Image8 gpu = render(gpuModel, posedGpu, vp, mode, target);
    const ar::Image8 cpu = render(cpuModel, identity, vp, mode, target);
    const int covered = coveredPixels(cpu, 0, 0, 0);
    EXPECT_GT(covered, 256 * 256 / 50) << "the character covers too little of the frame to compare";
    const ImageDifference d = compareImages(gpu, cpu, 24);
    std::printf("%s mode %d: %d character pixels, %.4f %% differ by > 24/255, mean %.4f/255\n", path.c_str(), mode,
                covered, 100.0 * d.fractionOver, d.meanAbs);
    // Float rounding moves a few edge pixels; a wrong matrix moves whole limbs.
    EXPECT_LT(d.fractionOver, 0.004) << path << " mode " << mode << ": mean " << d.meanAbs;
    EXPECT_LT(d.meanAbs, 0.5) << path << " mode " << mode;
    // And the test could fail: the rest pose (identity palette) differs from the posed frame.
    if (mode == 1) {
      ar::CharacterPose rest(asset.skeleton);
      const ar::Image8 unposed = render(gpuModel, rest, vp, mode, target);
      EXPECT_GT(compareImages(unposed, cpu, 24).fractionOver, 0.01) << "the pose does not show";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Characters, GpuSkinning,
                         ::testing::Values(assimpModel("X/BCN_Epileptic.X"),
                                           sharedAsset("characters/RobotExpressive.glb"),
                                           sharedAsset("characters/CesiumMan.glb")),
                         [](const ::testing::TestParamInfo<std::string>& param_info) {  // the file's stem: no path in the name
                           return std::filesystem::path(param_info.param).stem().string();
                         });

TEST_F(GlTest, TexturesShowOnGodette) {
  const std::string path = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(path);
  Posed posed = posedCharacter(path, 0.0);
  ASSERT_NE(posed.character, nullptr);
  const Asset& asset = *posed.asset;
  Diagnostics warnings, error;
  ar::CharacterModel textured, plain;
  ASSERT_TRUE(textured.upload(asset, warnings)) << warnings.format();
  EXPECT_TRUE(warnings.items.empty()) << warnings.format();
  Asset untextured = asset;
  for (Material& m : untextured.materials) m.baseColorTexture.clear();
  ASSERT_TRUE(plain.upload(untextured, error)) << error.format();
  ar::CharacterPose pose(asset.skeleton);
  pose.update(posed.character->transformBuffer());
  ar::RenderTarget target;
  ASSERT_TRUE(target.create(256, 256, 1, error)) << error.format();
  const glm::mat4 vp = framing(asset, posed.character->transformBuffer());
  const ar::Image8 a = render(textured, pose, vp, 1, target), b = render(plain, pose, vp, 1, target);
  // Textures change most of the character's pixels (hair, clothes, face).
  EXPECT_GT(compareImages(a, b, 24).fractionOver * 256 * 256, 0.3 * coveredPixels(b, 0, 0, 0));
}

TEST_F(GlTest, VisemeMorphMovesGodettesMouth) {
  const std::string path = sharedAsset("characters/Godette_vrm_v4.vrm");
  MARIONETTE_REQUIRE_FILE(path);
  Posed posed = posedCharacter(path, 0.0);
  ASSERT_NE(posed.character, nullptr);
  const Asset& asset = *posed.asset;
  int ah = -1;
  for (std::size_t i = 0; i < asset.morphTargets.size(); ++i)
    if (asset.morphTargets[i] == "vrm_aa" || asset.morphTargets[i] == "ah") ah = int(i);
  ASSERT_GE(ah, 0) << "Godette's 'aa' mouth shape";
  Diagnostics error;
  ar::CharacterModel model;
  ASSERT_TRUE(model.upload(asset, error)) << error.format();
  ASSERT_GT(model.morphTargetCount(), 0u);

  // Frame the head: Godette is chibi, her head is the top third of her bounds; her mesh faces -Z (VRM 0.x).
  const TransformBuffer& rest = posed.character->transformBuffer();
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (const Mesh& m : asset.meshes)
    for (const MeshPrimitive& p : m.primitives)
      for (const glm::vec3& v : p.positions) lo = glm::min(lo, v), hi = glm::max(hi, v);
  const float height = hi.y - lo.y;
  const glm::vec3 face(0.5f * (lo.x + hi.x), hi.y - 0.22f * height, 0.0f);
  const glm::mat4 vp = glm::perspective(glm::radians(30.0f), 1.0f, 0.01f, 10.0f) *
                       glm::lookAt(face - glm::vec3(0, 0, 0.55f * height), face, glm::vec3(0, 1, 0));
  TransformBuffer open = rest;
  open.writeMorphWeights()[std::size_t(ah)] = 1.0f;
  ar::CharacterPose closedPose(asset.skeleton), openPose(asset.skeleton);
  closedPose.update(rest);
  openPose.update(open);
  ar::RenderTarget target;
  ASSERT_TRUE(target.create(256, 256, 1, error)) << error.format();
  const ar::Image8 closed = render(model, closedPose, vp, 1, target), opened = render(model, openPose, vp, 1, target);
  if (const char* dir = std::getenv("MARIONETTE_TEST_IMAGES")) {  // to look at them
    (void)ar::writeImage(std::string(dir) + "/godette_mouth_closed.png", closed, error);
    (void)ar::writeImage(std::string(dir) + "/godette_mouth_open.png", opened, error);
  }
  const ImageDifference d = compareImages(closed, opened, 24);
  EXPECT_GT(d.fractionOver * d.pixels, 150) << "the open mouth changes too few pixels";
  EXPECT_LT(d.fractionOver, 0.2) << "more than the mouth moved";
}

}  // namespace
}  // namespace marionette::test
