// The light estimated from camera frames against the probe's truth (docs/accuracy.md, "Light
// estimated from the camera"). For each probe and each hand-held path (tests/support/
// camera_sweep.hpp: 640 x 480, 60-degree horizontal field of view, auto exposure, sRGB 8 bits
// with clipping), the frames go through marionette::ar::CameraLightEstimator with their
// relative exposures; the estimate, with the first frame's exposure undone, is compared with
// the probe's own 9 SH coefficients (prt::projectRadiance) over 1000 Fibonacci normals:
//   - error / mean E: per normal, the largest over R, G, B of |E_est - E_probe| / (the probe's
//     mean E in that channel); the mean over the normals and the worst normal;
//   - pointwise: the same over E_probe at that normal (prt::irradianceError);
//   - shape: the mean error / mean E once the estimate is scaled to the probe's mean luminance
//     (what is left when the scale, lost with the clipped highlights, is set right);
//   - direction: the angle between the band-1 luminance vectors (the main light direction);
//   - uniform: the error / mean E of the best uniform light (the probe's DC term alone), a
//     baseline that knows the mean exactly and nothing of the direction;
//   - seen: the share of the sphere's solid angle the camera saw; clipped: of that, the share
//     whose cells hold clipped pixels; cost: the median addFrame time.
// Then, per probe, the share of its power above 5.3 times its median radiance: what a camera
// exposed for the median (mid grey at 0.18, clipping at 0.956) cannot measure.
//
// Usage: marionette_camera_light_error [--fps F] [--metering median|mean|locked] [--compressed]
//                                      [--clipped-factor K] [--bracket STOPS] [--summary]
//   defaults: 30 fps, median metering, the estimator's default factor; --compressed squeezes each
//   probe into the camera's range (L / (1 + L)) and locks the exposure at 1 unless --metering is
//   given; --bracket brackets the exposure (camera_sweep.hpp's runSweep: every second and third
//   frame of three STOPS and 2 STOPS darker than metered); --summary prints the closing line alone.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "camera_sweep.hpp"
#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sphere_sampling.hpp"
#include "marionette_ar/camera_light_estimate.hpp"
#include "test_data.hpp"

using namespace marionette;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// A pointwise error: where the probe's own 9-coefficient irradiance reaches 0 (a negative lobe
// opposite a sun) it is unbounded, so past 1000 % it reads "> 1000 %".
std::string percent(double fraction, const char* format) {
  char text[32];
  if (fraction > 10.0) return "> 1000 %";
  std::snprintf(text, sizeof text, format, 100.0 * fraction);
  return text;
}

// The share of the map's power (luminance x solid angle) above `times` its solid-angle median.
double powerAbove(const prt::EnvironmentMap& map, double times) {
  std::vector<std::pair<double, double>> lw;  // luminance, solid angle
  double total = 0.0, power = 0.0;
  for (int r = 0; r < map.height(); ++r)
    for (int c = 0; c < map.width(); ++c) {
      const glm::vec3 t = map.texel(c, r);
      const double l = 0.2126 * t.r + 0.7152 * t.g + 0.0722 * t.b, w = map.texelSolidAngle(r);
      lw.emplace_back(l, w);
      total += w;
      power += l * w;
    }
  std::sort(lw.begin(), lw.end());
  double seen = 0.0, middle = 0.0;
  for (const auto& [l, w] : lw) {
    if (seen < 0.5 * total) middle = l;
    seen += w;
  }
  double above = 0.0;
  for (const auto& [l, w] : lw)
    if (l > times * middle) above += l * w;
  return power > 0.0 ? above / power : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  double fps = 30.0;
  test::Metering metering = test::Metering::Median;
  bool meteringGiven = false, compressed = false, summaryOnly = false;
  int bracketStops = 0;
  ar::CameraLightSettings settings;
  for (int i = 1; i < argc; ++i) {
    const bool hasValue = i + 1 < argc;
    if (!std::strcmp(argv[i], "--fps") && hasValue) {
      fps = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--metering") && hasValue) {
      const std::string m = argv[++i];
      metering = m == "mean" ? test::Metering::Mean : m == "locked" ? test::Metering::Locked : test::Metering::Median;
      meteringGiven = true;
    } else if (!std::strcmp(argv[i], "--clipped-factor") && hasValue) {
      settings.clippedFactor = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--bracket") && hasValue) {
      bracketStops = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--compressed")) {
      compressed = true;
    } else if (!std::strcmp(argv[i], "--summary")) {
      summaryOnly = true;
    } else {
      std::fprintf(stderr, "usage: %s [--fps F] [--metering median|mean|locked] [--compressed] [--clipped-factor K] [--bracket STOPS] [--summary]\n",
                   argv[0]);
      return 2;
    }
  }
  if (!(fps > 0.0 && fps <= 240.0)) {
    std::fprintf(stderr, "--fps must be in (0, 240]\n");
    return 2;
  }
  if (compressed && !meteringGiven) metering = test::Metering::Locked;
  if (bracketStops < 0 || bracketStops > 10) {
    std::fprintf(stderr, "--bracket must be 0..10 stops\n");
    return 2;
  }

  std::vector<std::pair<std::string, std::string>> probes;
  for (const char* n : {"city", "courtyard", "forest", "interior", "night", "studio", "sunrise", "sunset"})
    probes.emplace_back(std::string("studiolights/") + n, test::blenderStudiolight(std::string(n) + ".exr"));
  probes.emplace_back("quarry_01_1k", test::sharedAsset("envmaps/quarry_01_1k.hdr"));
  probes.emplace_back("royal_esplanade_1k", test::sharedAsset("envmaps/royal_esplanade_1k.hdr"));

  const std::vector<glm::dvec3> normals = prt::fibonacciSphere(1000);
  if (!summaryOnly) {
    std::printf("| probe | path | frames | seen | clipped | error / mean E: mean | max | pointwise: mean | max | shape: mean "
                "| direction (deg) | uniform light: mean | cost (ms / frame, median) |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  }
  int failures = 0, goalRuns = 0, goalMet = 0;
  std::vector<std::string> goalProbes;
  std::vector<double> goalErrors, allCosts;
  std::vector<std::pair<std::string, double>> reach;
  for (const auto& [name, path] : probes) {
    const prt::EnvironmentMapLoad load = prt::loadEnvironmentMap(path);
    if (!load.map) {
      std::fprintf(stderr, "%s\n", load.diagnostics.format().c_str());
      ++failures;
      continue;
    }
    const prt::EnvironmentMap map = compressed ? test::compressIntoCameraRange(*load.map) : *load.map;
    reach.emplace_back(name, powerAbove(map, 0.956 / 0.18));
    const prt::ShCoefficients truth = prt::projectRadiance(map);
    prt::ShCoefficients uniform;
    uniform.c[0] = truth.c[0];
    const test::LightError baseline = test::compareIrradiance(uniform, truth, normals);
    const test::ProbeCamera camera(map, metering);
    for (const test::SweepPath& sweep : test::kSweepPaths) {
      ar::CameraLightEstimator estimator(settings);
      const test::SweepRun run = test::runSweep(camera, sweep, fps, estimator, bracketStops);
      const test::LightError e = test::compareIrradiance(run.probeUnits, truth, normals);
      allCosts.insert(allCosts.end(), run.frameMilliseconds.begin(), run.frameMilliseconds.end());
      if (!summaryOnly)
        std::printf("| %s | %s | %d | %.0f %% | %.1f %% | %.1f %% | %.0f %% | %s | %s | %.1f %% | %.1f | %.1f %% | %.3f |\n",
                    name.c_str(), sweep.name, run.frames, 100.0 * run.estimate.seenFraction,
                    100.0 * run.estimate.clippedFraction, 100.0 * e.meanOfMeanE, 100.0 * e.maxOfMeanE,
                    percent(e.meanPointwise, "%.1f %%").c_str(), percent(e.maxPointwise, "%.0f %%").c_str(),
                    100.0 * e.meanShape, e.directionDegrees, 100.0 * baseline.meanOfMeanE, median(run.frameMilliseconds));
      if (run.estimate.seenFraction >= 1.0 / 3.0) {
        ++goalRuns;
        goalErrors.push_back(e.meanOfMeanE);
        if (e.meanOfMeanE <= 0.15 && e.directionDegrees <= 20.0) {
          ++goalMet;
          if (std::find(goalProbes.begin(), goalProbes.end(), name) == goalProbes.end()) goalProbes.push_back(name);
        }
      }
    }
  }
  if (!summaryOnly && !compressed) {
    std::printf("\n| probe | power above 5.3 x the median radiance |\n|---|---|\n");
    for (const auto& [name, share] : reach) std::printf("| %s | %.0f %% |\n", name.c_str(), 100.0 * share);
    std::printf("\n");
  }
  std::printf("%s metering%s%s, clipped factor %g, %g fps: %d of %d runs that saw a third of the sphere are within 15 %% "
              "(mean error / mean E) and 20 degrees, on %zu probes; their median error %.1f %%; median cost %.3f ms / frame.\n",
              test::meteringName(metering), compressed ? ", probes compressed into the camera's range" : "",
              bracketStops ? (", bracketed by " + std::to_string(bracketStops) + " and " + std::to_string(2 * bracketStops) + " stops").c_str() : "",
              settings.clippedFactor, fps, goalMet, goalRuns, goalProbes.size(), 100.0 * median(goalErrors),
              median(allCosts));
  return failures == 0 ? 0 : 1;
}
