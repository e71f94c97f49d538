// Environment lighting with 9 SH coefficients against brute force (docs/accuracy.md,
// "Environment lighting (9 SH coefficients)"). For each map: the time to project it, the time
// to evaluate the irradiance at one normal, and the mean / max relative irradiance error over
// 1000 Fibonacci-sphere normals (per normal: the worst of R, G, B of |E_SH - E_ref| / E_ref),
// as a Markdown table on stdout.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../prt/prt_test_util.hpp"
#include "marionette/prt/environment_map.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "test_data.hpp"

using namespace marionette::prt;
using Clock = std::chrono::steady_clock;

namespace {
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
}  // namespace

int main() {
  std::vector<std::pair<std::string, std::string>> maps = {
      {"blender_studiolight_forest.exr", marionette::test::sharedAsset("envmaps/blender_studiolight_forest.exr")},
      {"quarry_01_1k.hdr", marionette::test::sharedAsset("envmaps/quarry_01_1k.hdr")},
      {"royal_esplanade_1k.hdr", marionette::test::sharedAsset("envmaps/royal_esplanade_1k.hdr")}};
  for (const char* n : {"city", "courtyard", "forest", "interior", "night", "studio", "sunrise", "sunset"})
    maps.emplace_back(std::string("studiolights/world/") + n + ".exr", marionette::test::blenderStudiolight(std::string(n) + ".exr"));

  const auto normals = marionette::prt::test::fibonacciSphere(1000);
  std::printf("| map | projection (ms) | evaluation (ns / normal) | brute force (ms / 1000 normals) | mean rel. error | max rel. error | max error / mean E |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  int failures = 0;
  for (const auto& [name, path] : maps) {
    auto load = loadEnvironmentMap(path);
    if (!load.map) {
      std::fprintf(stderr, "%s\n", load.diagnostics.format().c_str());
      ++failures;
      continue;
    }
    const EnvironmentMap& map = *load.map;
    // Projection: best of 5.
    double project = 1e30;
    ShCoefficients sh;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = Clock::now();
      sh = projectRadiance(map);
      project = std::min(project, seconds(t0, Clock::now()));
    }
    // Evaluation: the shader's work, from the irradiance coefficients; best of 5 x 100 passes.
    const ShCoefficients c = irradianceCoefficients(sh);
    std::vector<glm::dvec3> approx(normals.size());
    double evaluate = 1e30;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = Clock::now();
      for (int pass = 0; pass < 100; ++pass)
        for (std::size_t i = 0; i < normals.size(); ++i) approx[i] = c.evaluate(normals[i]);
      evaluate = std::min(evaluate, seconds(t0, Clock::now()) / (100.0 * static_cast<double>(normals.size())));
    }
    const auto t0 = Clock::now();
    const auto reference = bruteForceIrradiance(map, normals, 1);
    const double brute = seconds(t0, Clock::now());
    const auto stats = marionette::prt::test::errorStats(approx, reference);
    // The error against the map's mean irradiance (the scale R&H report): small where the
    // relative error is large only because the irradiance there is small.
    glm::dvec3 meanE(0.0);
    for (const auto& e : reference) meanE += e / static_cast<double>(reference.size());
    double maxAbs = 0.0;
    for (std::size_t i = 0; i < reference.size(); ++i)
      for (int k = 0; k < 3; ++k) maxAbs = std::max(maxAbs, std::abs(approx[i][k] - reference[i][k]) / meanE[k]);
    std::printf("| %s | %.1f | %.1f | %.0f | %.3f | %.3f | %.3f |\n", name.c_str(), project * 1e3, evaluate * 1e9,
                brute * 1e3, stats.mean, stats.max, maxAbs);
  }
  return failures == 0 ? 0 : 1;
}
