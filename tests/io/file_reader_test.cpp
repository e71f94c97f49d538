// Loading through an engine's file reader (ImportOptions::readFile, SceneLoadOptions::readFile):
// every file comes from the reader, under paths that do not exist on disk, so a read that
// went to the disk instead would fail; the folder rule holds through it.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/rig/character_profile.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/scene_file/scene_file.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {

// A virtual file system: virtual path -> the bytes of a real file (or given text), and the
// paths asked for, in order.
struct VirtualFiles {
  std::map<std::string, std::string> files;
  std::vector<std::string> asked;

  void mount(const std::string& virtualPath, const std::string& realPath) {
    std::string bytes = test::readFile(realPath);
    ASSERT_FALSE(bytes.empty()) << "test data missing: " << realPath;
    files[virtualPath] = std::move(bytes);
  }
  FileReader reader() {
    return [this](const std::string& path, std::string& bytes, std::string& why) {
      asked.push_back(path);
      const auto it = files.find(path);
      if (it == files.end()) {
        why = "not in the archive";
        return false;
      }
      bytes = it->second;
      return true;
    };
  }
  [[nodiscard]] bool wasAsked(const std::string& path) const {
    return std::find(asked.begin(), asked.end(), path) != asked.end();
  }
};

const std::string kBoxFolder = assimpModel("glTF2/BoxTextured-glTF");

}  // namespace

// A .gltf whose buffer is a file of its own: the buffer comes from the reader too.
TEST(FileReader, GltfWithExternalBufferComesFromTheReader) {
  VirtualFiles vfs;
  vfs.mount("/archive/box/BoxTextured.gltf", kBoxFolder + "/BoxTextured.gltf");
  vfs.mount("/archive/box/BoxTextured0.bin", kBoxFolder + "/BoxTextured0.bin");
  vfs.mount("/archive/box/CesiumLogoFlat.png", kBoxFolder + "/CesiumLogoFlat.png");
  ImportOptions options;
  options.readFile = vfs.reader();
  const ImportResult fromArchive = importAsset("/archive/box/BoxTextured.gltf", options);
  ASSERT_TRUE(fromArchive.ok()) << fromArchive.diagnostics.format();
  EXPECT_TRUE(vfs.wasAsked("/archive/box/BoxTextured0.bin"));
  const ImportResult fromDisk = importAsset(kBoxFolder + "/BoxTextured.gltf");
  ASSERT_TRUE(fromDisk.ok()) << fromDisk.diagnostics.format();
  ASSERT_EQ(fromArchive.asset->meshes.size(), fromDisk.asset->meshes.size());
  EXPECT_EQ(fromArchive.asset->skeleton.jointCount(), fromDisk.asset->skeleton.jointCount());
}

// From memory: the bytes are the file; what it names is read through the reader.
TEST(FileReader, FromMemoryResolvesAgainstTheNameHint) {
  VirtualFiles vfs;
  vfs.mount("/archive/box/BoxTextured0.bin", kBoxFolder + "/BoxTextured0.bin");
  vfs.mount("/archive/box/CesiumLogoFlat.png", kBoxFolder + "/CesiumLogoFlat.png");
  ImportOptions options;
  options.readFile = vfs.reader();
  const std::string gltf = test::readFile(kBoxFolder + "/BoxTextured.gltf");
  const ImportResult r = importAssetFromMemory(gltf, "/archive/box/BoxTextured.gltf", options);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  EXPECT_FALSE(vfs.wasAsked("/archive/box/BoxTextured.gltf"));  // the bytes given are the file
  EXPECT_TRUE(vfs.wasAsked("/archive/box/BoxTextured0.bin"));

  const std::string glb = test::readFile(sharedAsset("characters/RobotExpressive.glb"));
  const ImportResult robot = importAssetFromMemory(glb, "RobotExpressive.glb", {.loadMeshes = false});
  ASSERT_TRUE(robot.ok()) << robot.diagnostics.format();
  const ImportResult robotFromDisk = importAsset(sharedAsset("characters/RobotExpressive.glb"), {.loadMeshes = false});
  ASSERT_TRUE(robotFromDisk.ok());
  EXPECT_EQ(robot.asset->skeleton.names, robotFromDisk.asset->skeleton.names);
  ASSERT_EQ(robot.asset->clips.size(), robotFromDisk.asset->clips.size());
  EXPECT_EQ(robot.asset->sourcePath, "RobotExpressive.glb");

  const ImportResult noName = importAssetFromMemory(glb, "robot", {});
  EXPECT_FALSE(noName.ok());
  EXPECT_NE(noName.diagnostics.format().find("needs a name with an extension"), std::string::npos);
}

#ifdef MARIONETTE_HAS_ASSIMP
// Assimp's formats read through the reader: a BVH from memory, and an OBJ whose .mtl is a
// second file (Assimp's IOSystem asks the reader for it).
TEST(FileReader, AssimpFormatsComeFromTheReader) {
  const std::string bvhPath = sharedAsset("motions/bvh/pirouette.bvh");
  const ImportResult fromMemory =
      importAssetFromMemory(test::readFile(bvhPath), "/archive/motions/pirouette.bvh", {.loadMeshes = false});
  ASSERT_TRUE(fromMemory.ok()) << fromMemory.diagnostics.format();
  const ImportResult fromDisk = importAsset(bvhPath, {.loadMeshes = false});
  ASSERT_TRUE(fromDisk.ok());
  EXPECT_EQ(fromMemory.asset->skeleton.names, fromDisk.asset->skeleton.names);
  ASSERT_EQ(fromMemory.asset->clips.size(), fromDisk.asset->clips.size());
  EXPECT_EQ(fromMemory.asset->clips[0].duration, fromDisk.asset->clips[0].duration);

  VirtualFiles vfs;
  vfs.mount("/archive/obj/concave_polygon.obj", assimpModel("OBJ/concave_polygon.obj"));
  vfs.mount("/archive/obj/concave_polygon.mtl", assimpModel("OBJ/concave_polygon.mtl"));
  ImportOptions options;
  options.readFile = vfs.reader();
  const ImportResult obj = importAsset("/archive/obj/concave_polygon.obj", options);
  ASSERT_TRUE(obj.ok()) << obj.diagnostics.format();
  EXPECT_TRUE(vfs.wasAsked("/archive/obj/concave_polygon.mtl"));
  for (const std::string& path : vfs.asked) EXPECT_EQ(path.rfind("/archive/obj/", 0), 0u) << path;
}
#endif  // MARIONETTE_HAS_ASSIMP

// The folder rule holds through the reader: a glTF naming "../x.bin" is an error naming the
// file, and the reader is never asked for it.
TEST(FileReader, FolderEscapeIsRefusedWithoutAskingTheReader) {
  VirtualFiles vfs;
  std::string gltf = test::readFile(kBoxFolder + "/BoxTextured.gltf");
  const std::string uri = "\"uri\": \"BoxTextured0.bin\"";
  const auto at = gltf.find(uri);
  ASSERT_NE(at, std::string::npos);
  gltf.replace(at, uri.size(), "\"uri\": \"../secret/BoxTextured0.bin\"");
  vfs.files["/archive/box/BoxTextured.gltf"] = gltf;
  vfs.mount("/archive/secret/BoxTextured0.bin", kBoxFolder + "/BoxTextured0.bin");
  ImportOptions options;
  options.readFile = vfs.reader();
  const ImportResult r = importAsset("/archive/box/BoxTextured.gltf", options);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.diagnostics.format().find("outside the model's folder"), std::string::npos) << r.diagnostics.format();
  EXPECT_FALSE(vfs.wasAsked("/archive/secret/BoxTextured0.bin"));
  options.allowFilesOutsideModelFolder = true;  // trusted files: allowed
  EXPECT_TRUE(importAsset("/archive/box/BoxTextured.gltf", options).ok());
  EXPECT_TRUE(vfs.wasAsked("/archive/secret/BoxTextured0.bin"));
}

// A reader that fails, or throws, is an error naming the file; never a crash.
TEST(FileReader, ReaderFailuresAreErrorsNamingTheFile) {
  ImportOptions options;
  options.readFile = [](const std::string&, std::string&, std::string& why) {
    why = "the archive is locked";
    return false;
  };
  ImportResult r = importAsset("/archive/robot.glb", options);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.diagnostics.format().find("/archive/robot.glb"), std::string::npos);
  EXPECT_NE(r.diagnostics.format().find("the archive is locked"), std::string::npos) << r.diagnostics.format();
  options.readFile = [](const std::string&, std::string&, std::string&) -> bool { throw std::runtime_error("boom"); };
  r = importAsset("/archive/robot.gltf", options);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.diagnostics.format().find("boom"), std::string::npos) << r.diagnostics.format();
  // A buffer the reader lacks: the glTF is named, and the missing file.
  VirtualFiles vfs;
  vfs.mount("/archive/box/BoxTextured.gltf", kBoxFolder + "/BoxTextured.gltf");
  options.readFile = vfs.reader();
  r = importAsset("/archive/box/BoxTextured.gltf", options);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.diagnostics.format().find("BoxTextured0.bin"), std::string::npos) << r.diagnostics.format();
}

// A whole scene file through the reader: the scene, the character (VRM), its profile and the
// joint map the profile names, a recorded line (WAV and alignment) and a BML file.
TEST(FileReader, SceneFileAndEverythingItNamesComeFromTheReader) {
  VirtualFiles vfs;
  vfs.mount("/pak/characters/Godette_vrm_v4.vrm", sharedAsset("characters/Godette_vrm_v4.vrm"));
  vfs.mount("/pak/profiles/Godette_vrm_v4.json", sourceFile("assets/profiles/Godette_vrm_v4.json"));
  vfs.mount("/pak/jointmaps/Godette_vrm_v4.json", sourceFile("assets/jointmaps/Godette_vrm_v4.json"));
  vfs.mount("/pak/speech/line.wav", sharedAsset("speech/arctic_a0009.wav"));
  vfs.mount("/pak/speech/line.phones.txt", sharedAsset("speech/arctic_a0009.phones.txt"));
  vfs.mount("/pak/bml/speaks.xml", sourceFile("assets/bml/godette_speaks.xml"));
  vfs.files["/pak/scenes/s.json"] = R"({
    "characters": [ { "name": "godette", "asset": "../characters/Godette_vrm_v4.vrm",
                      "profile": "../profiles/Godette_vrm_v4.json" } ],
    "speech": { "lines": [ { "text": "He turned sharply, and faced Gregson across the table.",
                             "audio": "../speech/line.wav", "alignment": "../speech/line.phones.txt" } ],
                "synthesizer": false },
    "bml": [ { "file": "../bml/speaks.xml", "time": 0.5, "character": "godette" } ] })";
  Scene scene;
  SceneLoadOptions options;
  options.readFile = vfs.reader();
  const SceneLoadResult r = loadSceneFile("/pak/scenes/s.json", scene, options);
  ASSERT_TRUE(r.ok()) << r.diagnostics.format();
  ASSERT_NE(scene.findCharacter("godette"), nullptr);
  for (const char* file : {"/pak/scenes/s.json", "/pak/characters/Godette_vrm_v4.vrm", "/pak/profiles/Godette_vrm_v4.json",
                           "/pak/jointmaps/Godette_vrm_v4.json", "/pak/speech/line.wav", "/pak/speech/line.phones.txt",
                           "/pak/bml/speaks.xml"})
    EXPECT_TRUE(vfs.wasAsked(file)) << file;
  for (const std::string& path : vfs.asked) EXPECT_TRUE(vfs.files.count(path)) << "asked for a file not in the archive: " << path;
  ASSERT_EQ(r.bml.size(), 1u);
  ASSERT_TRUE(r.bml[0].text.has_value());  // read during the load, through the reader
  EXPECT_EQ(*r.bml[0].text, vfs.files["/pak/bml/speaks.xml"]);
  // The profile's joint map was used: the same joints as the profile loaded from disk.
  const CharacterProfileResult fromDisk =
      loadCharacterProfile(sourceFile("assets/profiles/Godette_vrm_v4.json"), *r.assetOf("godette"));
  ASSERT_TRUE(fromDisk.diagnostics.ok());
  EXPECT_EQ(scene.findCharacter("godette")->rig().profile().head, fromDisk.profile.head);
  EXPECT_EQ(scene.findCharacter("godette")->rig().profile().leftArm.upper, fromDisk.profile.leftArm.upper);
}
