// `marionette prt`: precomputed radiance transfer on the command line.
//   lighting-error  the n-band SH irradiance of a light probe against brute force
//   precompute      the transfer vectors of a character's mesh, into a cache file
//   report          the PRT accuracy report (prt_report.cpp)
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "marionette/io/import.hpp"
#include "marionette/prt/mirror_ball.hpp"
#include "marionette/prt/progress_bar.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/transfer.hpp"
#include "marionette/prt/transfer_cache.hpp"

namespace marionette::cli {

namespace {
int fail(const std::string& message) {
  std::fprintf(stderr, "marionette prt: error: %s\n", message.c_str());
  return 2;
}

bool windowFrom(const std::string& name, prt::ShWindow& w) {
  for (prt::ShWindow k : {prt::ShWindow::None, prt::ShWindow::Hann, prt::ShWindow::Lanczos, prt::ShWindow::Sinc4})
    if (name == prt::windowName(k)) return w = k, true;
  return false;
}

bool probeKindFrom(const std::string& name, prt::LightProbeKind& kind) {
  if (name == "latlong") return kind = prt::LightProbeKind::LatLong, true;
  if (name == "mirror-ball") return kind = prt::LightProbeKind::MirrorBall, true;
  if (name == "auto") return kind = prt::LightProbeKind::Auto, true;
  return false;
}

}  // namespace

int prtLightingErrorCommand(const PrtLightingErrorOptions& o) {
  prt::ShWindow window;
  if (!windowFrom(o.window, window)) return fail("--window '" + o.window + "': expected none, hann, lanczos or sinc4");
  prt::LightProbeKind kind;
  if (!probeKindFrom(o.probe, kind)) return fail("--probe '" + o.probe + "': expected latlong, mirror-ball or auto");
  prt::EnvironmentMapLoad load = prt::loadLightProbe(o.env, kind);
  std::fputs(load.diagnostics.format().c_str(), stderr);
  if (!load.map) return 2;
  const int bands = o.bands > 0 ? o.bands : prt::kDefaultLightingBands;
  const prt::IrradianceError e = prt::lightingError(*load.map, bands, window);
  if (o.json) {
    nlohmann::ordered_json j;
    j["mean"] = e.mean;
    j["max"] = e.max;
    j["bands"] = bands;
    j["window"] = o.window;
    j["env"] = o.env;
    std::printf("%s\n", j.dump().c_str());
  } else {
    std::printf("%s, %d bands (%d coefficients), window %s: relative irradiance error over 1000 normals: mean %.4f, max %.4f\n",
                o.env.c_str(), bands, bands * bands, o.window.c_str(), e.mean, e.max);
  }
  return load.diagnostics.hasWarnings() ? 1 : 0;
}

int prtPrecomputeCommand(const PrtPrecomputeOptions& o) {
  const std::string& file = o.mesh;
  ImportResult imported = importAsset(file, {.isolateThirdPartyParsers = true});  // a tool: isolated
  std::fputs(imported.diagnostics.format().c_str(), stderr);
  if (!imported.asset) return 2;
  Diagnostics d;
  const prt::TransferMesh mesh = prt::bindPoseMesh(*imported.asset, d);
  if (mesh.positions.empty()) d.error(file, "has no mesh to precompute the transfer of");
  std::fputs(d.format().c_str(), stderr);
  if (!d.ok()) return 2;

  prt::TransferOptions settings;
  settings.bands = o.bands > 0 ? o.bands : prt::kDefaultTransferBands;
  settings.raysPerVertex = o.rays;
  settings.shadowed = o.shadowed;
  settings.threads = static_cast<unsigned>(o.threads);
  Diagnostics run;
  std::unique_ptr<prt::OcclusionTracer> tracer;
  if (settings.shadowed) tracer = prt::makeEmbreeOcclusion(mesh, run);
  prt::TransferStats stats;
  const prt::VertexTransfer transfer =
      prt::computeTransfer(mesh, settings, tracer.get(), run, prt::terminalProgressBar("prt " + file), &stats);
  prt::RawOcclusionTime raw;
  if (tracer && transfer.bands > 0) raw = prt::rawOcclusionSeconds(mesh, settings, *tracer);
  // Throughput against Embree alone on the same rays, from CPU time: on a shared machine the
  // wall times of two passes see different loads, CPU times much less so.
  const double ratio = stats.cpuSeconds > 0.0 ? raw.cpuSeconds / stats.cpuSeconds : 0.0;
  if (transfer.bands > 0) (void)prt::saveTransfer(o.output, prt::transferCacheKey(mesh, settings), settings, transfer, run);
  std::fputs(run.format().c_str(), stderr);
  if (!run.ok()) return 2;
  if (o.json) {
    nlohmann::ordered_json j;
    j["vertices"] = transfer.vertexCount();
    j["seconds"] = stats.seconds;
    j["raw_ray_seconds"] = raw.seconds;
    j["cpu_seconds"] = stats.cpuSeconds;
    j["raw_ray_cpu_seconds"] = raw.cpuSeconds;
    j["throughput_ratio"] = ratio;
    j["rays"] = stats.rays;
    j["threads"] = stats.threads;
    j["bands"] = settings.bands;
    j["shadowed"] = settings.shadowed;
    std::printf("%s\n", j.dump().c_str());
  } else {
    std::printf("%s: %zu vertices, %d bands, %s, %.3f s", file.c_str(), transfer.vertexCount(), settings.bands,
                settings.shadowed ? "shadowed" : "unshadowed", stats.seconds);
    if (settings.shadowed)
      std::printf(" (%llu rays; Embree alone on the same rays %.3f s; %.0f %% of its throughput by CPU time)",
                  static_cast<unsigned long long>(stats.rays), raw.seconds, 100.0 * ratio);
    std::printf(" -> %s\n", o.output.c_str());
  }
  return run.hasWarnings() ? 1 : 0;
}
}  // namespace marionette::cli
