// Run-time relighting on the CPU: per vertex, E_v = sum_i L_i T_v,i for the RGB lighting
// coefficients L (radiance SH of the environment, already turned into the character's model
// frame) and the vertex's transfer T. The renderer multiplies by albedo / pi, the texture and
// the exposure. The transfer is kept in blocks of 8 vertices, coefficient-major inside a block
// (each block's floats contiguous), so that the inner loop runs over 8 vertices at once in
// vector registers and reads memory in order.
#pragma once
#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <vector>

#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/transfer.hpp"

namespace marionette::prt {

class TransferRelighter {
 public:
  TransferRelighter() = default;
  explicit TransferRelighter(const VertexTransfer& transfer);

  [[nodiscard]] int bands() const noexcept { return bands_; }
  [[nodiscard]] std::size_t vertexCount() const noexcept { return vertices_; }

  // out[v] = sum_i L_i T_v,i over min(lighting.bands, bands()) bands. out.size() must be
  // vertexCount() (otherwise nothing is written). No allocation, noexcept.
  void relight(const ShCoefficients& lighting, std::span<glm::vec3> out) const noexcept;

 private:
  int bands_ = 0;
  std::size_t vertices_ = 0, stride_ = 0;
  std::vector<float> transfer_;  // [vertex / 8][coefficient][vertex % 8]; stride_ = vertices padded to 8
};

}  // namespace marionette::prt
