#include "marionette/prt/relight.hpp"

#include <algorithm>

namespace marionette::prt {

namespace {
constexpr std::size_t kBlock = 8;
}

TransferRelighter::TransferRelighter(const VertexTransfer& t)
    : bands_(t.bands), vertices_(t.vertexCount()), stride_((t.vertexCount() + kBlock - 1) / kBlock * kBlock) {
  const std::size_t count = static_cast<std::size_t>(t.count());
  transfer_.assign(count * stride_, 0.0f);
  for (std::size_t v = 0; v < vertices_; ++v)
    for (std::size_t i = 0; i < count; ++i) transfer_[i * stride_ + v] = t.coefficients[v * count + i];
}

void TransferRelighter::relight(const ShCoefficients& lighting, std::span<glm::vec3> out) const noexcept {
  if (out.size() != vertices_) return;
  const std::size_t count = static_cast<std::size_t>(shCount(std::min(bands_, lighting.bands)));
  std::array<float, kMaxShCoefficients> lr{}, lg{}, lb{};
  for (std::size_t i = 0; i < count; ++i)
    lr[i] = static_cast<float>(lighting.c[i].x), lg[i] = static_cast<float>(lighting.c[i].y),
    lb[i] = static_cast<float>(lighting.c[i].z);
  for (std::size_t v0 = 0; v0 < stride_; v0 += kBlock) {
    float r[kBlock] = {}, g[kBlock] = {}, b[kBlock] = {};
    for (std::size_t i = 0; i < count; ++i) {
      const float* t = transfer_.data() + i * stride_ + v0;
      for (std::size_t j = 0; j < kBlock; ++j) {
        r[j] += lr[i] * t[j];
        g[j] += lg[i] * t[j];
        b[j] += lb[i] * t[j];
      }
    }
    const std::size_t n = std::min(kBlock, vertices_ - v0);
    for (std::size_t j = 0; j < n; ++j) out[v0 + j] = {r[j], g[j], b[j]};
  }
}

}  // namespace marionette::prt
