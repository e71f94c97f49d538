// CameraLightAccuracy: the camera light estimate over hand-held sweeps of real light probes,
// against each probe's own 9 SH coefficients (tests/support/camera_sweep.hpp; the table,
// its metric and its command: docs/accuracy.md, "Light estimated from the camera"). 10 fps, as
// the table. The goal (issue 44): a mean irradiance error of at most 15 % of the mean
// irradiance and a main direction within 20 degrees once a third of the sphere is seen.
//   - Probes squeezed into the camera's range (nothing clipped): the goal holds on a full turn,
//     on five probes; asserted with regression bounds at the published figures.
//   - The real probes, auto-exposed at the frame's median: most of their power lies in
//     highlights an 8-bit camera clips, so the goal is met on one run of the table (sunset's
//     full turn) and asserted there; every other run is held to its published figure.
#include <gtest/gtest.h>

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

constexpr double kFps = 10.0;
constexpr double kGoalMean = 0.15, kGoalDegrees = 20.0;

// Regression bounds (docs/testing.md): 1.25 times the published error plus half a percent, the
// published direction error times 1.5 plus 2 degrees.
double errorBound(double published) { return 1.25 * published + 0.005; }
double directionBound(double published) { return 1.5 * published + 2.0; }

struct Published {
  const char* probe;  // under Blender's studio lights
  double halfMean, halfDegrees, fullMean, fullDegrees;  // error / mean E (fraction), degrees
};

test::LightError sweep(const prt::EnvironmentMap& map, test::Metering metering, const test::SweepPath& path,
                       double& seen) {
  const prt::ShCoefficients truth = prt::projectRadiance(map);
  const test::ProbeCamera camera(map, metering);
  ar::CameraLightEstimator estimator;
  const test::SweepRun run = test::runSweep(camera, path, kFps, estimator);
  seen = run.estimate.seenFraction;
  return test::compareIrradiance(run.probeUnits, truth, prt::fibonacciSphere(1000));
}

prt::EnvironmentMap load(const std::string& name) {
  const std::string path = test::blenderStudiolight(name + ".exr");
  prt::EnvironmentMapLoad loaded = prt::loadEnvironmentMap(path);
  EXPECT_TRUE(loaded.map) << loaded.diagnostics.format();
  return loaded.map ? std::move(*loaded.map) : prt::EnvironmentMap();
}

}  // namespace

TEST(CameraLightAccuracy, ProbesWithinTheCameraRangeMeetTheGoalOnAFullTurn) {
  // docs/accuracy.md, the second table (--compressed): full turns.
  const Published published[] = {
      {"city", 0, 0, 0.049, 6.5}, {"forest", 0, 0, 0.057, 4.9}, {"interior", 0, 0, 0.028, 3.3},
      {"night", 0, 0, 0.022, 2.2}, {"sunset", 0, 0, 0.032, 1.1}};
  for (const Published& p : published) {
    MARIONETTE_REQUIRE_FILE(test::blenderStudiolight(std::string(p.probe) + ".exr"));
    double seen = 0.0;
    const test::LightError e =
        sweep(test::compressIntoCameraRange(load(p.probe)), test::Metering::Locked, test::kSweepPaths[2], seen);
    EXPECT_GE(seen, 1.0 / 3.0) << p.probe;
    EXPECT_LE(e.meanOfMeanE, kGoalMean) << p.probe << ": the goal";
    EXPECT_LE(e.directionDegrees, kGoalDegrees) << p.probe << ": the goal";
    EXPECT_LE(e.meanOfMeanE, errorBound(p.fullMean)) << p.probe << ": published " << p.fullMean;
    EXPECT_LE(e.directionDegrees, directionBound(p.fullDegrees)) << p.probe << ": published " << p.fullDegrees;
  }
}

TEST(CameraLightAccuracy, RealProbesStayWithinTheirPublishedErrors) {
  // docs/accuracy.md, the first table: half and full turns, median metering.
  const Published published[] = {
      {"city", 0.300, 21.3, 0.280, 13.7}, {"forest", 0.352, 23.1, 0.242, 16.2}, {"interior", 0.483, 47.5, 0.490, 48.4},
      {"night", 0.620, 43.7, 0.555, 34.1}, {"sunset", 0.299, 26.4, 0.081, 3.3}};
  for (const Published& p : published) {
    MARIONETTE_REQUIRE_FILE(test::blenderStudiolight(std::string(p.probe) + ".exr"));
    const prt::EnvironmentMap map = load(p.probe);
    for (int path = 1; path <= 2; ++path) {
      const test::SweepPath& s = test::kSweepPaths[path];
      const double mean = path == 1 ? p.halfMean : p.fullMean, degrees = path == 1 ? p.halfDegrees : p.fullDegrees;
      double seen = 0.0;
      const test::LightError e = sweep(map, test::Metering::Median, s, seen);
      EXPECT_GE(seen, 1.0 / 3.0) << p.probe << ", " << s.name;
      EXPECT_LE(e.meanOfMeanE, errorBound(mean)) << p.probe << ", " << s.name << ": published " << mean;
      EXPECT_LE(e.directionDegrees, directionBound(degrees)) << p.probe << ", " << s.name << ": published " << degrees;
      if (mean <= kGoalMean && degrees <= kGoalDegrees) {  // where the table meets the goal, it holds
        EXPECT_LE(e.meanOfMeanE, kGoalMean) << p.probe << ", " << s.name;
        EXPECT_LE(e.directionDegrees, kGoalDegrees) << p.probe << ", " << s.name;
      }
    }
  }
}
