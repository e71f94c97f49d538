// PRT report, 3. end to end on RobotExpressive, shadowed: sum_i L_i T_v,i against ray-traced
// irradiance, with the precompute and relight times.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "marionette/core/finite.hpp"
#include "marionette/io/import.hpp"
#include "marionette/prt/ray_occlusion.hpp"
#include "marionette/prt/relight.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/transfer.hpp"
#include "marionette/prt/transfer_mesh.hpp"
#include "prt_report_detail.hpp"
#include "report_tables.hpp"

namespace marionette::cli::detail {

namespace {

// f(i) for i in [0, count) on `threads` threads (dynamic, one index at a time).
void parallelFor(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& f) {
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < count;) f(i);
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, k > 0 ? k - 1 : 0)];
}

ChannelError channelError(const std::vector<glm::dvec3>& approx, const std::vector<glm::dvec3>& reference) {
  ChannelError e;
  for (int c = 0; c < 3; ++c) {
    double mean = 0.0;
    for (const auto& r : reference) mean += r[c] / static_cast<double>(reference.size());
    std::vector<double> rel(reference.size());
    double sum = 0.0;
    for (std::size_t v = 0; v < reference.size(); ++v) {
      rel[v] = mean > 0 ? std::abs(approx[v][c] - reference[v][c]) / mean : std::abs(approx[v][c] - reference[v][c]);
      sum += rel[v];
    }
    e.mean[c] = reference.empty() ? 0.0 : sum / static_cast<double>(reference.size());
    e.p95[c] = percentile(rel, 0.95);
  }
  return e;
}

}  // namespace

bool measureEndToEnd(const Plan& plan, const ReportOptions& o, const fs::path& data, EndToEndResult& result,
                     Diagnostics& diagnostics) {
  std::fprintf(stderr, "prt report: 3/4 end to end: loading RobotExpressive\n");
  const std::string character = o.assets + "/characters/RobotExpressive.glb";
  ImportResult imported = importAsset(character, {.isolateThirdPartyParsers = true});  // a tool: isolated
  if (!imported.asset) {
    diagnostics.items.insert(diagnostics.items.end(), imported.diagnostics.items.begin(), imported.diagnostics.items.end());
    return false;
  }
  Diagnostics d;
  const prt::TransferMesh mesh = prt::bindPoseMesh(*imported.asset, d);
  std::unique_ptr<prt::OcclusionTracer> tracer = prt::makeEmbreeOcclusion(mesh, d);
  if (!d.ok() || !tracer || mesh.positions.empty()) {
    diagnostics.items.insert(diagnostics.items.end(), d.items.begin(), d.items.end());
    diagnostics.error(character, "no mesh to trace the transfer on");
    return false;
  }
  const std::size_t vertexCount = mesh.positions.size();
  result.vertices = vertexCount;

  const std::vector<MapSpec> mapSpecs{{"blender_forest", o.assets + "/envmaps/blender_studiolight_forest.exr"},
                                      {"royal_esplanade", o.assets + "/envmaps/royal_esplanade_1k.hdr"}};
  std::vector<prt::EnvironmentMap> maps;
  for (const MapSpec& spec : mapSpecs) {
    const std::optional<prt::EnvironmentMap> full = loadMap(spec.path, diagnostics);
    if (!full) return false;
    std::optional<prt::EnvironmentMap> small = boxDownsample(*full, plan.downWidth, plan.downHeight);
    if (!small)
      return diagnostics.error(spec.path, str("%dx%d is not a multiple of %dx%d", full->width(), full->height(),
                                              plan.downWidth, plan.downHeight)),
             false;
    maps.push_back(std::move(*small));
    result.maps.push_back(spec.name);
  }
  result.downWidth = plan.downWidth, result.downHeight = plan.downHeight;

  // The reference: per vertex, every pixel of the downsampled map, a ray toward its centre
  // from the same origin computeTransfer uses (position + offset * geometric normal).
  const prt::TransferOptions defaults;
  const std::vector<glm::vec3> geometric = prt::geometricVertexNormals(mesh);
  const float offset = prt::rayOriginOffset(mesh, defaults.originOffset);
  const std::size_t stride = std::max<std::size_t>(1, vertexCount / static_cast<std::size_t>(plan.subsetVertices));
  std::vector<std::size_t> candidates;
  for (std::size_t k = 0; k < static_cast<std::size_t>(plan.subsetVertices) && k * stride < vertexCount; ++k)
    candidates.push_back(k * stride);
  result.candidates = candidates.size();
  const int pixels = plan.downWidth * plan.downHeight;
  std::vector<glm::dvec3> directions(static_cast<std::size_t>(pixels));
  std::vector<double> solidAngle(static_cast<std::size_t>(pixels));
  for (int r = 0; r < plan.downHeight; ++r)
    for (int c = 0; c < plan.downWidth; ++c) {
      const auto k = static_cast<std::size_t>(r * plan.downWidth + c);
      directions[k] = maps[0].texelDirection(c, r);
      solidAngle[k] = maps[0].texelSolidAngle(r);
    }
  auto usable = [](const glm::vec3& v) {
    return isFinite(v) && glm::dot(v, v) > 1e-12f;
  };
  std::vector<std::vector<glm::dvec3>> reference(maps.size(), std::vector<glm::dvec3>(candidates.size()));
  std::vector<double> occludedFraction(candidates.size(), 0.0);
  std::vector<glm::vec3> shadingNormal(candidates.size());
  std::fprintf(stderr, "prt report: 3/4 end to end: ray-traced reference, %zu vertices x %d pixels\n",
               candidates.size(), pixels);
  const auto referenceStart = Clock::now();
  parallelFor(candidates.size(), o.threads, [&](std::size_t j) {
    const std::size_t v = candidates[j];
    const glm::vec3 n = usable(mesh.normals[v]) ? glm::normalize(mesh.normals[v]) : glm::vec3(0, 1, 0);
    const glm::vec3 g = usable(geometric[v]) ? geometric[v] : n;
    shadingNormal[j] = n;
    const glm::vec3 origin = mesh.positions[v] + offset * g;
    std::vector<prt::OcclusionRay> rays;
    std::vector<std::size_t> pixel;
    std::vector<double> weight;
    for (std::size_t k = 0; k < directions.size(); ++k) {
      const double c = glm::dot(glm::dvec3(n), directions[k]);
      if (c <= 0.0) continue;
      rays.push_back({origin, 0.0f, glm::vec3(directions[k]), std::numeric_limits<float>::infinity()});
      pixel.push_back(k);
      weight.push_back(c * solidAngle[k]);
    }
    std::vector<std::uint8_t> hit(rays.size());
    tracer->occluded(rays, hit);
    double blocked = 0.0, total = 0.0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      total += weight[i];
      if (hit[i]) {
        blocked += weight[i];
        continue;
      }
      for (std::size_t m = 0; m < maps.size(); ++m) {
        const glm::vec3 l = maps[m].texel(static_cast<int>(pixel[i]) % plan.downWidth,
                                          static_cast<int>(pixel[i]) / plan.downWidth);
        reference[m][j] += weight[i] * glm::dvec3(l);
      }
    }
    occludedFraction[j] = total > 0 ? blocked / total : 1.0;
  });
  result.referenceSeconds = secondsSince(referenceStart);
  std::vector<std::size_t> kept;  // indices into candidates
  for (std::size_t j = 0; j < candidates.size(); ++j)
    if (occludedFraction[j] < 0.99) kept.push_back(j);
  result.buried = candidates.size() - kept.size();
  std::vector<std::vector<glm::dvec3>> keptReference(maps.size());
  for (std::size_t m = 0; m < maps.size(); ++m) {
    glm::dvec3 mean(0.0);
    for (std::size_t j : kept) keptReference[m].push_back(reference[m][j]), mean += reference[m][j];
    result.meanReference.push_back(mean / static_cast<double>(std::max<std::size_t>(1, kept.size())));
  }

  // Lighting from the same downsampled maps.
  std::vector<std::array<prt::ShCoefficients, prt::kMaxShBands + 1>> lighting(maps.size());
  for (std::size_t m = 0; m < maps.size(); ++m)
    for (int n = 2; n <= prt::kMaxShBands; ++n) lighting[m][n] = prt::projectRadiance(maps[m], n);

  auto prtIrradiance = [&](const prt::ShCoefficients& l, int count, const std::function<double(std::size_t, int)>& t) {
    std::vector<glm::dvec3> e(kept.size(), glm::dvec3(0.0));
    for (std::size_t q = 0; q < kept.size(); ++q)
      for (int i = 0; i < count; ++i) e[q] += l.c[static_cast<std::size_t>(i)] * t(q, i);
    return e;
  };

  // The precompute: the whole mesh for every (n, N), timed; the kept vertices' values used.
  std::array<double, prt::kMaxShBands + 1> relightUs{};
  for (int rays : plan.transferRays)
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      std::fprintf(stderr, "prt report: 3/4 end to end: precompute n = %d, N = %d\n", n, rays);
      prt::TransferOptions settings;
      settings.bands = n;
      settings.raysPerVertex = rays;
      settings.shadowed = true;
      settings.threads = o.threads;
      prt::TransferStats stats;
      Diagnostics run;
      const prt::VertexTransfer transfer = prt::computeTransfer(mesh, settings, tracer.get(), run, {}, &stats);
      if (!run.ok() || transfer.vertexCount() != vertexCount) {
        diagnostics.items.insert(diagnostics.items.end(), run.items.begin(), run.items.end());
        if (diagnostics.ok())
          diagnostics.error(character, str("the transfer has %zu vertices, not %zu", transfer.vertexCount(), vertexCount));
        return false;
      }
      if (rays == plan.transferRays.back()) {
        result.meshBuried = static_cast<std::size_t>(
            std::count_if(transfer.occluded.begin(), transfer.occluded.end(), [](float f) { return f >= 0.99f; }));
        const prt::TransferRelighter relighter(transfer);
        std::vector<glm::vec3> out(vertexCount);
        const double s = bestSeconds(plan.relightRepeats, [&] { relighter.relight(lighting[0][n], out); });
        relightUs[n] = 1e6 * s * 1e4 / static_cast<double>(vertexCount);
      }
      for (std::size_t m = 0; m < maps.size(); ++m) {
        const auto e = prtIrradiance(lighting[m][n], transfer.count(), [&](std::size_t q, int i) {
          return static_cast<double>(transfer.vertex(candidates[kept[q]])[static_cast<std::size_t>(i)]);
        });
        result.rows.push_back({result.maps[m], n, rays, stats.seconds, 0.0, channelError(e, keptReference[m])});
      }
    }
  for (EndToEndRow& row : result.rows) row.relightUs = relightUs[row.n];
  std::sort(result.rows.begin(), result.rows.end(), [&](const EndToEndRow& a, const EndToEndRow& b) {
    const auto ma = std::find(result.maps.begin(), result.maps.end(), a.map) - result.maps.begin();
    const auto mb = std::find(result.maps.begin(), result.maps.end(), b.map) - result.maps.begin();
    return std::tie(ma, a.n, a.rays) < std::tie(mb, b.n, b.rays);
  });
  // Unshadowed (closed form, no rays) against the same shadowed reference: what the shadows are worth.
  for (std::size_t m = 0; m < maps.size(); ++m)
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      std::vector<std::array<float, prt::kMaxShCoefficients>> t(kept.size());
      for (std::size_t q = 0; q < kept.size(); ++q) prt::unshadowedTransfer(shadingNormal[kept[q]], n, t[q]);
      const auto e = prtIrradiance(lighting[m][n], prt::shCount(n), [&](std::size_t q, int i) {
        return static_cast<double>(t[q][static_cast<std::size_t>(i)]);
      });
      result.unshadowed.push_back({result.maps[m], n, 0, 0.0, relightUs[n], channelError(e, keptReference[m])});
    }

  Csv csv(data / "end_to_end.csv",
          "map,n,N,precompute_s,relight_us_per_10k,mean_r,mean_g,mean_b,p95_r,p95_g,p95_b,mean_worst,p95_worst");
  auto write = [&](Csv& out, const EndToEndRow& r) {
    out.row({r.map, std::to_string(r.n), std::to_string(r.rays), str("%.4f", r.precomputeSeconds), str("%.2f", r.relightUs),
             str("%.6g", r.error.mean.x), str("%.6g", r.error.mean.y), str("%.6g", r.error.mean.z), str("%.6g", r.error.p95.x),
             str("%.6g", r.error.p95.y), str("%.6g", r.error.p95.z), str("%.6g", r.error.worstMean()),
             str("%.6g", r.error.worstP95())});
  };
  for (const auto& r : result.rows) write(csv, r);
  Csv un(data / "end_to_end_unshadowed.csv",
         "map,n,N,precompute_s,relight_us_per_10k,mean_r,mean_g,mean_b,p95_r,p95_g,p95_b,mean_worst,p95_worst");
  for (const auto& r : result.unshadowed) write(un, r);
  if (!csv.ok() || !un.ok()) return diagnostics.error((data / "end_to_end*.csv").string(), "cannot be written"), false;
  return true;
}

}  // namespace marionette::cli::detail
