// Writing a character (skeleton, meshes, materials, morph targets) and clips as
// glTF 2.0, in a form the Khronos glTF-Validator accepts without errors.
//
// The container follows the extension of `path`:
//   .glb   one binary file (JSON chunk + BIN chunk holding every buffer and image);
//   .gltf  JSON, with the binary data in a file beside it named like the output
//          with the extension .bin ("walk.gltf" -> "walk.bin"), referenced by a
//          relative URI.
// Anything else is an error naming the path. See docs/gltf-export.md for what is
// written, what is dropped and how to validate the result (scripts/validate-gltf).
#pragma once
#include <span>
#include <string>

#include "marionette/core/diagnostic.hpp"
#include "marionette/asset/asset.hpp"

namespace marionette {

struct GltfWriteOptions {
  // Copy base-colour images (PNG or JPEG) into the file. When false, a texture
  // that is a file is referenced by a URI relative to the output's folder.
  bool embedTextures = true;
  std::string generator = "Marionette";  // asset.generator
};

// Writes `character` with one glTF animation per clip (clips bound to
// character.skeleton). Never throws. Errors (unwritable path, a clip that
// Clip::validate rejects, non-finite data, ...) name the file and the problem;
// with an error nothing is written. Repairs that change data (duplicate key times
// merged, non-unit quaternions normalized, zero normals, dropped textures) are
// warnings.
[[nodiscard]] Diagnostics writeGltf(const std::string& path, const Asset& character, std::span<const Clip> clips,
                                    const GltfWriteOptions& options = {});

}  // namespace marionette
