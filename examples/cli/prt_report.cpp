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
// This file: the command and the report's Markdown; each experiment is in its own
// prt_report_<experiment>.cpp, what they share in prt_report_detail.hpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "prt_report_detail.hpp"
#include "report_tables.hpp"

namespace marionette::cli {

namespace detail {
namespace {

int reportFail(const std::string& message) {
  std::fprintf(stderr, "marionette prt report: error: %s\n", message.c_str());
  return 2;
}

int reportFail(const Diagnostics& diagnostics) {
  std::fputs(diagnostics.format().c_str(), stderr);
  return 2;
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
                Diagnostics& diagnostics) {
  const std::string path = o.scripts + "/" + script;
  const std::string command = "gnuplot -e \"data='" + data.string() + "'; img='" + img.string() + "'\" '" + path + "'";
  if (std::system(command.c_str()) != 0) return diagnostics.error(path, "gnuplot failed on the script (" + command + ")"), false;
  return true;
}
}  // namespace
}  // namespace detail

int prtReportCommand(const PrtReportOptions& o) {
  using namespace detail;
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

  Diagnostics problems;
  std::vector<LightingResult> lighting;
  if (!measureLighting(plan, o, data, lighting, problems)) return reportFail(problems);
  std::vector<SamplingCase> sampling;
  if (!measureSampling(plan, data, sampling, problems)) return reportFail(problems);
  EndToEndResult endToEnd;
  if (!measureEndToEnd(plan, o, data, endToEnd, problems)) return reportFail(problems);
  std::vector<Check> checks;
  if (!measureExtremes(plan, o, data, checks, problems)) return reportFail(problems);
  for (const char* script : {"plot_prt_lighting.gp", "plot_prt_sampling.gp", "plot_prt_end_to_end.gp"})
    if (!runGnuplot(o, script, data, img, problems)) return reportFail(problems);
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
