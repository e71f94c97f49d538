// glTF import of small hand-written files generated here: STEP and CUBICSPLINE keys, quantized
// rotations, sparse morph targets, materials and a VRM 1.0 humanoid, skins with intermediate
// nodes, broken files, and buffers or images outside the model's folder.
#include <gtest/gtest.h>

#include "gltf_import_helpers.hpp"

namespace marionette {
namespace {

using namespace gltf_test;

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
