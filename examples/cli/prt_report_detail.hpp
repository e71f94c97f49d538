// Private to `marionette prt report`: what its files share. The plan of the measurements, the
// timing and light-probe helpers, and each experiment's results and the function that measures them.
#pragma once
#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "commands.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/sh_lighting.hpp"

namespace marionette::cli::detail {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
inline constexpr double kPi = std::numbers::pi;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

template <class F>
double bestSeconds(int repeats, F&& f) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    f();
    best = std::min(best, secondsSince(start));
  }
  return best;
}

using ReportOptions = PrtReportOptions;

struct MapSpec {
  std::string name, path;
};

// What each measurement runs on; the full report and --quick differ only here.
struct Plan {
  std::vector<MapSpec> lightingMaps;
  int lightingNormals = 1000, projectionRepeats = 3;
  int samplingNormals = 64;
  std::vector<int> samplingRays{100, 324, 1024, 3136, 10000, 31329, 99856};
  int subsetVertices = 400, downWidth = 256, downHeight = 128;
  std::vector<int> transferRays{64, 256, 1024, 4096};
  int relightRepeats = 300;
  int rotationMapWidth = 1024;  // the map the ShRotation check resamples (downsampled when smaller)
};

// Each measurement below returns false with an error in `diagnostics` naming the file (a light
// probe or character it cannot load, a CSV it cannot write) and the problem.

// Light probes and SH irradiance for the experiments (prt_report_maps.cpp).
std::optional<prt::EnvironmentMap> loadMap(const std::string& path, Diagnostics& diagnostics);
std::optional<prt::EnvironmentMap> boxDownsample(const prt::EnvironmentMap& map, int width, int height);
std::vector<glm::dvec3> evaluateAll(const prt::ShCoefficients& irradianceCoeffs,
                                    const std::vector<glm::dvec3>& normals);

// ---------------------------------------------------------------------------------------------
// 1. Lighting truncation (prt_report_lighting.cpp)
struct LightingResult {
  std::string map;
  std::array<prt::IrradianceError, prt::kMaxShBands + 1> error{};
  std::array<double, prt::kMaxShBands + 1> projectionMs{};
  double bruteForceMs = 0.0;
  int width = 0, height = 0;
  struct Window {
    prt::IrradianceError error;
    double cutoff = 0.0, minOverMean = 0.0, ms = 0.0;
  };
  std::array<std::array<Window, 4>, 2> windows{};  // at kWindowBands[0], kWindowBands[1]
};

inline constexpr std::array<prt::ShWindow, 4> kWindows{prt::ShWindow::None, prt::ShWindow::Hann, prt::ShWindow::Lanczos,
                                                       prt::ShWindow::Sinc4};
// Windows at n = 3 (where the truncated kernel's ringing shows most) and at n = 8.
inline constexpr std::array<int, 2> kWindowBands{3, 8};

bool measureLighting(const Plan& plan, const ReportOptions& o, const fs::path& data,
                     std::vector<LightingResult>& results, Diagnostics& diagnostics);

// ---------------------------------------------------------------------------------------------
// 2. Transfer sampling error against the exact cone transfer (prt_report_sampling.cpp)
inline constexpr int kSamplingBands = 4;
struct SamplingCase {
  double halfAngleDeg = 90.0;
  std::vector<double> mean, max, usPerNormal;
  double slope = 0.0, intercept = 0.0;
};

bool measureSampling(const Plan& plan, const fs::path& data, std::vector<SamplingCase>& cases,
                     Diagnostics& diagnostics);

// ---------------------------------------------------------------------------------------------
// 3. End to end on RobotExpressive, shadowed (prt_report_end_to_end.cpp)
struct ChannelError {
  glm::dvec3 mean{0.0}, p95{0.0};
  [[nodiscard]] double worstMean() const { return std::max({mean.x, mean.y, mean.z}); }
  [[nodiscard]] double worstP95() const { return std::max({p95.x, p95.y, p95.z}); }
};

struct EndToEndRow {
  std::string map;
  int n = 0, rays = 0;
  double precomputeSeconds = 0.0, relightUs = 0.0;
  ChannelError error;
};

struct EndToEndResult {
  std::size_t vertices = 0, candidates = 0, buried = 0;
  std::size_t meshBuried = 0;  // vertices of the whole mesh with >= 99 % of the precompute's rays blocked (largest N)
  int downWidth = 0, downHeight = 0;
  double referenceSeconds = 0.0;
  std::vector<std::string> maps;
  std::vector<glm::dvec3> meanReference;  // per map
  std::vector<EndToEndRow> rows;
  std::vector<EndToEndRow> unshadowed;  // rays = 0: the closed-form unshadowed transfer, per map and n
};

bool measureEndToEnd(const Plan& plan, const ReportOptions& o, const fs::path& data, EndToEndResult& result,
                     Diagnostics& diagnostics);

// ---------------------------------------------------------------------------------------------
// 4. Stiff and extreme cases (prt_report_extremes.cpp)
struct Check {
  std::string name, value, tolerance;
  bool pass = false;
};

bool measureExtremes(const Plan& plan, const ReportOptions& o, const fs::path& data, std::vector<Check>& checks,
                     Diagnostics& diagnostics);

}  // namespace marionette::cli::detail
