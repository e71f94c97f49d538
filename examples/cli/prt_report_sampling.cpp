// PRT report, 2. transfer sampling: the stratified cosine-weighted estimator against the exact
// transfer of a vertex that sees a cone (coneTransfer), error against the ray count N.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "marionette/prt/sphere_sampling.hpp"
#include "marionette/prt/transfer.hpp"
#include "prt_report_detail.hpp"
#include "report_tables.hpp"

namespace marionette::cli::detail {

namespace {

// Least-squares line through (log x, log y): slope and intercept.
std::pair<double, double> logLogFit(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {slope, (sy - slope * sx) / n};
}

}  // namespace

bool measureSampling(const Plan& plan, const fs::path& data, std::vector<SamplingCase>& cases,
                     Diagnostics& diagnostics) {
  std::fprintf(stderr, "prt report: 2/4 transfer sampling\n");
  const std::vector<glm::dvec3> normals = prt::fibonacciSphere(plan.samplingNormals);
  const int count = prt::shCount(kSamplingBands);
  for (double deg : {90.0, 85.0, 60.0, 30.0}) {
    SamplingCase c;
    c.halfAngleDeg = deg;
    const double half = deg * kPi / 180.0;
    for (int rays : plan.samplingRays) {
      double sum = 0.0, worst = 0.0, seconds = 0.0;
      for (std::size_t j = 0; j < normals.size(); ++j) {
        const glm::vec3 n(normals[j]);
        std::array<double, prt::kMaxShCoefficients> exact{}, sampled{};
        prt::coneTransfer(normals[j], kSamplingBands, half, exact);
        const float cosHalf = static_cast<float>(std::cos(half));
        const std::function<float(const glm::vec3&)> visible =
            deg >= 90.0 ? std::function<float(const glm::vec3&)>([](const glm::vec3&) { return 1.0f; })
                        : std::function<float(const glm::vec3&)>([n, cosHalf](const glm::vec3& d) {
                            return glm::dot(d, n) >= cosHalf ? 1.0f : 0.0f;
                          });
        const auto start = Clock::now();
        prt::sampleTransfer(n, kSamplingBands, rays, 1000 + j, visible, sampled);
        seconds += secondsSince(start);
        double diff = 0.0, norm = 0.0;
        for (int i = 0; i < count; ++i) {
          const auto k = static_cast<std::size_t>(i);
          diff += (sampled[k] - exact[k]) * (sampled[k] - exact[k]);
          norm += exact[k] * exact[k];
        }
        const double e = std::sqrt(diff / norm);
        sum += e, worst = std::max(worst, e);
      }
      c.mean.push_back(sum / static_cast<double>(normals.size()));
      c.max.push_back(worst);
      c.usPerNormal.push_back(1e6 * seconds / static_cast<double>(normals.size()));
    }
    std::vector<double> x(plan.samplingRays.begin(), plan.samplingRays.end());
    std::tie(c.slope, c.intercept) = logLogFit(x, c.mean);
    cases.push_back(c);
  }
  Csv csv(data / "transfer_sampling.csv", "half_angle_deg,N,mean_rel_l2_error,max_rel_l2_error,fit,slope,us_per_normal");
  for (const SamplingCase& c : cases)
    for (std::size_t k = 0; k < plan.samplingRays.size(); ++k) {
      const double fit = std::exp(c.intercept) * std::pow(static_cast<double>(plan.samplingRays[k]), c.slope);
      csv.row({str("%g", c.halfAngleDeg), std::to_string(plan.samplingRays[k]), str("%.6g", c.mean[k]),
               str("%.6g", c.max[k]), str("%.6g", fit), str("%.4f", c.slope), str("%.2f", c.usPerNormal[k])});
    }
  if (!csv.ok()) return diagnostics.error((data / "transfer_sampling.csv").string(), "cannot be written"), false;
  return true;
}

}  // namespace marionette::cli::detail
