// `marionette prt report`: regenerates the PRT accuracy report from scratch. Every approximation
// of the PRT pipeline is measured against an oracle on real data, with its run time:
//   1. lighting truncation: n-band SH irradiance of 11 light probes against brute force, and
//      the windows against ringing at n = 8;
//   2. transfer sampling: the stratified cosine-weighted estimator against the exact transfer
//      of a vertex that sees a cone (coneTransfer), error against the ray count N;
//   3. end to end on RobotExpressive, shadowed: sum_i L_i T_v,i against ray-traced irradiance;
//   4. stiff and extreme cases, pass/fail against stated tolerances.
// Output: CSVs in DIR/data/prt/, PNGs in DIR/img/ (gnuplot, scripts/plot_prt_*.gp) and the
// tables in DIR/prt-report.md. Nothing in the markdown depends on the date or the run, except
// the timing columns (and the total run time).
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "commands.hpp"
#include "marionette/core/finite.hpp"
#include "marionette/io/import.hpp"
#include "marionette/prt/mirror_ball.hpp"
#include "marionette/prt/ray_occlusion.hpp"
#include "marionette/prt/relight.hpp"
#include "marionette/prt/sh_lighting.hpp"
#include "marionette/prt/sh_rotation.hpp"
#include "marionette/prt/sphere_sampling.hpp"
#include "marionette/prt/transfer.hpp"
#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::cli {

namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

int reportFail(const std::string& message) {
  std::fprintf(stderr, "marionette prt report: error: %s\n", message.c_str());
  return 2;
}

__attribute__((format(printf, 1, 2))) std::string str(const char* format, ...) {
  va_list args, copy;
  va_start(args, format);
  va_copy(copy, args);
  const int size = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string out(static_cast<std::size_t>(std::max(size, 0)) + 1, '\0');
  std::vsnprintf(out.data(), out.size(), format, args);
  va_end(args);
  out.pop_back();
  return out;
}

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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

// A CSV file written row by row; numbers are formatted by the caller.
class Csv {
 public:
  Csv(const fs::path& path, const std::string& header) : out_(path) { out_ << header << '\n'; }
  void row(const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) out_ << (i ? "," : "") << cells[i];
    out_ << '\n';
  }
  [[nodiscard]] bool ok() const { return static_cast<bool>(out_); }

 private:
  std::ofstream out_;
};

struct Markdown {
  std::string text;
  void line(const std::string& s = "") { text += s + "\n"; }
  static std::string cell(const std::string& text) {  // a '|' inside a cell must be escaped
    std::string out;
    for (char ch : text) out += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return out;
  }
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
    std::string h = "|", sep = "|";
    for (const auto& c : header) h += " " + cell(c) + " |", sep += "---|";
    line(h);
    line(sep);
    for (const auto& r : rows) {
      std::string s = "|";
      for (const auto& c : r) s += " " + cell(c) + " |";
      line(s);
    }
    line();
  }
};

std::optional<prt::EnvironmentMap> loadMap(const std::string& path, std::string& error) {
  prt::EnvironmentMapLoad load = prt::loadLightProbe(path, prt::LightProbeKind::LatLong);
  if (!load.map) error = load.diagnostics.format();
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

std::string machine() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  int cores = 0;
  while (std::getline(in, line)) {
    if (line.rfind("processor", 0) == 0) ++cores;
    if (line.rfind("model name", 0) == 0 && model == "unknown CPU") {
      const auto colon = line.find(':');
      if (colon != std::string::npos) model = line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  }
  return model + ", " + std::to_string(cores) + " logical cores";
}

// ---------------------------------------------------------------------------------------------
// 1. Lighting truncation
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

constexpr std::array<prt::ShWindow, 4> kWindows{prt::ShWindow::None, prt::ShWindow::Hann, prt::ShWindow::Lanczos,
                                                prt::ShWindow::Sinc4};
// Windows at n = 3 (where the truncated kernel's ringing shows most) and at n = 8.
constexpr std::array<int, 2> kWindowBands{3, 8};

bool measureLighting(const Plan& plan, const ReportOptions& o, const fs::path& data, std::vector<LightingResult>& results,
                     std::string& error) {
  const std::vector<glm::dvec3> normals = prt::fibonacciSphere(plan.lightingNormals);
  Csv csv(data / "lighting_truncation.csv", "map,n,coefficients,mean_rel_error,max_rel_error,projection_ms");
  Csv win(data / "lighting_windows.csv", "map,n,window,cutoff,mean_rel_error,max_rel_error,min_E_over_mean_E,window_ms");
  for (const MapSpec& spec : plan.lightingMaps) {
    std::fprintf(stderr, "prt report: 1/4 lighting truncation: %s\n", spec.name.c_str());
    const std::optional<prt::EnvironmentMap> map = loadMap(spec.path, error);
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
  if (!csv.ok() || !win.ok()) return error = "cannot write " + (data / "lighting_*.csv").string(), false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// 2. Transfer sampling error against the exact cone transfer
constexpr int kSamplingBands = 4;
struct SamplingCase {
  double halfAngleDeg = 90.0;
  std::vector<double> mean, max, usPerNormal;
  double slope = 0.0, intercept = 0.0;
};

bool measureSampling(const Plan& plan, const fs::path& data, std::vector<SamplingCase>& cases, std::string& error) {
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
  if (!csv.ok()) return error = "cannot write " + (data / "transfer_sampling.csv").string(), false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// 3. End to end on RobotExpressive, shadowed
struct ChannelError {
  glm::dvec3 mean{0.0}, p95{0.0};
  [[nodiscard]] double worstMean() const { return std::max({mean.x, mean.y, mean.z}); }
  [[nodiscard]] double worstP95() const { return std::max({p95.x, p95.y, p95.z}); }
};

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
                     std::string& error) {
  std::fprintf(stderr, "prt report: 3/4 end to end: loading RobotExpressive\n");
  const std::string character = o.assets + "/characters/RobotExpressive.glb";
  ImportResult imported = importAsset(character);
  if (!imported.asset) return error = imported.diagnostics.format(), false;
  Diagnostics d;
  const prt::TransferMesh mesh = prt::bindPoseMesh(*imported.asset, d);
  std::unique_ptr<prt::OcclusionTracer> tracer = prt::makeEmbreeOcclusion(mesh, d);
  if (!d.ok() || !tracer || mesh.positions.empty()) return error = character + ": " + d.format(), false;
  const std::size_t vertexCount = mesh.positions.size();
  result.vertices = vertexCount;

  const std::vector<MapSpec> mapSpecs{{"blender_forest", o.assets + "/envmaps/blender_studiolight_forest.exr"},
                                      {"royal_esplanade", o.assets + "/envmaps/royal_esplanade_1k.hdr"}};
  std::vector<prt::EnvironmentMap> maps;
  for (const MapSpec& spec : mapSpecs) {
    const std::optional<prt::EnvironmentMap> full = loadMap(spec.path, error);
    if (!full) return false;
    std::optional<prt::EnvironmentMap> small = boxDownsample(*full, plan.downWidth, plan.downHeight);
    if (!small)
      return error = str("%s: %dx%d is not a multiple of %dx%d", spec.path.c_str(), full->width(), full->height(),
                         plan.downWidth, plan.downHeight),
             false;
    maps.push_back(std::move(*small));
    result.maps.push_back(spec.name);
  }
  result.downWidth = plan.downWidth, result.downHeight = plan.downHeight;

  // The reference: per vertex, every pixel of the downsampled map, a ray toward its centre
  // from the same origin computeTransfer uses (position + offset * geometric normal).
  const prt::TransferSettings defaults;
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
      prt::TransferSettings settings;
      settings.bands = n;
      settings.raysPerVertex = rays;
      settings.shadowed = true;
      settings.threads = o.threads;
      prt::TransferStats stats;
      Diagnostics run;
      const prt::VertexTransfer transfer = prt::computeTransfer(mesh, settings, tracer.get(), run, {}, &stats);
      if (!run.ok() || transfer.vertexCount() != vertexCount) return error = run.format(), false;
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
  if (!csv.ok() || !un.ok()) return error = "cannot write " + (data / "end_to_end*.csv").string(), false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// 4. Stiff and extreme cases
struct Check {
  std::string name, value, tolerance;
  bool pass = false;
};

double maxCoefficientDifference(const prt::ShCoefficients& a, const prt::ShCoefficients& b, int bands) {
  double e = 0.0;
  for (int i = 0; i < prt::shCount(bands); ++i)
    for (int c = 0; c < 3; ++c)
      e = std::max(e, std::abs(a.c[static_cast<std::size_t>(i)][c] - b.c[static_cast<std::size_t>(i)][c]));
  return e;
}
double dcScale(const prt::ShCoefficients& a) { return std::max({std::abs(a.c[0].x), std::abs(a.c[0].y), std::abs(a.c[0].z)}); }

bool measureExtremes(const Plan& plan, const ReportOptions& o, const fs::path& data, std::vector<Check>& checks,
                     std::string& error) {
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
    std::string mapError;
    const std::string path = o.assets + "/envmaps/blender_studiolight_forest.exr";
    const std::optional<prt::EnvironmentMap> full = loadMap(path, mapError);
    if (!full) return error = mapError, false;
    std::optional<prt::EnvironmentMap> map =
        boxDownsample(*full, std::min(full->width(), plan.rotationMapWidth), std::min(full->height(), plan.rotationMapWidth / 2));
    if (!map) return error = path + ": cannot downsample for the rotation check", false;
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
  if (!csv.ok()) return error = "cannot write " + (data / "extremes.csv").string(), false;
  return true;
}

// ---------------------------------------------------------------------------------------------
std::string fixed(double v, int digits) { return str("%.*f", digits, v); }

void writeLightingSection(Markdown& md, const Plan& plan, const std::vector<LightingResult>& results) {
  md.line("## 1. Lighting truncation");
  md.line();
  md.line(str("Irradiance from n SH bands (n^2 coefficients) against brute force over every pixel of the full-size map "
              "(`bruteForceIrradiance`, computed once per map), at %d Fibonacci normals. Error per normal: the worst of "
              "R, G, B of |E_SH - E_ref| / E_ref (`irradianceError`); mean and max over the normals. Projection: "
              "`projectRadiance`, one thread, best of %d. Data: [lighting_truncation.csv](data/prt/lighting_truncation.csv), "
              "[lighting_windows.csv](data/prt/lighting_windows.csv).",
              plan.lightingNormals, plan.projectionRepeats));
  md.line();
  md.line("![lighting truncation](img/prt_lighting_truncation.png)");
  md.line();
  md.line("Error (mean / max relative irradiance error):");
  md.line();
  std::vector<std::string> header{"map", "size"};
  for (int n = 2; n <= prt::kMaxShBands; ++n) header.push_back(str("n = %d", n));
  std::vector<std::vector<std::string>> rows, timing;
  for (const auto& r : results) {
    std::vector<std::string> row{r.map, str("%dx%d", r.width, r.height)}, t{r.map, fixed(r.bruteForceMs, 0)};
    for (int n = 2; n <= prt::kMaxShBands; ++n) {
      row.push_back(str("%.4f / %.3f", r.error[n].mean, r.error[n].max));
      t.push_back(fixed(r.projectionMs[n], 2));
    }
    rows.push_back(row), timing.push_back(t);
  }
  md.table(header, rows);
  md.line("n = 4, 6, 8 give exactly the error of n = 3, 5, 7: they add an odd band l = 3, 5, 7, and the clamped "
          "cosine's A_l is 0 for every odd l > 1, so the irradiance does not see those bands (they matter for "
          "shadowed transfer, section 3).");
  md.line();
  md.line("Timing (ms): the brute force over all normals, and the projection for each n:");
  md.line();
  header[1] = "brute force";
  md.table(header, timing);
  for (std::size_t b = 0; b < kWindowBands.size(); ++b) {
    md.line(str("Windows at n = %d: mean / max relative error, and the lowest irradiance over the normals divided by "
                "the map's mean irradiance (below 0: the ringing's negative lobe). Sinc4's cutoff h is the largest "
                "that leaves no negative lobe (inf: none needed, so no blur). The error the others add over 'none' "
                "is the blur they cost.",
                kWindowBands[b]));
    md.line();
    rows.clear();
    for (const auto& r : results) {
      std::vector<std::string> row{r.map};
      const double h = r.windows[b][3].cutoff;
      row.push_back(std::isfinite(h) ? str("%.3g", h) : "inf");
      for (const auto& w : r.windows[b]) row.push_back(str("%.4f / %.3f / %.3f", w.error.mean, w.error.max, w.minOverMean));
      rows.push_back(row);
    }
    md.table({"map", "sinc4 h", "none", "hann", "lanczos", "sinc4"}, rows);
  }
}

void writeSamplingSection(Markdown& md, const Plan& plan, const std::vector<SamplingCase>& cases) {
  md.line("## 2. Transfer sampling");
  md.line();
  md.line(str("`sampleTransfer` (N stratified, jittered cosine-weighted directions, as `computeTransfer` casts them) for "
              "a vertex that sees only a cone of half-angle a about its normal (visibility 1 inside the cone, 0 "
              "outside; a = 90 degrees is unshadowed), against the exact `coneTransfer`, n = %d bands. Error: "
              "||T_sampled - T_exact|| / ||T_exact|| over the %d coefficients, mean over %d Fibonacci normals (one "
              "seed each). The slope is the least-squares fit of log error against log N. Data: "
              "[transfer_sampling.csv](data/prt/transfer_sampling.csv).",
              kSamplingBands, prt::shCount(kSamplingBands), plan.samplingNormals));
  md.line();
  md.line("![transfer sampling](img/prt_transfer_sampling.png)");
  md.line();
  std::vector<std::string> header{"cone half-angle"};
  for (int n : plan.samplingRays) header.push_back(str("N = %d", n));
  header.push_back("fitted slope");
  std::vector<std::vector<std::string>> rows;
  for (const auto& c : cases) {
    std::vector<std::string> row{str("%g deg", c.halfAngleDeg)};
    for (double e : c.mean) row.push_back(str("%.2e", e));
    row.push_back(str("%.3f", c.slope));
    rows.push_back(row);
  }
  md.table(header, rows);
  md.line("Reading the slopes: the estimator maps a stratum (i, j) of the unit square to the disc point of radius "
          "sqrt(u1), so a cone about the normal is exactly u1 < sin^2(a): its edge is a line of the sqrt(N) x sqrt(N) "
          "grid's rows. For 30 and 60 degrees (sin^2 = 1/4, 3/4) the edge falls on stratum boundaries whenever 4 "
          "divides sqrt(N) (N = 1024, 3136, 10000, 99856): no stratum straddles it and the error is as small as "
          "unshadowed (slope near -1, the smooth integrand's rate under jittered stratification). At sqrt(N) = 10, "
          "18 and 177 a row of strata straddles the edge and the error jumps. 85 degrees never aligns: its slope is "
          "the honest one for a visibility edge (theory: -0.75 for a discontinuity in 2D, jittered). A real "
          "occluder's edge is not aligned with the grid, so plan with the 85 degree row.");
  md.line();
  md.line("Timing (microseconds per normal, one thread; the estimator alone, no ray tracing):");
  md.line();
  rows.clear();
  header.pop_back();
  for (const auto& c : cases) {
    std::vector<std::string> row{str("%g deg", c.halfAngleDeg)};
    for (double us : c.usPerNormal) row.push_back(fixed(us, 1));
    rows.push_back(row);
  }
  md.table(header, rows);
}

void writeEndToEndSection(Markdown& md, const Plan& plan, const ReportOptions& o, const EndToEndResult& r) {
  md.line("## 3. End to end on RobotExpressive, shadowed");
  md.line();
  md.line(str("RobotExpressive in its rest pose (`bindPoseMesh` default), %zu vertices. Reference: for %zu vertices "
              "(every %zu-th), the ray-traced irradiance E_ref(v) = sum over the pixels of the map downsampled to "
              "%dx%d (box filter weighted by solid angle) of L(pixel) V(v, pixel centre) max(0, n.w) dw, the "
              "visibility by Embree rays from the same origin as `computeTransfer` (position + `rayOriginOffset` "
              "along the geometric normal; n the shading normal). %zu of the %zu vertices are buried (>= 99 %% of "
              "their cosine-weighted rays blocked: inside other parts of the model) and left out: %zu remain (over the "
              "whole mesh, the precompute at N = %d finds %zu of %zu vertices so buried). PRT: E_prt(v) = sum_i L_i T_v,i with "
              "L projected from the SAME downsampled map, so the two differ only by the band limit and the sampling. "
              "T from `computeTransfer` on the whole mesh for each (n, N), %u threads, timed; the subset's values "
              "used. Error per channel: |E_prt - E_ref| / mean(E_ref) (relative to the mean: shadowed irradiance "
              "can be ~0), mean and 95th percentile over the vertices. Relight: `TransferRelighter::relight` on the "
              "whole mesh, one thread, best of %d, scaled to 10k vertices. Reference time: %.1f s. Data: "
              "[end_to_end.csv](data/prt/end_to_end.csv) (every channel), "
              "[end_to_end_unshadowed.csv](data/prt/end_to_end_unshadowed.csv).",
              r.vertices, r.candidates, std::max<std::size_t>(1, r.vertices / std::max<std::size_t>(1, r.candidates)),
              r.downWidth, r.downHeight, r.buried, r.candidates, r.candidates - r.buried, plan.transferRays.back(),
              r.meshBuried, r.vertices, o.threads,
              plan.relightRepeats, r.referenceSeconds));
  md.line();
  md.line("![end to end work-precision](img/prt_end_to_end.png)");
  md.line();
  for (std::size_t m = 0; m < r.maps.size(); ++m) {
    md.line(str("**%s** (mean E_ref R, G, B: %.3g, %.3g, %.3g). Mean error R / G / B, p95 of the worst channel, "
                "precompute seconds (whole mesh), relight microseconds per 10k vertices:",
                r.maps[m].c_str(), r.meanReference[m].x, r.meanReference[m].y, r.meanReference[m].z));
    md.line();
    std::vector<std::vector<std::string>> rows;
    for (const auto& row : r.rows)
      if (row.map == r.maps[m])
        rows.push_back({std::to_string(row.n), std::to_string(row.rays),
                        str("%.4f / %.4f / %.4f", row.error.mean.x, row.error.mean.y, row.error.mean.z),
                        str("%.4f", row.error.worstP95()), fixed(row.precomputeSeconds, 2), fixed(row.relightUs, 1)});
    md.table({"n", "N", "mean error R / G / B", "p95 (worst channel)", "precompute s", "relight us / 10k"}, rows);
  }
  md.line("Work-precision summary at the largest N (error: mean of the worst channel), with the unshadowed transfer "
          "(closed form, no rays) against the same shadowed reference, i.e. what the shadows are worth:");
  md.line();
  std::vector<std::string> header{"n"};
  for (const auto& name : r.maps) header.push_back(name + " shadowed"), header.push_back(name + " unshadowed");
  header.push_back(str("precompute s (N = %d)", plan.transferRays.back()));
  header.push_back("relight us / 10k");
  header.push_back("d log error / d log n^2 from n - 1 (per map)");
  std::vector<std::vector<std::string>> rows;
  auto shadowedAt = [&](const std::string& name, int n) -> const EndToEndRow* {
    for (const auto& x : r.rows)
      if (x.map == name && x.n == n && x.rays == plan.transferRays.back()) return &x;
    return nullptr;
  };
  for (int n = 2; n <= prt::kMaxShBands; ++n) {
    std::vector<std::string> row{std::to_string(n)};
    double seconds = 0.0, us = 0.0;
    std::string elasticity;
    for (const auto& name : r.maps) {
      if (const EndToEndRow* x = shadowedAt(name, n)) {
        row.push_back(str("%.4f", x->error.worstMean())), seconds = x->precomputeSeconds, us = x->relightUs;
        const EndToEndRow* previous = shadowedAt(name, n - 1);
        if (previous && previous->error.worstMean() > 0 && x->error.worstMean() > 0)
          elasticity += (elasticity.empty() ? "" : " / ") +
                        str("%.2f", std::log(x->error.worstMean() / previous->error.worstMean()) /
                                        std::log(static_cast<double>(n * n) / ((n - 1) * (n - 1))));
      }
      for (const auto& x : r.unshadowed)
        if (x.map == name && x.n == n) row.push_back(str("%.4f", x.error.worstMean()));
    }
    row.push_back(fixed(seconds, 2));
    row.push_back(fixed(us, 1));
    row.push_back(elasticity.empty() ? "-" : elasticity);
    rows.push_back(row);
  }
  md.table(header, rows);
  md.line("The last column is the slope of the work-precision curve between n - 1 and n, with the per-frame work "
          "taken as n^2 (the relight loop is n^2 multiply-adds per channel and vertex; the measured times follow it "
          "within the machine's noise, 7 to 8 us per coefficient per 10k vertices), so that the column does not "
          "change between runs: below -1 the error falls faster than the work grows, above -1 each step buys less "
          "than it costs.");
  md.line();
}

void writeExtremesSection(Markdown& md, const std::vector<Check>& checks) {
  md.line("## 4. Stiff and extreme cases");
  md.line();
  md.line("Values measured by this run; pass when within the stated tolerance. Data: "
          "[extremes.csv](data/prt/extremes.csv).");
  md.line();
  std::vector<std::vector<std::string>> rows;
  for (const auto& c : checks) rows.push_back({c.name, c.value, c.tolerance, c.pass ? "pass" : "**FAIL**"});
  md.table({"check", "value", "tolerance", "result"}, rows);
}

bool runGnuplot(const ReportOptions& o, const std::string& script, const fs::path& data, const fs::path& img,
                std::string& error) {
  const std::string path = o.scripts + "/" + script;
  const std::string command = "gnuplot -e \"data='" + data.string() + "'; img='" + img.string() + "'\" '" + path + "'";
  if (std::system(command.c_str()) != 0) return error = "gnuplot failed on " + path + " (" + command + ")", false;
  return true;
}
}  // namespace

int prtReportCommand(const PrtReportOptions& o) {
  for (const std::string* p : {&o.docs, &o.scripts})
    if (p->find_first_of("'\"") != std::string::npos) return reportFail("paths with quotes are not supported: " + *p);
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    return reportFail("gnuplot not found on PATH: the report draws its plots with it (Debian: apt-get install gnuplot-nox)");
  for (const char* script : {"plot_prt_lighting.gp", "plot_prt_sampling.gp", "plot_prt_end_to_end.gp"})
    if (!fs::exists(o.scripts + "/" + script))
      return reportFail(o.scripts + "/" + script + ": gnuplot script not found (--scripts DIR: the source tree's scripts/)");

  const auto start = Clock::now();
  Plan plan;
  const std::string shared = o.assets + "/envmaps/";
  plan.lightingMaps = {{"royal_esplanade", shared + "royal_esplanade_1k.hdr"},
                       {"quarry_01", shared + "quarry_01_1k.hdr"},
                       {"blender_forest", shared + "blender_studiolight_forest.exr"}};
  for (const char* name : {"city", "courtyard", "forest", "interior", "night", "studio", "sunrise", "sunset"})
    plan.lightingMaps.push_back({std::string("studiolight_") + name, o.studiolights + "/" + name + ".exr"});
  if (o.quick) {
    plan.lightingMaps = {plan.lightingMaps[2], plan.lightingMaps[0]};
    plan.lightingNormals = 200;
    plan.projectionRepeats = 1;
    plan.samplingNormals = 16;
    plan.samplingRays = {100, 324, 1024, 3136};
    plan.subsetVertices = 100;
    plan.downWidth = 64, plan.downHeight = 32;
    plan.transferRays = {16, 64};
    plan.relightRepeats = 20;
    plan.rotationMapWidth = 256;
  }
  const fs::path docs(o.docs), data = docs / "data" / "prt", img = docs / "img";
  std::error_code ec;
  fs::create_directories(data, ec);
  fs::create_directories(img, ec);
  if (!fs::is_directory(data) || !fs::is_directory(img)) return reportFail("cannot create " + data.string() + " and " + img.string());

  std::string error;
  std::vector<LightingResult> lighting;
  if (!measureLighting(plan, o, data, lighting, error)) return reportFail(error);
  std::vector<SamplingCase> sampling;
  if (!measureSampling(plan, data, sampling, error)) return reportFail(error);
  EndToEndResult endToEnd;
  if (!measureEndToEnd(plan, o, data, endToEnd, error)) return reportFail(error);
  std::vector<Check> checks;
  if (!measureExtremes(plan, o, data, checks, error)) return reportFail(error);
  for (const char* script : {"plot_prt_lighting.gp", "plot_prt_sampling.gp", "plot_prt_end_to_end.gp"})
    if (!runGnuplot(o, script, data, img, error)) return reportFail(error);
  const double total = secondsSince(start);

  Markdown md;
  md.line("# PRT accuracy report");
  md.line();
  md.line(str("Generated by `marionette prt report --docs %s%s` (do not edit: rerun it; `scripts/accuracy` does). "
              "Every figure is measured by that run; reruns differ only in the timing columns.",
              o.docs.c_str(), o.quick ? " --quick" : ""));
  md.line();
  md.line("Machine: " + machine() + str("; %u threads where stated, otherwise one. Total run time of the report: %.0f s%s.",
                                        o.threads, total, o.quick ? " (--quick: fewer maps, normals, rays and vertices)" : ""));
  md.line();
  writeLightingSection(md, plan, lighting);
  writeSamplingSection(md, plan, sampling);
  writeEndToEndSection(md, plan, o, endToEnd);
  writeExtremesSection(md, checks);
  std::ofstream(docs / "prt-report.md") << md.text;
  if (!fs::exists(docs / "prt-report.md")) return reportFail("cannot write " + (docs / "prt-report.md").string());

  std::size_t failed = 0;
  for (const Check& c : checks)
    if (!c.pass) ++failed, std::fprintf(stderr, "marionette prt report: warning: check failed: %s: %s (tolerance %s)\n",
                                        c.name.c_str(), c.value.c_str(), c.tolerance.c_str());
  std::printf("wrote %s, %s/*.csv, %s/prt_*.png in %.1f s\n", (docs / "prt-report.md").c_str(), data.c_str(), img.c_str(),
              total);
  return failed ? 1 : 0;
}

}  // namespace marionette::cli
