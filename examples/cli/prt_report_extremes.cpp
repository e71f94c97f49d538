// PRT report, 4. stiff and extreme cases: each a value measured against a stated tolerance,
// pass or fail.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sh_rotation.hpp"
#include "marionette/prt/sphere_sampling.hpp"
#include "prt_report_detail.hpp"
#include "report_tables.hpp"

namespace marionette::cli::detail {

namespace {

double maxCoefficientDifference(const prt::ShCoefficients& a, const prt::ShCoefficients& b, int bands) {
  double e = 0.0;
  for (int i = 0; i < prt::shCount(bands); ++i)
    for (int c = 0; c < 3; ++c)
      e = std::max(e, std::abs(a.c[static_cast<std::size_t>(i)][c] - b.c[static_cast<std::size_t>(i)][c]));
  return e;
}
double dcScale(const prt::ShCoefficients& a) { return std::max({std::abs(a.c[0].x), std::abs(a.c[0].y), std::abs(a.c[0].z)}); }

}  // namespace

bool measureExtremes(const Plan& plan, const ReportOptions& o, const fs::path& data, std::vector<Check>& checks,
                     Diagnostics& diagnostics) {
  std::fprintf(stderr, "prt report: 4/4 stiff and extreme cases\n");
  auto add = [&](std::string name, double value, double tolerance, bool pass, const char* format = "%.3g") {
    checks.push_back({std::move(name), str(format, value), str("%.3g", tolerance), pass});
  };
  {  // Legendre against the standard library (Condon-Shortley phase removed).
    double worst = 0.0;
    bool finite = true;
    for (int l = 0; l <= 40; ++l)
      for (int m = 0; m <= l; ++m)
        for (int k = 0; k <= 180; ++k) {
          const double theta = kPi * k / 180.0;
          const double ref = (m % 2 ? -1.0 : 1.0) *
                             std::sph_legendre(static_cast<unsigned>(l), static_cast<unsigned>(m), theta);
          const double ours = prt::normalizedLegendre(l, m, std::cos(theta));
          finite = finite && std::isfinite(ours);
          worst = std::max(worst, std::abs(ours - ref));
        }
    add("max |normalizedLegendre - (-1)^m std::sph_legendre|, l <= 40, all m, 181 angles", worst, 1e-12,
        finite && worst <= 1e-12);
  }
  {  // The basis at the poles: every m != 0 exactly zero.
    double worst = 0.0;
    for (const glm::dvec3 pole : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0)}) {
      prt::ShBasis y{};
      prt::shBasis(prt::kMaxShBands, pole, y);
      std::array<float, prt::kMaxShCoefficients> yf{};
      prt::shBasis(prt::kMaxShBands, glm::vec3(pole), yf);
      for (int l = 0; l < prt::kMaxShBands; ++l)
        for (int m = -l; m <= l; ++m)
          if (m != 0)
            worst = std::max({worst, std::abs(y[static_cast<std::size_t>(prt::shIndex(l, m))]),
                              static_cast<double>(std::abs(yf[static_cast<std::size_t>(prt::shIndex(l, m))]))});
    }
    add("basis at the poles +-Y, n = 8, double and float: max |Y_lm|, m != 0", worst, 0.0, worst == 0.0);
  }
  {  // A constant map projects to the DC term alone.
    const prt::EnvironmentMap constant(1024, 512, std::vector<float>(1024 * 512 * 3, 1.0f));
    double worst = 0.0;
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      const prt::ShCoefficients c = prt::projectRadiance(constant, n);
      prt::ShCoefficients dcOnly;
      dcOnly.c[0] = c.c[0];
      worst = std::max(worst, maxCoefficientDifference(c, dcOnly, n) / dcScale(c));
    }
    add("constant map 1024x512, n = 2..8: max |non-DC coefficient| / DC", worst, 1e-12, worst <= 1e-12);
  }
  {  // A one-pixel sun of 3e4 on black: finite, and its coefficients those of a delta light.
    const int w = 1024, h = 512, col = 700, row = 150;
    std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3, 0.0f);
    for (int c = 0; c < 3; ++c) rgb[(static_cast<std::size_t>(row) * w + col) * 3 + static_cast<std::size_t>(c)] = 3e4f;
    const prt::EnvironmentMap sun(w, h, std::move(rgb));
    const double power = 3e4 * sun.texelSolidAngle(row);
    const glm::dvec3 dir = sun.texelDirection(col, row);
    double worstDeviation = 0.0, lowestRatio = 1.0, highestRatio = 1.0;
    bool finite = true;
    const std::vector<glm::dvec3> normals = prt::fibonacciSphere(200);
    const std::vector<glm::dvec3> reference = prt::bruteForceIrradiance(sun, normals, o.threads);
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      const prt::ShCoefficients c = prt::projectRadiance(sun, n);
      prt::ShBasis y{};
      prt::shBasis(n, dir, y);
      double num = 0.0, den = 0.0;
      for (int i = 0; i < prt::shCount(n); ++i) {
        const double delta = power * y[static_cast<std::size_t>(i)];
        const double got = c.c[static_cast<std::size_t>(i)].x;
        finite = finite && std::isfinite(got);
        worstDeviation = std::max(worstDeviation, std::abs(got - delta) / (power * y[0]));
        num += got * got, den += delta * delta;
      }
      const double ratio = std::sqrt(num / den);
      lowestRatio = std::min(lowestRatio, ratio), highestRatio = std::max(highestRatio, ratio);
      const prt::IrradianceError e =
          prt::irradianceError(evaluateAll(prt::irradianceCoefficients(c), normals), reference);
      finite = finite && std::isfinite(e.mean) && std::isfinite(e.max);
    }
    add("one-pixel sun 3e4 (1024x512): max |L_i - P Y_i(sun)| / (P Y_0), n = 2..8 (all finite)", worstDeviation, 1e-2,
        finite && worstDeviation <= 1e-2);
    checks.push_back({"one-pixel sun: ||L|| / ||delta light||, lowest and highest over n = 2..8",
                      str("%.5f .. %.5f", lowestRatio, highestRatio), "1 +- 0.01",
                      finite && lowestRatio >= 0.99 && highestRatio <= 1.01});
  }
  {  // A black map: zero coefficients, a finite error.
    const prt::EnvironmentMap black(256, 128, std::vector<float>(256 * 128 * 3, 0.0f));
    double worst = 0.0;
    bool finite = true;
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      const prt::ShCoefficients c = prt::projectRadiance(black, n);
      worst = std::max(worst, maxCoefficientDifference(c, prt::ShCoefficients{}, n));
      const prt::IrradianceError e = prt::lightingError(black, n, prt::ShWindow::None, 100);
      finite = finite && std::isfinite(e.mean) && std::isfinite(e.max);
      for (prt::ShWindow window : kWindows) {
        const prt::ShCoefficients wc = prt::windowRadiance(c, window);
        worst = std::max(worst, maxCoefficientDifference(wc, prt::ShCoefficients{}, n));
      }
    }
    add("black map, n = 2..8, every window: max |coefficient| (error finite)", worst, 0.0, finite && worst == 0.0);
  }
  {  // The clamped-cosine kernel has no odd band past 1.
    double worst = 0.0;
    for (int l = 3; l <= 39; l += 2) worst = std::max(worst, std::abs(prt::cosineLobeBand(l)));
    add("cosineLobeBand(l), odd l = 3..39: max |A_l|", worst, 0.0, worst == 0.0);
  }
  {  // Rotations.
    const std::string path = o.assets + "/envmaps/blender_studiolight_forest.exr";
    const std::optional<prt::EnvironmentMap> full = loadMap(path, diagnostics);
    if (!full) return false;
    std::optional<prt::EnvironmentMap> map =
        boxDownsample(*full, std::min(full->width(), plan.rotationMapWidth), std::min(full->height(), plan.rotationMapWidth / 2));
    if (!map) return diagnostics.error(path, "cannot downsample for the rotation check"), false;
    const int w = map->width(), h = map->height();
    const prt::ShRotation rotation(prt::kMaxShBands);
    const prt::ShCoefficients original = prt::projectRadiance(*map, prt::kMaxShBands);
    // Any rotation: the map resampled (2x2 bilinear samples per pixel) and re-projected.
    const glm::dmat3 r = glm::dmat3(glm::rotate(glm::dmat4(1.0), 1.1, glm::normalize(glm::dvec3(1, 2, 3))));
    std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        glm::dvec3 sum(0.0);
        for (int sy = 0; sy < 2; ++sy)
          for (int sx = 0; sx < 2; ++sx) {
            const glm::dvec3 d =
                prt::EnvironmentMap::direction((x + 0.25 + 0.5 * sx) / w, (y + 0.25 + 0.5 * sy) / h);
            sum += glm::dvec3(map->sample(glm::transpose(r) * d));
          }
        float* p = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
        p[0] = static_cast<float>(sum.x / 4), p[1] = static_cast<float>(sum.y / 4), p[2] = static_cast<float>(sum.z / 4);
      }
    const prt::ShCoefficients reprojected = prt::projectRadiance(prt::EnvironmentMap(w, h, std::move(rgb)), prt::kMaxShBands);
    const double general = maxCoefficientDifference(rotation.rotate(r, original), reprojected, prt::kMaxShBands) /
                           dcScale(original);
    add(str("ShRotation (1.1 rad about (1,2,3)) vs the re-projected resampled forest map %dx%d, n = 8: max diff / DC", w, h),
        general, 1e-2, general <= 1e-2);
    // About +Y by a whole number of columns: the shifted map is exact, so is the comparison.
    const int shift = w / 8 + 3;
    const double angle = 2.0 * kPi * shift / w;
    std::vector<float> shifted(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c)
          shifted[(static_cast<std::size_t>(y) * w + x) * 3 + static_cast<std::size_t>(c)] =
              map->pixels()[(static_cast<std::size_t>(y) * w + static_cast<std::size_t>((x + shift) % w)) * 3 +
                            static_cast<std::size_t>(c)];
    const prt::ShCoefficients shiftedProjection = prt::projectRadiance(prt::EnvironmentMap(w, h, std::move(shifted)),
                                                                       prt::kMaxShBands);
    const double aboutY = maxCoefficientDifference(prt::rotateAboutY(original, angle), shiftedProjection,
                                                   prt::kMaxShBands) / dcScale(original);
    add(str("rotateAboutY (%d columns) vs the re-projected column-shifted map, n = 8: max diff / DC", shift), aboutY,
        1e-9, aboutY <= 1e-9);
    glm::dmat3 ry(1.0);
    ry[0] = glm::dvec3(std::cos(angle), 0.0, -std::sin(angle));  // image of +X
    ry[2] = glm::dvec3(std::sin(angle), 0.0, std::cos(angle));   // image of +Z: turned toward +X
    const double agree = maxCoefficientDifference(prt::rotateAboutY(original, angle), rotation.rotate(ry, original),
                                                  prt::kMaxShBands) / dcScale(original);
    add("rotateAboutY vs ShRotation of the same turn about +Y, n = 8: max diff / DC", agree, 1e-12, agree <= 1e-12);
  }
  Csv csv(data / "extremes.csv", "check,value,tolerance,pass");
  for (const Check& c : checks) csv.row({"\"" + c.name + "\"", c.value, c.tolerance, c.pass ? "pass" : "FAIL"});
  if (!csv.ok()) return diagnostics.error((data / "extremes.csv").string(), "cannot be written"), false;
  return true;
}

}  // namespace marionette::cli::detail
