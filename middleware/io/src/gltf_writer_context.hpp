// Private to the glTF writer: the Writer that every stage of the export shares —
// the inputs, the diagnostics, the JSON document and the binary buffer being
// built — with its stages, declared by the file of the concept that defines them.
#pragma once
#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gltf_binary_buffer.hpp"
#include "marionette/io/embedded_images.hpp"
#include "marionette/io/gltf_writer.hpp"

namespace marionette::gltf_writer_detail {

struct ImageBytes {
  std::vector<unsigned char> bytes;
  std::string mimeType;
};

// A relative URI: unreserved characters and '/' as they are, everything else %XX.
std::string uriEncoded(const std::string& path);

class Writer {
 public:
  Writer(const std::string& path, const Asset& asset, std::span<const Clip> clips, const GltfWriteOptions& options,
         Diagnostics& diag)
      : path_(path), asset_(asset), skeleton_(asset.skeleton), clips_(clips), options_(options), diag_(diag),
        images_(asset) {}

  void run();

 private:
  const std::string& path_;
  const Asset& asset_;
  const Skeleton& skeleton_;
  std::span<const Clip> clips_;
  const GltfWriteOptions& options_;
  Diagnostics& diag_;
  EmbeddedImages images_;
  bool ok_ = true;
  bool binary_ = true;

  Json doc_ = Json::object();
  Json nodes_ = Json::array();
  Json sceneNodes_ = Json::array();
  BinaryBuffer buffer_;
  std::vector<Clip> cleanClips_;
  std::vector<int> meshNode_;  // per Asset mesh: its node, or -1 when not written
  std::vector<int> materialIndex_;  // Asset material -> glTF material (all written, same order)
  int skin_ = -1;

  void error(std::string message) {
    diag_.error(path_, std::move(message));
    ok_ = false;
  }
  void warning(std::string message) { diag_.warning(path_, std::move(message)); }

  // gltf_writer.cpp: the skeleton checked, nodes and skin, the document and its files
  bool checkSkeleton();
  void writeNodes();
  Json rootSpaceNode(Json roots);
  void writeSkin();
  std::string binPath() const;
  void finishDocument();
  void save();

  // gltf_writer_materials.cpp: materials and their images
  std::vector<char> materialsWithoutUvUse() const;
  std::optional<ImageBytes> embeddedImage(const Material& m);
  std::optional<ImageBytes> fileImage(const Material& m);
  int image(const Material& m, Json& images, std::map<std::string, int>& known);
  void writeMaterials();

  // gltf_writer_mesh.cpp: meshes, their vertex attributes, skin weights and morph targets
  std::size_t skinAttributes(const Mesh& mesh, const MeshPrimitive& p, std::vector<glm::u16vec4>& joints,
                             std::vector<glm::vec4>& weights) const;
  struct PrimitiveIssues {
    std::size_t normals = 0, skin = 0;
    bool droppedUvs = false, droppedNormals = false;
  };
  bool primitiveData(const std::string& where, const MeshPrimitive& p);
  std::optional<Json> primitive(const Mesh& mesh, std::size_t pi, bool skinned);
  Json morphTargets(const std::string& where, const Mesh& mesh, const MeshPrimitive& p);
  void writeMeshes();
  void attachMeshNode(const Mesh& mesh, bool skinned, int index);
  std::vector<std::string> morphNames(const Mesh& mesh) const;

  // gltf_writer_animation.cpp: clips cleaned and checked, then written as animations
  bool prepareClips();
  struct Channels;  // one animation's samplers and channels
  void vec3Channel(Channels& ch, int node, const char* path, const Track<glm::vec3>& track);
  void rotationChannel(Channels& ch, int node, const Track<glm::quat>& track);
  void morphChannels(Channels& ch, const Clip& clip);
  void writeAnimations();
};

}  // namespace marionette::gltf_writer_detail
