#include "marionette/prt/transfer.hpp"

#include "marionette/core/finite.hpp"
#include "marionette/core/split_mix.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

#include <glm/geometric.hpp>

namespace marionette::prt {

namespace {
constexpr float kPiF = std::numbers::pi_v<float>;
using Clock = std::chrono::steady_clock;

double threadCpuSeconds() noexcept {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
// Sums the CPU time of worker threads (each adds its own once, when it ends).
struct CpuTotal {
  std::atomic<std::uint64_t> nanoseconds{0};
  void add(double seconds) noexcept { nanoseconds += static_cast<std::uint64_t>(seconds * 1e9); }
  [[nodiscard]] double seconds() const noexcept { return 1e-9 * static_cast<double>(nanoseconds.load()); }
};

// A vertex's own random stream from (seed, vertex), independent of threads.
using SplitMix = SplitMix64;
std::uint64_t vertexSeed(std::uint64_t seed, std::size_t vertex) noexcept {
  SplitMix s{seed * 0x2545F4914F6CDD1Dull + vertex};
  return s.next();
}

// An orthonormal basis around a unit normal (Duff et al. 2017, branchless).
void tangentFrame(const glm::vec3& n, glm::vec3& t, glm::vec3& b) noexcept {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

bool usable(const glm::vec3& v) noexcept {
  return isFinite(v) && glm::dot(v, v) > 1e-12f;
}

std::size_t vertexCountOf(const TransferMesh& mesh) noexcept { return mesh.positions.size(); }
}  // namespace

int stratifiedRayCount(int rays) noexcept {
  const int k = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(std::clamp(rays, 1, 1 << 20)))));
  return k * k;
}

namespace {
// Stratified cosine-weighted directions in a local frame (z = the normal), made once per
// precompute. Malley's method: a point uniform in area on the unit disc (r = sqrt(u1),
// phi = 2 pi u2), lifted to the hemisphere, has pdf cos(theta) / pi; cell (i, j) of the k x k
// grid jitters u1 in [i, i+1) / k and u2 in [j, j+1) / k. Each vertex then turns the pattern
// by its own random angle about its normal (Cranley-Patterson style, in azimuth): every vertex
// gets a jittered stratified set, neighbours get different ones, and a direction costs nine
// multiply-adds instead of random numbers, square roots and a sine and cosine.
struct StratifiedPattern {
  std::vector<glm::vec3> local;
};
StratifiedPattern makePattern(int rays, std::uint64_t seed) {
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(stratifiedRayCount(rays)))));
  StratifiedPattern p;
  p.local.reserve(static_cast<std::size_t>(k) * k);
  SplitMix rng{seed ^ 0xA5A5A5A5DEADBEEFull};
  const float inv = 1.0f / static_cast<float>(k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      const float u1 = (static_cast<float>(i) + rng.uniform()) * inv;
      const float u2 = (static_cast<float>(j) + rng.uniform()) * inv;
      const float r = std::sqrt(u1), phi = 2.0f * kPiF * u2;
      p.local.push_back({r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1))});
    }
  return p;
}
// The pattern about `normal`, turned by the vertex's own angle, handed to emit(k, direction).
template <class Emit>
void orientPattern(const StratifiedPattern& p, const glm::vec3& normal, std::uint64_t vertexSeed, Emit&& emit) noexcept {
  glm::vec3 t, b;
  tangentFrame(normal, t, b);
  SplitMix rng{vertexSeed};
  const float angle = 2.0f * kPiF * rng.uniform(), c = std::cos(angle), s = std::sin(angle);
  const glm::vec3 tt = c * t + s * b, bb = c * b - s * t;
  for (std::size_t k = 0; k < p.local.size(); ++k) {
    const glm::vec3& l = p.local[k];
    emit(k, l.x * tt + l.y * bb + l.z * normal);
  }
}
}  // namespace

void stratifiedCosineDirections(const glm::vec3& normal, int rays, std::uint64_t seed, std::vector<glm::vec3>& out) {
  const StratifiedPattern pattern = makePattern(rays, seed);
  out.resize(pattern.local.size());
  orientPattern(pattern, normal, seed, [&](std::size_t i, const glm::vec3& d) { out[i] = d; });
}

void sampleTransfer(const glm::vec3& normal, int bands, int rays, std::uint64_t seed,
                    const std::function<float(const glm::vec3&)>& visible, std::span<double> out) {
  bands = std::clamp(bands, kMinShBands, kMaxShBands);
  std::vector<glm::vec3> dirs;
  stratifiedCosineDirections(glm::normalize(normal), rays, seed, dirs);
  std::fill(out.begin(), out.begin() + shCount(bands), 0.0);
  ShBasis y{};
  for (const glm::vec3& d : dirs) {
    const float v = visible(d);
    if (v == 0.0f) continue;
    shBasis(bands, glm::dvec3(d), y);
    for (int i = 0; i < shCount(bands); ++i) out[static_cast<std::size_t>(i)] += v * y[i];
  }
  const double scale = std::numbers::pi / static_cast<double>(dirs.size());
  for (int i = 0; i < shCount(bands); ++i) out[static_cast<std::size_t>(i)] *= scale;
}

void unshadowedTransfer(const glm::vec3& normal, int bands, std::span<float> out) noexcept {
  bands = std::clamp(bands, kMinShBands, kMaxShBands);
  std::array<float, kMaxShCoefficients> y{};
  shBasis(bands, normal, y);
  for (int i = 0; i < shCount(bands) && i < static_cast<int>(out.size()); ++i)
    out[static_cast<std::size_t>(i)] = static_cast<float>(cosineLobeBand(shBandOf(i))) * y[i];
}

void coneTransfer(const glm::dvec3& normal, int bands, double halfAngle, std::span<double> out) {
  bands = std::clamp(bands, kMinShBands, kMaxShBands);
  static const GaussLegendre gl = gaussLegendre(16);  // degree <= 1 + 7: exact
  const double lo = std::cos(std::clamp(halfAngle, 0.0, std::numbers::pi / 2));
  ShBasis y{};
  shBasis(bands, normal, y);
  for (int l = 0; l < bands; ++l) {
    double zonal = 0.0;
    for (std::size_t k = 0; k < gl.nodes.size(); ++k) {
      const double t = lo + (1.0 - lo) * 0.5 * (gl.nodes[k] + 1.0);
      zonal += 0.5 * (1.0 - lo) * gl.weights[k] * t * normalizedLegendre(l, 0, t);
    }
    zonal *= 2.0 * std::numbers::pi * std::sqrt(4.0 * std::numbers::pi / (2.0 * l + 1.0));
    for (int m = -l; m <= l; ++m) out[static_cast<std::size_t>(shIndex(l, m))] = zonal * y[shIndex(l, m)];
  }
}

VertexTransfer computeTransfer(const TransferMesh& mesh, const TransferOptions& settings,
                               const OcclusionTracer* tracer, Diagnostics& diagnostics,
                               const TransferProgress& progress, TransferStats* stats) {
  const auto start = Clock::now();
  VertexTransfer result;
  if (settings.bands < 2 || settings.bands > kMaxShBands) {
    diagnostics.error("prt", "transfer bands must be 2.." + std::to_string(kMaxShBands) + ", got " +
                      std::to_string(settings.bands));
    return result;
  }
  if (settings.shadowed && settings.raysPerVertex < 1) {
    diagnostics.error("prt", "rays per vertex must be at least 1, got " + std::to_string(settings.raysPerVertex));
    return result;
  }
  if (settings.shadowed && !tracer) {
    diagnostics.error("prt", "shadowed transfer needs a ray tracer for the mesh");
    return result;
  }
  if (mesh.normals.size() != mesh.positions.size()) {
    diagnostics.error("prt", "the mesh has " + std::to_string(mesh.positions.size()) + " positions but " +
                      std::to_string(mesh.normals.size()) + " normals");
    return result;
  }
  const std::size_t vertices = vertexCountOf(mesh);
  const int count = shCount(settings.bands);
  result.bands = settings.bands;
  result.coefficients.assign(vertices * static_cast<std::size_t>(count), 0.0f);
  result.occluded.assign(vertices, 0.0f);

  // Shading normals for the cosine, geometric normals for the ray origins.
  std::vector<glm::vec3> geometric = geometricVertexNormals(mesh);
  std::size_t badNormals = 0;
  std::vector<glm::vec3> shading(vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    const glm::vec3 n = mesh.normals[v];
    shading[v] = usable(n) ? glm::normalize(n) : (usable(geometric[v]) ? glm::normalize(geometric[v]) : glm::vec3(0.0f));
    if (!usable(shading[v]) || !usable(mesh.positions[v])) ++badNormals;
    if (!usable(geometric[v])) geometric[v] = shading[v];
  }
  if (badNormals > 0)
    diagnostics.warning("prt", std::to_string(badNormals) +
                        " vertices have no usable normal or position; their transfer is zero");

  unsigned threads = settings.threads ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
  if (stats) *stats = TransferStats{.seconds = 0.0, .cpuSeconds = 0.0, .rays = 0, .threads = threads};
  if (!settings.shadowed) {  // closed form: nothing to sample
    for (std::size_t v = 0; v < vertices; ++v)
      if (usable(shading[v]) && usable(mesh.positions[v]))
        unshadowedTransfer(shading[v], settings.bands,
                           {result.coefficients.data() + v * static_cast<std::size_t>(count), static_cast<std::size_t>(count)});
    if (progress) progress(vertices, vertices);
    if (stats) stats->seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
  }

  const float offset = rayOriginOffset(mesh, settings.originOffset);
  const int rays = stratifiedRayCount(settings.raysPerVertex);
  const float scale = kPiF / static_cast<float>(rays);
  const StratifiedPattern pattern = makePattern(rays, settings.seed);
  constexpr std::size_t kChunk = 32;
  std::atomic<std::size_t> next{0}, done{0};
  CpuTotal cpu;
  auto work = [&](bool report) {
    const double cpuStart = threadCpuSeconds();
    std::vector<OcclusionRay> batch(static_cast<std::size_t>(rays));
    std::vector<std::uint8_t> hit(static_cast<std::size_t>(rays));
    std::array<float, kMaxShCoefficients> sum{};
    auto lastReport = Clock::now();
    for (std::size_t begin; (begin = next.fetch_add(kChunk)) < vertices;) {
      const std::size_t end = std::min(vertices, begin + kChunk);
      for (std::size_t v = begin; v < end; ++v) {
        if (!usable(shading[v]) || !usable(mesh.positions[v])) continue;
        const glm::vec3 origin = mesh.positions[v] + offset * geometric[v];
        orientPattern(pattern, shading[v], vertexSeed(settings.seed, v), [&](std::size_t k, const glm::vec3& d) {
          batch[k] = {origin, 0.0f, d, std::numeric_limits<float>::infinity()};
        });
        tracer->occluded(batch, hit);
        sum.fill(0.0f);
        std::size_t blocked = 0;
        for (std::size_t k = 0; k < batch.size(); ++k) {
          if (hit[k]) {
            ++blocked;
            continue;
          }
          addShBasis(settings.bands, batch[k].direction, sum.data());
        }
        float* out = result.coefficients.data() + v * static_cast<std::size_t>(count);
        for (int i = 0; i < count; ++i) out[i] = sum[static_cast<std::size_t>(i)] * scale;
        result.occluded[v] = static_cast<float>(blocked) / static_cast<float>(rays);
      }
      const std::size_t finished = done.fetch_add(end - begin) + (end - begin);
      if (report && progress && Clock::now() - lastReport > std::chrono::milliseconds(100)) {
        lastReport = Clock::now();
        progress(finished, vertices);
      }
    }
    cpu.add(threadCpuSeconds() - cpuStart);
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, false);
  work(true);
  for (auto& t : pool) t.join();
  if (progress) progress(vertices, vertices);
  if (stats) {
    stats->seconds = std::chrono::duration<double>(Clock::now() - start).count();
    stats->rays = static_cast<std::uint64_t>(vertices) * static_cast<std::uint64_t>(rays);
    stats->cpuSeconds = cpu.seconds();
  }
  return result;
}

RawOcclusionTime rawOcclusionSeconds(const TransferMesh& mesh, const TransferOptions& settings,
                                     const OcclusionTracer& tracer, std::size_t maxRays) {
  const std::size_t vertices = vertexCountOf(mesh);
  const int rays = stratifiedRayCount(settings.raysPerVertex);
  if (vertices == 0 || mesh.normals.size() != vertices) return {};
  const std::size_t perVertex = static_cast<std::size_t>(rays);
  const std::size_t used = std::max<std::size_t>(1, std::min(vertices, maxRays / perVertex));
  // The same rays as computeTransfer: same normals, origins and seeds.
  std::vector<glm::vec3> geometric = geometricVertexNormals(mesh);
  const float offset = rayOriginOffset(mesh, settings.originOffset);
  std::vector<OcclusionRay> all(used * perVertex);
  const StratifiedPattern pattern = makePattern(rays, settings.seed);
  for (std::size_t v = 0; v < used; ++v) {
    const glm::vec3 n = usable(mesh.normals[v]) ? glm::normalize(mesh.normals[v]) : glm::vec3(0, 1, 0);
    const glm::vec3 origin = mesh.positions[v] + offset * (usable(geometric[v]) ? geometric[v] : n);
    orientPattern(pattern, n, vertexSeed(settings.seed, v), [&](std::size_t k, const glm::vec3& d) {
      all[v * perVertex + k] = {origin, 0.0f, d, std::numeric_limits<float>::infinity()};
    });
  }
  const unsigned threads = settings.threads ? settings.threads : std::max(1u, std::thread::hardware_concurrency());
  std::atomic<std::size_t> next{0};
  CpuTotal cpu;
  auto work = [&] {
    const double cpuStart = threadCpuSeconds();
    std::vector<std::uint8_t> hit(perVertex);
    for (std::size_t v; (v = next.fetch_add(1)) < used;)
      tracer.occluded(std::span<const OcclusionRay>(all.data() + v * perVertex, perVertex), hit);
    cpu.add(threadCpuSeconds() - cpuStart);
  };
  const auto start = Clock::now();
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double scale = static_cast<double>(vertices) / static_cast<double>(used);
  return {seconds * scale, cpu.seconds() * scale};
}

}  // namespace marionette::prt
