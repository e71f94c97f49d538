// `marionette prt` on the command line: lighting-error, precompute and the report (its --quick
// smoke run), as a user runs them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "test_data.hpp"

using namespace marionette::test;

namespace {
// The last line of the output that is a JSON object (warnings may come before it).
nlohmann::json lastJson(const std::string& out) {
  std::istringstream in(out);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line[0] == '{') last = line;
  return nlohmann::json::parse(last, nullptr, false);
}

// A CSV file as rows of named cells (no quoted commas in the columns read here).
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::map<std::string, std::string>> rows;
  if (!std::getline(in, line)) return rows;
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::map<std::string, std::string> row;
    std::size_t k = 0;
    for (std::string cell; std::getline(ss, cell, ',') && k < header.size(); ++k) row[header[k]] = cell;
    rows.push_back(row);
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& key) {
  const auto it = row.find(key);
  return it == row.end() ? std::nan("") : std::strtod(it->second.c_str(), nullptr);
}

// Regression bound (issue 41): each error of a quick-report row that the published full report
// (docs/data/prt/<table>.csv) also has stays within 1.5x the published figure. The quick run
// uses fewer pixels and samples, and its rows come out at 0.69-1.45x the published ones
// (deterministic); a change that doubles an error fails. Returns how many rows were compared.
int expectWithinPublished(const std::string& quickCsv, const std::string& table, const std::vector<std::string>& keys,
                          const std::vector<std::string>& errors) {
  const auto published = readCsv(sourceFile("docs/data/prt/" + table + ".csv"));
  EXPECT_FALSE(published.empty()) << "docs/data/prt/" << table << ".csv";
  const auto keyOf = [&](const std::map<std::string, std::string>& row) {
    std::string k;
    for (const auto& name : keys) k += (row.count(name) ? row.at(name) : "?") + "/";
    return k;
  };
  std::map<std::string, std::map<std::string, std::string>> byKey;
  for (const auto& row : published) byKey[keyOf(row)] = row;
  int compared = 0;
  for (const auto& row : readCsv(quickCsv)) {
    const auto it = byKey.find(keyOf(row));
    if (it == byKey.end()) continue;
    ++compared;
    for (const auto& e : errors)
      EXPECT_LE(number(row, e), 1.5 * number(it->second, e))
          << table << " row " << keyOf(row) << " column " << e << ": published " << it->second.at(e);
  }
  return compared;
}
}  // namespace

TEST(PrtCli, LightingErrorJsonFallsWithTheBandCount) {
  const std::string map = sharedAsset("envmaps/blender_studiolight_forest.exr");
  MARIONETTE_REQUIRE_FILE(map);
  double previous = 1e9;
  for (int bands : {2, 4, 8}) {
    const CliRun r = runCli("prt lighting-error --env " + map + " --bands " + std::to_string(bands) + " --json");
    ASSERT_LE(r.status, 1) << r.out;
    const nlohmann::json j = lastJson(r.out);
    ASSERT_FALSE(j.is_discarded()) << r.out;
    ASSERT_TRUE(j.contains("mean") && j.contains("max")) << r.out;
    const double mean = j["mean"], max = j["max"];
    EXPECT_TRUE(std::isfinite(mean) && std::isfinite(max)) << r.out;
    EXPECT_GT(mean, 0.0);
    EXPECT_LE(mean, max);
    EXPECT_LT(mean, previous) << "bands " << bands;
    EXPECT_EQ(j["bands"], bands);
    previous = mean;
  }
}

TEST(PrtCli, LightingErrorRejectsAMissingMapAndTooManyBands) {
  CliRun r = runCli("prt lighting-error --env /nonexistent/sky.hdr --json");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("/nonexistent/sky.hdr"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;

  const std::string map = sharedAsset("envmaps/quarry_01_1k.hdr");
  r = runCli("prt lighting-error --env " + map + " --bands 9 --json");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("--bands: '9': expected an integer in 2..8"), std::string::npos) << r.out;
  EXPECT_EQ(runCli("prt lighting-error").status, 2);
}

TEST(PrtCli, PrecomputeJsonWritesTheCacheAndTimesTheRays) {
  const std::string robot = sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(robot);
  const std::string cache = ::testing::TempDir() + "prt_cli_robot.prt";
  std::filesystem::remove(cache);
  CliRun r = runCli("prt precompute " + robot + " --bands 3 --rays 16 --shadowed --threads 2 -o " + cache + " --json");
  ASSERT_LE(r.status, 1) << r.out;
  nlohmann::json j = lastJson(r.out);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  ASSERT_TRUE(j.contains("vertices") && j.contains("seconds") && j.contains("raw_ray_seconds")) << r.out;
  EXPECT_GT(j["vertices"].get<std::size_t>(), 1000u);
  EXPECT_GT(j["seconds"].get<double>(), 0.0);
  EXPECT_GT(j["raw_ray_seconds"].get<double>(), 0.0);
  EXPECT_TRUE(j["shadowed"].get<bool>());
  EXPECT_TRUE(std::filesystem::exists(cache));
  EXPECT_GT(std::filesystem::file_size(cache), 0u);

  std::filesystem::remove(cache);
  r = runCli("prt precompute " + robot + " --bands 3 -o " + cache + " --json");
  ASSERT_LE(r.status, 1) << r.out;
  j = lastJson(r.out);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  EXPECT_EQ(j["raw_ray_seconds"].get<double>(), 0.0);
  EXPECT_FALSE(j["shadowed"].get<bool>());
  EXPECT_TRUE(std::filesystem::exists(cache));

  EXPECT_EQ(runCli("prt precompute " + robot).status, 2);  // no -o
}

TEST(PrtCli, QuickReportWritesSaneTablesCsvsAndPlots) {
  MARIONETTE_REQUIRE_FILE(sharedAsset("characters/RobotExpressive.glb"));
  MARIONETTE_REQUIRE_FILE(blenderStudiolight("forest.exr"));
  const std::filesystem::path docs = ::testing::TempDir() + "prt_report_quick";
  std::filesystem::remove_all(docs);
  const CliRun r = runCli("prt report --quick --docs " + docs.string() + " --assets " + sharedAsset("") +
                          " --studiolights " + blenderStudiolight("") + " --scripts " + sourceFile("scripts"));
  ASSERT_EQ(r.status, 0) << r.out;

  const std::string md = readFile((docs / "prt-report.md").string());
  for (const char* section : {"## 1. Lighting truncation", "## 2. Transfer sampling", "## 3. End to end",
                              "## 4. Stiff and extreme cases", "Machine: ", "marionette prt report"})
    EXPECT_NE(md.find(section), std::string::npos) << section;
  EXPECT_EQ(md.find("FAIL"), std::string::npos) << md;
  for (const char* png : {"prt_lighting_truncation.png", "prt_transfer_sampling.png", "prt_end_to_end.png"}) {
    const std::string bytes = readFile((docs / "img" / png).string());
    ASSERT_GT(bytes.size(), 1000u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
  }

  const std::filesystem::path data = docs / "data" / "prt";
  // 1. Lighting: finite, and the error on forest falls from n = 2 to n = 8.
  std::map<int, double> forest;
  for (const auto& row : readCsv((data / "lighting_truncation.csv").string())) {
    EXPECT_TRUE(std::isfinite(number(row, "mean_rel_error")) && std::isfinite(number(row, "max_rel_error")));
    EXPECT_GE(number(row, "projection_ms"), 0.0);
    if (row.at("map") == "blender_forest") forest[static_cast<int>(number(row, "n"))] = number(row, "mean_rel_error");
  }
  ASSERT_EQ(forest.size(), 7u);
  EXPECT_LT(forest[8], forest[2]);
  EXPECT_LT(forest[8], 0.05);
  EXPECT_EQ(readCsv((data / "lighting_windows.csv").string()).size(), 16u);  // 2 maps x 2 n x 4 windows
  // 2. Sampling: the unshadowed error falls at least as fast as N^-0.5.
  int unshadowedRows = 0;
  for (const auto& row : readCsv((data / "transfer_sampling.csv").string())) {
    EXPECT_GT(number(row, "mean_rel_l2_error"), 0.0);
    EXPECT_LT(number(row, "mean_rel_l2_error"), 1.0);
    if (number(row, "half_angle_deg") == 90.0) {
      ++unshadowedRows;
      EXPECT_LT(number(row, "slope"), -0.5);
    } else {
      EXPECT_LT(number(row, "slope"), -0.3);
    }
  }
  EXPECT_GE(unshadowedRows, 3);
  // 3. End to end: finite errors well under 1, positive times, every n for both maps.
  const auto endToEnd = readCsv((data / "end_to_end.csv").string());
  std::map<int, double> forestEnd;  // n -> mean error (worst channel) at the largest N
  EXPECT_EQ(endToEnd.size(), 2u * 7u * 2u);  // maps x n x N (--quick: 2 ray counts)
  for (const auto& row : endToEnd) {
    for (const char* key : {"mean_r", "mean_g", "mean_b", "p95_worst"}) {
      EXPECT_TRUE(std::isfinite(number(row, key))) << key;
      EXPECT_GE(number(row, key), 0.0) << key;
    }
    EXPECT_LT(number(row, "mean_worst"), 2.0);  // royal_esplanade's sun at n = 2: 0.9
    EXPECT_GT(number(row, "precompute_s"), 0.0);
    EXPECT_GT(number(row, "relight_us_per_10k"), 0.0);
    if (row.at("map") == "blender_forest" && number(row, "N") == 64) forestEnd[static_cast<int>(number(row, "n"))] =
        number(row, "mean_worst");
  }
  ASSERT_EQ(forestEnd.size(), 7u);
  EXPECT_LT(forestEnd[4], forestEnd[2]);  // shadowed forest at N = 64: about 0.1 against 0.28
  EXPECT_LT(forestEnd[4], 0.2);
  // Regression bounds against the published full report.
  EXPECT_EQ(expectWithinPublished((data / "lighting_truncation.csv").string(), "lighting_truncation", {"map", "n"},
                                  {"mean_rel_error", "max_rel_error"}),
            14);
  EXPECT_EQ(expectWithinPublished((data / "transfer_sampling.csv").string(), "transfer_sampling",
                                  {"half_angle_deg", "N"}, {"mean_rel_l2_error", "max_rel_l2_error"}),
            16);
  EXPECT_EQ(expectWithinPublished((data / "end_to_end.csv").string(), "end_to_end", {"map", "n", "N"},
                                  {"mean_worst", "p95_worst"}),
            14);  // N = 64 (N = 16 is the quick run's own)
  // 4. Every stiff and extreme case passes.
  const std::string extremes = readFile((data / "extremes.csv").string());
  EXPECT_NE(extremes.find("pass"), std::string::npos);
  EXPECT_EQ(extremes.find("FAIL"), std::string::npos) << extremes;
}

TEST(PrtCli, ReportRejectsUnknownOptions) {
  const CliRun r = runCli("prt report --frobnicate");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("--frobnicate"), std::string::npos) << r.out;
}
