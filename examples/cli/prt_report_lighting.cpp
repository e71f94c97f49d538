// PRT report, 1. lighting truncation: n-band SH irradiance of the light probes against brute
// force, and the windows against ringing.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sphere_sampling.hpp"
#include "prt_report_detail.hpp"
#include "report_tables.hpp"

namespace marionette::cli::detail {

bool measureLighting(const Plan& plan, const ReportOptions& o, const fs::path& data, std::vector<LightingResult>& results,
                     Diagnostics& diagnostics) {
  const std::vector<glm::dvec3> normals = prt::fibonacciSphere(plan.lightingNormals);
  Csv csv(data / "lighting_truncation.csv", "map,n,coefficients,mean_rel_error,max_rel_error,projection_ms");
  Csv win(data / "lighting_windows.csv", "map,n,window,cutoff,mean_rel_error,max_rel_error,min_E_over_mean_E,window_ms");
  for (const MapSpec& spec : plan.lightingMaps) {
    std::fprintf(stderr, "prt report: 1/4 lighting truncation: %s\n", spec.name.c_str());
    const std::optional<prt::EnvironmentMap> map = loadMap(spec.path, diagnostics);
    if (!map) return false;
    LightingResult r;
    r.map = spec.name;
    r.width = map->width(), r.height = map->height();
    std::vector<glm::dvec3> reference;
    r.bruteForceMs = 1e3 * bestSeconds(1, [&] { reference = prt::bruteForceIrradiance(*map, normals, o.threads); });
    glm::dvec3 meanReference(0.0);
    for (const auto& e : reference) meanReference += e / static_cast<double>(reference.size());
    std::array<prt::ShCoefficients, kWindowBands.size()> windowInput;
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      prt::ShCoefficients radiance;
      r.projectionMs[n] = 1e3 * bestSeconds(plan.projectionRepeats, [&] { radiance = prt::projectRadiance(*map, n); });
      r.error[n] = prt::irradianceError(evaluateAll(prt::irradianceCoefficients(radiance), normals), reference);
      csv.row({spec.name, std::to_string(n), std::to_string(n * n), str("%.6g", r.error[n].mean),
               str("%.6g", r.error[n].max), str("%.3f", r.projectionMs[n])});
      for (std::size_t b = 0; b < kWindowBands.size(); ++b)
        if (n == kWindowBands[b]) windowInput[b] = radiance;
    }
    for (std::size_t b = 0; b < kWindowBands.size(); ++b)
    for (std::size_t w = 0; w < kWindows.size(); ++w) {
      LightingResult::Window& out = r.windows[b][w];
      prt::ShCoefficients windowed;
      out.ms = 1e3 * bestSeconds(1, [&] { windowed = prt::windowRadiance(windowInput[b], kWindows[w], &out.cutoff); });
      const std::vector<glm::dvec3> approx = evaluateAll(prt::irradianceCoefficients(windowed), normals);
      out.error = prt::irradianceError(approx, reference);
      out.minOverMean = std::numeric_limits<double>::infinity();
      for (const auto& e : approx)
        for (int c = 0; c < 3; ++c)
          if (meanReference[c] > 0) out.minOverMean = std::min(out.minOverMean, e[c] / meanReference[c]);
      if (!std::isfinite(out.minOverMean)) out.minOverMean = 0.0;
      win.row({spec.name, std::to_string(kWindowBands[b]), prt::windowName(kWindows[w]),
               std::isfinite(out.cutoff) ? str("%.4g", out.cutoff) : "inf", str("%.6g", out.error.mean),
               str("%.6g", out.error.max), str("%.6g", out.minOverMean), str("%.3f", out.ms)});
    }
    results.push_back(r);
  }
  if (!csv.ok() || !win.ok()) return diagnostics.error((data / "lighting_*.csv").string(), "cannot be written"), false;
  return true;
}

}  // namespace marionette::cli::detail
