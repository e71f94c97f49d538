// Per-vertex radiance transfer for diffuse surfaces (Sloan, Kautz and Snyder 2002): the SH
// coefficients T_i of V(w) max(0, n.w), so that at run time the irradiance at the vertex is
// sum_i L_i T_i for lighting coefficients L_i, and its radiance albedo / pi times that.
//   - Unshadowed (V = 1): T_i = A_l Y_i(n) in closed form. No rays, no sampling.
//   - Shadowed: V(w) = 0 where a ray from the vertex toward w hits the mesh itself. The
//     integral is estimated with N cosine-weighted directions, jittered and stratified on a
//     sqrt(N) x sqrt(N) grid, T_i = pi / N * sum_k V(w_k) Y_i(w_k). Ray origins are moved off
//     the surface along the geometric normal by a distance scaled to the mesh, so that a
//     convex mesh comes out 0 % occluded (no self-shadowing acne).
// Deterministic: the jittered pattern comes from the seed and each vertex turns it about its
// normal by an angle drawn from (seed, vertex index), whatever the thread count. Skinned characters: the transfer is computed in bind pose and then used in every pose,
// as the original system did (the shadows do not follow the limbs; docs/prt.md).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/ray_occlusion.hpp"
#include "marionette/prt/spherical_harmonics.hpp"
#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::prt {

inline constexpr int kDefaultTransferBands = 5;  // from the work-precision table: docs/accuracy.md "PRT"

struct TransferOptions {
  int bands = kDefaultTransferBands;   // 2..8
  int raysPerVertex = 1024;            // shadowed only; rounded up to a square (stratification)
  bool shadowed = true;
  unsigned threads = 0;                // 0: std::thread::hardware_concurrency()
  float originOffset = 1e-4f;          // ray origin offset, a fraction of the bounding-box diagonal
  std::uint64_t seed = 1;
};

// The per-vertex transfer vectors, vertex-major: coefficients[v * count() + i].
struct VertexTransfer {
  int bands = 0;
  std::vector<float> coefficients;
  // Shadowed: the fraction of each vertex's rays that were blocked (0 for unshadowed).
  std::vector<float> occluded;
  [[nodiscard]] int count() const noexcept { return shCount(bands); }
  [[nodiscard]] std::size_t vertexCount() const noexcept {
    return bands > 0 ? coefficients.size() / static_cast<std::size_t>(count()) : 0;
  }
  [[nodiscard]] std::span<const float> vertex(std::size_t v) const noexcept {
    return {coefficients.data() + v * static_cast<std::size_t>(count()), static_cast<std::size_t>(count())};
  }
};

struct TransferStats {
  double seconds = 0.0;          // wall time of the whole precompute
  double cpuSeconds = 0.0;       // CPU time of the worker threads (the per-vertex work), summed
  std::uint64_t rays = 0;        // rays cast (0 when unshadowed)
  unsigned threads = 0;
};

// Called from the calling thread with (vertices done, vertices in all), at most ~10 times a second.
using TransferProgress = std::function<void(std::size_t done, std::size_t total)>;

// The transfer of every vertex of `mesh`. Shadowed needs `tracer` (built from the same mesh);
// without it, or with bad settings, an error goes to `diagnostics` and the result is empty.
[[nodiscard]] VertexTransfer computeTransfer(const TransferMesh& mesh, const TransferOptions& settings,
                                             const OcclusionTracer* tracer, Diagnostics& diagnostics,
                                             const TransferProgress& progress = {}, TransferStats* stats = nullptr);

// One vertex's estimator, for the measurements: N stratified cosine-weighted directions about
// `normal`, each weighted by visible(direction) in [0, 1]. out holds count() values.
void sampleTransfer(const glm::vec3& normal, int bands, int rays, std::uint64_t seed,
                    const std::function<float(const glm::vec3&)>& visible, std::span<double> out);

// The stratified directions of one vertex (unit, in the hemisphere of `normal`), as
// computeTransfer casts them: ceil(sqrt(N))^2 of them.
void stratifiedCosineDirections(const glm::vec3& normal, int rays, std::uint64_t seed, std::vector<glm::vec3>& out);
[[nodiscard]] int stratifiedRayCount(int rays) noexcept;

// The closed-form unshadowed transfer of one normal: A_l Y_i(n).
void unshadowedTransfer(const glm::vec3& normal, int bands, std::span<float> out) noexcept;

// The exact transfer of a vertex that sees only a cone of half-angle `halfAngle` about its
// normal (pi / 2: unshadowed): T_lm = sqrt(4 pi / (2l + 1)) t_l Y_lm(n) with the zonal
// t_l = 2 pi int_{cos a}^{1} t Pbar_l^0(t) dt (Gauss-Legendre, exact for this polynomial).
// The oracle of the sampling-error measurement.
void coneTransfer(const glm::dvec3& normal, int bands, double halfAngle, std::span<double> out);

// Every ray of a shadowed precompute cast once more, with nothing else: the rays are made
// first (not timed), then only tracer.occluded runs, on `threads` threads. At most
// `maxRays` are cast (the times are scaled up to all of them; the rays of a big mesh would not
// fit in memory). For `marionette prt precompute --json`'s raw_ray_seconds. CPU seconds
// (summed over the threads) compare fairly with TransferStats::cpuSeconds on a machine that
// other work shares; wall seconds do not.
struct RawOcclusionTime {
  double seconds = 0.0, cpuSeconds = 0.0;
};
[[nodiscard]] RawOcclusionTime rawOcclusionSeconds(const TransferMesh& mesh, const TransferOptions& settings,
                                                   const OcclusionTracer& tracer,
                                                   std::size_t maxRays = std::size_t{1} << 24);

}  // namespace marionette::prt
