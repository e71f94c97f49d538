// Work-precision of the locomotion smoothing and foot IK (docs/accuracy.md) on
// RobotExpressive (../shared/assets/characters) with its profile. For each setting
// LocomotionSettings offers (gait blend time constant, foot planting on/off,
// contact height, release time, IK softness, and how far beyond the leg's reach
// a planted foot steps and the time it steps in) and for the frame step, over a
// range: the 5 m walk, run and mid-speed walk of
// tests/behavior/locomotion_real_test.cpp, measured as there
// (tests/support/locomotion_walk.hpp): foot skating, arrival and facing error,
// planted-foot drift from the lock point (all locks; the locks made at full gait
// weight), the IK's own residual and the catch-up steps taken (a planted foot the
// leg no longer reached); and the run time per Character update and of
// the locomotion controller alone (CharacterStats, wall clock: the mean over a
// walk's frames, median of kRepeats rounds that each run every walk once).
//   marionette_locomotion_work_precision OUT.csv
// One CSV block per setting family, separated by two blank lines (gnuplot's
// `index`); within a block a row per (value, gait) and a row "all" that pools the
// three gaits (skating frames over contact frames, the largest errors, the mean
// costs). planted_drift_m is empty when no foot was planted, and
// planted_drift_full_gait_m when none was planted at full gait weight. The blocks
// of the two step settings come after the frame step's (the plot shows the first
// six). Exit status 1 when two rounds measured differently (not deterministic).
#include <algorithm>
#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

#include "locomotion_walk.hpp"
#include "marionette/io/import.hpp"
#include "test_paths.hpp"

using namespace marionette;
using namespace marionette::test;

namespace {
constexpr int kRepeats = 15;
constexpr double kNever = 1e9;  // a setting value that switches the feature off

std::shared_ptr<Rig> loadRobot() {
  ImportResult r = importAsset(::marionette::test::sharedDir() + "/assets/characters/RobotExpressive.glb");
  if (!r.ok()) {
    std::fprintf(stderr, "%s", r.diagnostics.format().c_str());
    return nullptr;
  }
  auto asset = std::make_shared<Asset>(std::move(*r.asset));
  auto rig = std::make_shared<Rig>(*asset);
  CharacterProfileResult p =
      loadCharacterProfile(::marionette::test::sourceDir() + "/assets/profiles/RobotExpressive.json", *asset);
  if (!p.diagnostics.ok()) {
    std::fprintf(stderr, "%s", p.diagnostics.format().c_str());
    return nullptr;
  }
  rig->setProfile(std::move(p.profile));
  return rig;
}

struct Setting {
  std::string label;
  double value = 0.0;
  bool isDefault = false;
  LocomotionSettings settings;
  float dt = 1.0f / 60.0f;
};
struct Family {
  std::string name;
  std::vector<Setting> settings;
};

// The measures of one walk (deterministic) and its costs, one per repeat.
struct Row {
  WalkMeasure m;
  std::vector<double> usPerUpdate, usLocomotion;
  bool deterministic = true;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::vector<Family> families() {
  const LocomotionSettings d;
  std::vector<Family> out;
  auto family = [&](const std::string& name, std::initializer_list<double> values, double def, auto&& set) {
    Family f{name, {}};
    for (double v : values) {
      Setting s;
      s.value = v;
      s.isDefault = static_cast<float>(v) == static_cast<float>(def);  // the defaults are floats
      set(s, v);
      char buf[64];
      // Frame steps below 0.05 s read better as rates: 1/60.
      if (name.starts_with("frame") && v < 0.05) std::snprintf(buf, sizeof buf, "1/%.0f", 1.0 / v);
      else if (v >= kNever) std::snprintf(buf, sizeof buf, "never");  // no lock gets that far: no step
      else std::snprintf(buf, sizeof buf, "%g", v);
      s.label = buf;
      f.settings.push_back(s);
    }
    out.push_back(f);
  };
  family("blend time constant (s)", {0.0, 0.02, 0.05, 0.1, 0.15, 0.3, 0.6, 1.0}, d.blendTimeConstant,
         [](Setting& s, double v) { s.settings.blendTimeConstant = static_cast<float>(v); });
  family("foot planting (on = 1)", {0.0, 1.0}, d.feet.enabled ? 1.0 : 0.0,
         [](Setting& s, double v) { s.settings.feet.enabled = v != 0.0; });
  family("contact height (m)", {0.0, 0.01, 0.02, 0.04, 0.06, 0.1, 0.15, 0.25}, d.feet.contactHeight,
         [](Setting& s, double v) { s.settings.feet.contactHeight = static_cast<float>(v); });
  family("release time (s)", {0.0, 0.03, 0.06, 0.12, 0.25, 0.5}, d.feet.releaseSeconds,
         [](Setting& s, double v) { s.settings.feet.releaseSeconds = static_cast<float>(v); });
  family("IK softness", {0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.4}, d.feet.ik.softness,
         [](Setting& s, double v) { s.settings.feet.ik.softness = static_cast<float>(v); });
  family("frame step (s)", {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30, 0.1, 0.25, 0.5}, 1.0 / 60,
         [](Setting& s, double v) { s.dt = static_cast<float>(v); });
  family("step beyond the leg's reach by (m)", {0.0, 0.02, 0.05, 0.08, 0.12, kNever}, d.feet.maxOverreach,
         [](Setting& s, double v) { s.settings.feet.maxOverreach = static_cast<float>(v); });
  family("step time (s)", {0.1, 0.15, 0.25, 0.4, 0.6}, d.feet.stepSeconds,
         [](Setting& s, double v) { s.settings.feet.stepSeconds = static_cast<float>(v); });
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
    return 2;
  }
  const std::shared_ptr<Rig> rig = loadRobot();
  if (!rig) return 1;
  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "%s: cannot write\n", argv[1]);
    return 2;
  }
  float mid = 0.0f;
  {
    Scene scene;
    const LocomotionSet& set = scene.addCharacter("c", rig)->locomotionSet();
    mid = 0.5f * (set.walk.groundSpeed + set.run.groundSpeed);
  }
  const std::pair<const char*, WalkSpec> gaits[] = {{"walk", {{3.0f, 4.0f}, 90.0f, LocomotionManner::Walk, 0.0f}},
                                                    {"run", {{-4.0f, -3.0f}, -30.0f, LocomotionManner::Run, 0.0f}},
                                                    {"mid", {{0.0f, 5.0f}, 0.0f, LocomotionManner::Walk, mid}}};
  std::fprintf(out,
               "family,setting,is_default,gait,dt_s,skating_pct,contact_frames,arrival_error_m,facing_error_deg,"
               "planted_drift_m,planted_drift_full_gait_m,ik_residual_m,arrived,seconds,us_per_update,"
               "us_locomotion_per_update,us_locomotion_per_simulated_second,steps\n");
  // Every walk once per round, the rounds repeated: load from other processes
  // then falls on all settings alike instead of on whichever ran during it.
  const std::vector<Family> all = families();
  std::vector<Row> rows;
  for (const Family& family : all) rows.resize(rows.size() + family.settings.size() * std::size(gaits));
  for (int round = 0; round < kRepeats; ++round) {
    std::size_t j = 0;
    for (const Family& family : all)
      for (const Setting& s : family.settings)
        for (const auto& gait : gaits) {
          Row& row = rows[j++];
          const WalkMeasure m = measureWalk(rig, gait.second, s.dt, s.settings, true);
          if (round == 0) row.m = m;
          // The update is deterministic: every round must measure the same.
          if (m.skatingFrames != row.m.skatingFrames || m.arrivalError != row.m.arrivalError ||
              m.plantedDrift != row.m.plantedDrift || m.ikResidual != row.m.ikResidual || m.steps != row.m.steps)
            row.deterministic = false;
          row.usPerUpdate.push_back(m.updateMicros / std::max(1, m.frames));
          row.usLocomotion.push_back(m.locomotionMicros / std::max(1, m.frames));
        }
  }

  bool first = true, allDeterministic = true;
  std::size_t j = 0;
  for (const Family& family : all) {
    if (!first) std::fprintf(out, "\n\n");  // a gnuplot data block per family
    first = false;
    std::printf("%s\n", family.name.c_str());
    for (const Setting& s : family.settings) {
      int skating = 0, contact = 0, steps = 0;
      bool arrived = true;
      float arrival = 0.0f, facing = 0.0f, drift = -1.0f, driftFull = -1.0f, residual = 0.0f, seconds = 0.0f;
      double us = 0.0, usLoco = 0.0;
      // A drift < 0: no such lock was made (an empty field).
      auto line = [&](const char* gait, float skatingPct, int contactFrames, float arr, float fac, float dri,
                      float driFull, float res, bool done, float sec, double u, double ul, int stepCount) {
        char any[32] = "", full[32] = "";
        if (dri >= 0.0f) std::snprintf(any, sizeof any, "%.5f", static_cast<double>(dri));
        if (driFull >= 0.0f) std::snprintf(full, sizeof full, "%.5f", static_cast<double>(driFull));
        std::fprintf(out, "%s,%s,%d,%s,%.6f,%.3f,%d,%.5f,%.3f,%s,%s,%.5f,%d,%.3f,%.3f,%.3f,%.1f,%d\n",
                     family.name.c_str(), s.label.c_str(), s.isDefault ? 1 : 0, gait, static_cast<double>(s.dt),
                     static_cast<double>(skatingPct), contactFrames, static_cast<double>(arr),
                     static_cast<double>(fac), any, full, static_cast<double>(res), done ? 1 : 0,
                     static_cast<double>(sec), u, ul, ul / static_cast<double>(s.dt), stepCount);
        std::printf("  %-6s %-4s skating %6.2f %% of %4d  arrival %.3f m  facing %.2f deg  drift %.3f m (full gait "
                    "%.3f)  IK miss %.3f m  %d steps  %s %.2f s  %.2f us/update, locomotion %.2f us%s\n",
                    s.label.c_str(), gait, static_cast<double>(skatingPct), contactFrames, static_cast<double>(arr),
                    static_cast<double>(fac), static_cast<double>(dri), static_cast<double>(driFull),
                    static_cast<double>(res), stepCount, done ? "arrived" : "NOT ARRIVED", static_cast<double>(sec),
                    u, ul, s.isDefault ? "  (default)" : "");
      };
      for (const auto& gait : gaits) {
        const Row& r = rows[j++];
        allDeterministic = allDeterministic && r.deterministic;
        const float facingDeg = r.m.facingError * 180.0f / 3.14159265f;
        const double u = median(r.usPerUpdate), ul = median(r.usLocomotion);
        line(gait.first, 100.0f * r.m.skatingRatio, r.m.contactFrames, r.m.arrivalError, facingDeg,
             r.m.locks ? r.m.plantedDrift : -1.0f,
             r.m.fullGaitLocks ? r.m.plantedDriftFullGait : -1.0f, r.m.ikResidual, r.m.done, r.m.seconds, u, ul,
             r.m.steps);
        skating += r.m.skatingFrames;
        steps += r.m.steps;
        contact += r.m.contactFrames;
        arrived = arrived && r.m.done;
        arrival = std::max(arrival, r.m.arrivalError);
        facing = std::max(facing, facingDeg);
        if (r.m.locks) drift = std::max(drift, r.m.plantedDrift);
        if (r.m.fullGaitLocks) driftFull = std::max(driftFull, r.m.plantedDriftFullGait);
        residual = std::max(residual, r.m.ikResidual);
        seconds = std::max(seconds, r.m.seconds);
        us += u / static_cast<double>(std::size(gaits));
        usLoco += ul / static_cast<double>(std::size(gaits));
      }
      line("all", contact ? 100.0f * static_cast<float>(skating) / static_cast<float>(contact) : 100.0f, contact,
           arrival, facing, drift, driftFull, residual, arrived, seconds, us, usLoco, steps);
    }
  }
  std::fclose(out);
  if (!allDeterministic) {
    std::fprintf(stderr, "error: repeated walks measured differently (the update is meant to be deterministic)\n");
    return 1;
  }
  return 0;
}
