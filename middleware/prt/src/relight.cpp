#include "marionette/prt/relight.hpp"

#include <algorithm>
#include <cstring>

namespace marionette::prt {

namespace {
constexpr std::size_t kBlock = 8;

// Eight vertices' worth of floats: GCC/Clang vector extensions, so that the compiler keeps
// the three accumulators in registers (one AVX register each, or two SSE ones) instead of
// vectorising across coefficients as it chose to with plain arrays (measured 4x slower).
using Lanes = float __attribute__((vector_size(kBlock * sizeof(float))));

// The kernel, compiled twice: for AVX2 (8 vertices per instruction) and for the base x86-64
// (SSE2, two halves); the loader picks one for the machine (GCC function multi-versioning).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=haswell", "default")))
#endif
void relightKernel(const float* transfer, std::size_t stride, std::size_t vertices, std::size_t count, const float* lr,
                   const float* lg, const float* lb, glm::vec3* out) noexcept {
  for (std::size_t v0 = 0; v0 < stride; v0 += kBlock) {
    Lanes r{}, g{}, b{};
    const float* block = transfer + v0 * count;  // this block's count x 8 floats, contiguous
    for (std::size_t i = 0; i < count; ++i) {
      Lanes t;
      std::memcpy(&t, block + i * kBlock, sizeof t);
      r += lr[i] * t;
      g += lg[i] * t;
      b += lb[i] * t;
    }
    const std::size_t n = std::min(kBlock, vertices - v0);
    for (std::size_t j = 0; j < n; ++j) out[v0 + j] = {r[j], g[j], b[j]};
  }
}
}  // namespace

TransferRelighter::TransferRelighter(const VertexTransfer& t)
    : bands_(t.bands), vertices_(t.vertexCount()), stride_((t.vertexCount() + kBlock - 1) / kBlock * kBlock) {
  const std::size_t count = static_cast<std::size_t>(t.count());
  transfer_.assign(count * stride_, 0.0f);
  for (std::size_t v = 0; v < vertices_; ++v)
    for (std::size_t i = 0; i < count; ++i)
      transfer_[(v / kBlock * count + i) * kBlock + v % kBlock] = t.coefficients[v * count + i];
}

void TransferRelighter::relight(const ShCoefficients& lighting, std::span<glm::vec3> out) const noexcept {
  if (out.size() != vertices_) return;
  const std::size_t count = static_cast<std::size_t>(shCount(std::min(bands_, lighting.bands)));
  std::array<float, kMaxShCoefficients> lr{}, lg{}, lb{};
  for (std::size_t i = 0; i < count; ++i)
    lr[i] = static_cast<float>(lighting.c[i].x), lg[i] = static_cast<float>(lighting.c[i].y),
    lb[i] = static_cast<float>(lighting.c[i].z);
  relightKernel(transfer_.data(), stride_, vertices_, count, lr.data(), lg.data(), lb.data(), out.data());
}

}  // namespace marionette::prt
