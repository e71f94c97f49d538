// The renderer's CPU side of precomputed radiance transfer (docs/ar-renderer.md,
// "PRT lighting"). At load, per distinct asset: the transfer mesh (rest pose, or the
// pose of a clip's frame), its transfer through the disk cache, and a relighter.
// Per frame, per character: the environment's radiance SH turned into the character's
// model frame, then E_v = sum_i L_i T_v,i for every vertex into a buffer sized at load.
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ar_scene_file.hpp"
#include "marionette/prt/relight.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sh_rotation.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette::ar {

// One asset's transfer, shared by every character made from it.
struct PrtAsset {
  std::vector<std::size_t> primitiveVertexOffset;  // prt::TransferMesh's, mesh-major
  std::size_t vertexCount = 0;
  prt::TransferRelighter relighter;
  bool shadowed = false, fromCache = false;
  std::string cachePath;
  double seconds = 0.0;     // the precompute's wall time (0 from the cache)
  std::uint64_t rays = 0;   // rays cast (0 from the cache or unshadowed)
  // "prt NAME: V vertices, N bands, shadowed, 12.3 s (1.2e6 rays)" or "... from cache PATH".
  [[nodiscard]] std::string describe(const std::string& name) const;
};

// Builds the transfer of `asset` (the one `rig` was made from) as `settings` say (which must not be Off). Problems
// go to `diagnostics` naming the asset (or `scenePath` and the key for an unknown pose
// clip); returns false when the asset cannot be lit by PRT.
bool loadPrtAsset(const Asset& asset, const Rig& rig, const ArPrt& settings, const std::string& scenePath, PrtAsset& out,
                  Diagnostics& diagnostics);

// The rotation that turns world-frame SH into the model frame of a character placed by
// `world`: the inverse of world's rotation part, orthonormalised (scale and shear dropped).
[[nodiscard]] glm::dmat3 worldToModelRotation(const glm::mat4& world) noexcept;

// One character's per-frame PRT light. Buffers are sized here; relight() allocates nothing.
class PrtCharacterLight {
 public:
  explicit PrtCharacterLight(const PrtAsset& asset) : asset_(&asset), irradiance_(asset.vertexCount) {}
  // `worldRadiance`: the environment's radiance SH in the world frame; `rotation` an
  // ShRotation of at least the asset's bands (built once). No allocation, noexcept.
  void relight(const prt::ShCoefficients& worldRadiance, const glm::mat4& world,
               const prt::ShRotation& rotation) noexcept;
  [[nodiscard]] std::span<const glm::vec3> irradiance() const noexcept { return irradiance_; }
  [[nodiscard]] const PrtAsset& asset() const noexcept { return *asset_; }

 private:
  const PrtAsset* asset_;
  prt::ShCoefficients modelRadiance_;
  std::vector<glm::vec3> irradiance_;
};

}  // namespace marionette::ar
