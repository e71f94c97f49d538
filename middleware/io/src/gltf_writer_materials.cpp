// glTF writer: materials (base colour, a dielectric) and the images of their
// base-colour textures, embedded in the buffer or referenced beside the file.
#include "marionette/core/finite.hpp"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "gltf_writer_context.hpp"

namespace marionette::gltf_writer_detail {
namespace {

namespace fs = std::filesystem;

std::string imageMimeType(const std::vector<unsigned char>& b) {
  static const unsigned char kPng[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (b.size() >= 8 && std::memcmp(b.data(), kPng, 8) == 0) return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  return {};
}

std::optional<std::vector<unsigned char>> readBytes(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) return std::nullopt;
  return b;
}

}  // namespace

// Materials whose texture some primitive cannot use (no TEXCOORD_0): the
// validator rejects a textured material on such a primitive.
std::vector<char> Writer::materialsWithoutUvUse() const {
  std::vector<char> bad(asset_.materials.size(), 0);
  for (const Mesh& mesh : asset_.meshes)
    for (const MeshPrimitive& p : mesh.primitives)
      if (p.material >= 0 && static_cast<std::size_t>(p.material) < bad.size() &&
          p.uvs.size() != p.positions.size())
        bad[static_cast<std::size_t>(p.material)] = 1;
  return bad;
}

std::optional<ImageBytes> Writer::embeddedImage(const Material& m) {
  const std::vector<unsigned char>* image = images_.find(EmbeddedImages::indexOf(m.baseColorTexture));
  if (!image) {
    warning("material '" + m.name + "': texture '" + m.baseColorTexture + "' is inside " +
            (asset_.sourcePath.empty() ? std::string("the source file") : "'" + asset_.sourcePath + "'") +
            " and its bytes cannot be read from there; the texture is dropped");
    return std::nullopt;
  }
  ImageBytes out{*image, imageMimeType(*image)};
  if (out.mimeType.empty()) {
    warning("material '" + m.name + "': texture '" + m.baseColorTexture +
            "' is neither PNG nor JPEG (what glTF allows); the texture is dropped");
    return std::nullopt;
  }
  return out;
}

std::optional<ImageBytes> Writer::fileImage(const Material& m) {
  auto bytes = readBytes(m.baseColorTexture);
  if (!bytes) {
    warning("material '" + m.name + "': texture file '" + m.baseColorTexture +
            "' cannot be read; the texture is dropped");
    return std::nullopt;
  }
  ImageBytes out{std::move(*bytes), {}};
  out.mimeType = imageMimeType(out.bytes);
  if (out.mimeType.empty()) {
    warning("material '" + m.name + "': texture file '" + m.baseColorTexture +
            "' is neither PNG nor JPEG (what glTF allows); the texture is dropped");
    return std::nullopt;
  }
  return out;
}

// The glTF image for a material's texture, shared by materials using the same
// one; -1 when dropped.
int Writer::image(const Material& m, Json& images, std::map<std::string, int>& known) {
  if (auto it = known.find(m.baseColorTexture); it != known.end()) return it->second;
  const bool embedded = m.baseColorTexture.rfind("embedded:", 0) == 0;
  std::optional<ImageBytes> bytes = embedded ? embeddedImage(m) : fileImage(m);
  int index = -1;
  if (bytes) {
    Json img = {{"mimeType", bytes->mimeType}};
    if (embedded || options_.embedTextures) {
      img["bufferView"] = buffer_.view(bytes->bytes.data(), bytes->bytes.size(), 0);
    } else {
      const fs::path dir = fs::absolute(fs::path(path_)).parent_path();
      img["uri"] = uriEncoded(fs::absolute(m.baseColorTexture).lexically_relative(dir).generic_string());
      img.erase("mimeType");
    }
    images.push_back(std::move(img));
    index = static_cast<int>(images.size()) - 1;
  }
  known[m.baseColorTexture] = index;
  return index;
}

void Writer::writeMaterials() {
  if (asset_.materials.empty()) return;
  const std::vector<char> noUvs = materialsWithoutUvUse();
  Json materials = Json::array(), images = Json::array(), textures = Json::array();
  std::map<std::string, int> known;
  for (std::size_t i = 0; i < asset_.materials.size(); ++i) {
    const Material& m = asset_.materials[i];
    glm::vec4 color = m.baseColor;
    if (!isFinite(color)) {
      warning("material '" + m.name + "': base colour is not finite; white is written");
      color = glm::vec4(1.0f);
    }
    const glm::vec4 clamped = glm::clamp(color, 0.0f, 1.0f);
    if (clamped != color) warning("material '" + m.name + "': base colour clamped to [0, 1] as glTF requires");
    // Material has no metallic value; a dielectric is the neutral choice (glTF's default is metal).
    Json pbr = {{"baseColorFactor", {clamped.r, clamped.g, clamped.b, clamped.a}}, {"metallicFactor", 0.0}};
    if (!m.baseColorTexture.empty()) {
      if (noUvs[i]) {
        warning("material '" + m.name + "': texture dropped, a primitive using it has no texture coordinates");
      } else if (const int img = image(m, images, known); img >= 0) {
        textures.push_back({{"source", img}});
        pbr["baseColorTexture"] = {{"index", textures.size() - 1}};
      }
    }
    Json mat = {{"pbrMetallicRoughness", std::move(pbr)}};
    if (!m.name.empty()) mat["name"] = m.name;
    materials.push_back(std::move(mat));
  }
  doc_["materials"] = std::move(materials);
  if (!images.empty()) doc_["images"] = std::move(images);
  if (!textures.empty()) doc_["textures"] = std::move(textures);
}

}  // namespace marionette::gltf_writer_detail
