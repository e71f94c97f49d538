// The light probes of the PRT report's experiments: loaded, box-downsampled keeping their power,
// and their SH irradiance evaluated at many normals.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "marionette/prt/mirror_ball.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "prt_report_detail.hpp"

namespace marionette::cli::detail {

std::optional<prt::EnvironmentMap> loadMap(const std::string& path, Diagnostics& diagnostics) {
  prt::EnvironmentMapLoad load = prt::loadLightProbe(path, prt::LightProbeKind::LatLong);
  if (!load.map)  // its errors (and warnings) name the file; a map read is not reported on
    diagnostics.items.insert(diagnostics.items.end(), load.diagnostics.items.begin(), load.diagnostics.items.end());
  return std::move(load.map);
}

// Box filter to width x height (the source's size must be a multiple of it), each source pixel
// weighted by its solid angle, so that the total power (sum of L dw) is kept.
std::optional<prt::EnvironmentMap> boxDownsample(const prt::EnvironmentMap& map, int width, int height) {
  if (map.width() == width && map.height() == height) return map;
  if (width <= 0 || height <= 0 || map.width() % width != 0 || map.height() % height != 0) return std::nullopt;
  const int fx = map.width() / width, fy = map.height() / height;
  std::vector<float> rgb(static_cast<std::size_t>(width) * height * 3);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      glm::dvec3 sum(0.0);
      double weight = 0.0;
      for (int rr = r * fy; rr < (r + 1) * fy; ++rr) {
        const double dw = map.texelSolidAngle(rr);
        for (int cc = c * fx; cc < (c + 1) * fx; ++cc) sum += dw * glm::dvec3(map.texel(cc, rr)), weight += dw;
      }
      const glm::dvec3 mean = sum / weight;
      float* p = &rgb[(static_cast<std::size_t>(r) * width + c) * 3];
      p[0] = static_cast<float>(mean.x), p[1] = static_cast<float>(mean.y), p[2] = static_cast<float>(mean.z);
    }
  return prt::EnvironmentMap(width, height, std::move(rgb));
}

std::vector<glm::dvec3> evaluateAll(const prt::ShCoefficients& irradianceCoeffs, const std::vector<glm::dvec3>& normals) {
  std::vector<glm::dvec3> out;
  out.reserve(normals.size());
  for (const auto& n : normals) out.push_back(irradianceCoeffs.evaluate(n));
  return out;
}

}  // namespace marionette::cli::detail
