// Work-precision of the lip-sync curves (docs/accuracy.md, "Lip-sync curves"):
// the viseme onset error and the bilabial closures, against the time to build the
// curves of a 10 s utterance and the time of one evaluate(), as one setting at a
// time moves away from its default.
//   marionette_lipsync_work_precision OUT.csv
// Ground truths: the real phone alignment of CMU ARCTIC arctic_a0009 (a recorded
// voice, ../shared/assets/speech), and, when the build has espeak-ng, its own
// phoneme events on five sentences (the ARCTIC one included) at 175 and 300 words
// per minute. Onset error and closure as defined in tests/support/lipsync_measure.hpp.
// Columns: setting, value, source, units, merged, dips, mean_ms (signed),
// mean_abs_ms, p95_abs_ms, max_abs_ms, share_within_45ms, bilabials, closure_missed,
// mean_peak and min_peak (how far each unit's viseme shows: 1 is no co-articulation
// at its peak), fastest_per_s (the fastest change of any channel, 1/s: how abrupt
// the mouth moves), build_us_10s and evaluate_ns (0 in the last, joint block:
// its cost is the defaults'). One block per setting and source, separated by two
// blank lines (gnuplot's `index`); the block order is printed on stderr.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "lipsync_measure.hpp"
#include "marionette/speech/alignment_io.hpp"
#ifdef MARIONETTE_HAS_TTS
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif
#include "marionette/speech/lipsync.hpp"
#include "test_paths.hpp"

using namespace marionette;
using namespace marionette::speech;

namespace {

struct Source {
  std::string name;
  std::vector<std::vector<Phoneme>> utterances;
  std::vector<double> durations;
};

const char* const kSentences[] = {
    "He turned sharply, and faced Gregson across the table.",
    "Peter Piper picked a peck of pickled peppers.",
    "Please remember to bring my umbrella, maybe by Monday.",
    "The quick brown fox jumps over the lazy dog.",
    "We will meet them at the museum before the boat leaves.",
};

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double buildMicroseconds(const std::vector<Phoneme>& tenSeconds, const LipSyncSettings& s) {
  std::vector<double> runs;
  for (int r = 0; r < 41; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const VisemeCurves c = buildVisemeCurves(tenSeconds, 10.0, s);
    const auto t1 = std::chrono::steady_clock::now();
    if (c.frames == 0) std::fprintf(stderr, "empty curves\n");
    runs.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  return medianOf(runs);
}

double evaluateNanoseconds(const std::vector<Phoneme>& tenSeconds, const LipSyncSettings& s) {
  const VisemeCurves c = buildVisemeCurves(tenSeconds, 10.0, s);
  std::array<float, kLipChannelCount> w{};
  std::vector<double> runs;
  float sink = 0.0f;
  constexpr int kCalls = 200000;
  for (int r = 0; r < 7; ++r) {
    double t = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kCalls; ++i) {
      c.evaluate(t, w);
      sink += w[static_cast<std::size_t>(i % kLipChannelCount)];
      t += 0.0167;  // about a frame at 60 Hz, wrapping
      if (t > 10.0) t -= 10.0;
    }
    const auto t1 = std::chrono::steady_clock::now();
    runs.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / kCalls);
  }
  if (sink == -1.0f) std::fprintf(stderr, "?\n");
  return medianOf(runs);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
    return 2;
  }
  std::vector<Source> sources;
  const Alignment arctic = readAlignment(::marionette::test::sharedDir() + "/assets/speech/arctic_a0009.phones.txt");
  if (!arctic.error.empty() || arctic.phonemes.empty()) {
    std::fprintf(stderr, "arctic_a0009: %s\n", arctic.error.c_str());
    return 1;
  }
  double arcticEnd = 0.0;
  for (const auto& p : arctic.phonemes) arcticEnd = std::max(arcticEnd, p.end);
  sources.push_back({"arctic_a0009", {arctic.phonemes}, {arcticEnd}});
#ifdef MARIONETTE_HAS_TTS
  std::string whyNot;
  if (const auto espeak = makeEspeakBackend(&whyNot)) {
    for (const int wpm : {175, 300}) {
      Source src{"espeak_" + std::to_string(wpm) + "wpm", {}, {}};
      for (const char* text : kSentences) {
        SpeechRequest req;
        req.text = text;
        req.wordsPerMinute = wpm;
        const SpeechResult r = espeak->synthesize(req);
        if (!r.utterance) {
          std::fprintf(stderr, "espeak-ng: %s\n", r.error.c_str());
          return 1;
        }
        src.utterances.push_back(r.utterance->phonemes);
        src.durations.push_back(r.utterance->duration);
      }
      sources.push_back(std::move(src));
    }
  } else {
    std::fprintf(stderr, "no espeak-ng sources: %s\n", whyNot.c_str());
  }
#else
  std::fprintf(stderr, "no espeak-ng sources: built without MARIONETTE_WITH_TTS\n");
#endif
  const std::vector<Phoneme> tenSeconds = test::tiledTo(arctic.phonemes, 10.0);

  struct Sweep {
    const char* name;
    std::vector<double> values;
    std::function<void(LipSyncSettings&, double)> set;
  };
  const std::vector<Sweep> sweeps = {
      {"sampleRate", {25, 50, 100, 200, 400}, [](LipSyncSettings& s, double v) { s.sampleRate = v; }},
      {"anticipationRate", {20, 40, 60, 90, 120, 180}, [](LipSyncSettings& s, double v) { s.anticipationRate = v; }},
      {"carryOverRate", {20, 40, 60, 90, 120, 180}, [](LipSyncSettings& s, double v) { s.carryOverRate = v; }},
      {"dominanceWidth", {0, 0.25, 0.5, 0.75, 1}, [](LipSyncSettings& s, double v) { s.dominanceWidth = v; }},
      {"maxSpeed", {4, 8, 12, 16, 24, 32, 0}, [](LipSyncSettings& s, double v) { s.maxSpeed = v; }},
      {"minVisible", {0, 0.03, 0.05, 0.08, 0.12}, [](LipSyncSettings& s, double v) { s.minVisible = v; }},
      {"pauseDominance", {0.1, 0.3, 1}, [](LipSyncSettings& s, double v) { s.pauseDominance = v; }},
  };

  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", argv[1]);
    return 1;
  }
  std::fprintf(out,
               "setting,value,source,units,merged,dips,mean_ms,mean_abs_ms,p95_abs_ms,max_abs_ms,share_within_45ms,"
               "bilabials,closure_missed,mean_peak,min_peak,fastest_per_s,build_us_10s,evaluate_ns\n");
  // One row: `s` on every utterance of `src`.
  const auto row = [&](const std::string& setting, const std::string& value, const Source& src, const LipSyncSettings& s,
                       double buildUs, double evalNs) {
    std::vector<double> errors;
    int units = 0, merged = 0, dips = 0, bilabials = 0, missed = 0;
    double peakSum = 0.0, peakMin = 1.0, fastest = 0.0;
    std::size_t peakCount = 0;
    for (std::size_t u = 0; u < src.utterances.size(); ++u) {
      const VisemeCurves c = buildVisemeCurves(src.utterances[u], src.durations[u], s);
      const test::OnsetReport r = test::measureOnsets(src.utterances[u], c);
      errors.insert(errors.end(), r.errors.begin(), r.errors.end());
      for (const double p : r.peaks) {
        peakSum += p;
        peakMin = std::min(peakMin, p);
        ++peakCount;
      }
      for (int k = 0; k + 1 < c.frames; ++k)
        for (std::size_t ch = 0; ch < static_cast<std::size_t>(kLipChannelCount); ++ch)
          fastest = std::max(fastest, static_cast<double>(std::fabs(c.values[(static_cast<std::size_t>(k) + 1) * kLipChannelCount + ch] -
                                                                    c.values[static_cast<std::size_t>(k) * kLipChannelCount + ch])) *
                                          c.sampleRate);
      units += r.units;
      merged += r.merged;
      dips += r.dips;
      const test::ClosureReport cr = test::measureClosures(src.utterances[u], c);
      bilabials += cr.bilabials;
      missed += cr.missed;
    }
    const test::ErrorStats st = test::errorStats(errors);
    std::fprintf(out, "%s,%s,%s,%d,%d,%d,%.2f,%.2f,%.2f,%.2f,%.3f,%d,%d,%.3f,%.3f,%.1f,%.2f,%.2f\n", setting.c_str(),
                 value.c_str(), src.name.c_str(), units, merged, dips, st.mean * 1e3, st.meanAbs * 1e3, st.p95Abs * 1e3,
                 st.maxAbs * 1e3, st.shareUnder(0.045, errors), bilabials, missed,
                 peakCount ? peakSum / static_cast<double>(peakCount) : 0.0, peakMin, fastest, buildUs, evalNs);
  };
  int block = 0;
  for (const Sweep& sw : sweeps) {
    // Timing per value once (it does not depend on the source).
    std::vector<double> buildUs, evalNs;
    for (const double v : sw.values) {
      LipSyncSettings s;
      sw.set(s, v);
      buildUs.push_back(buildMicroseconds(tenSeconds, s));
      evalNs.push_back(evaluateNanoseconds(tenSeconds, s));
    }
    for (const Source& src : sources) {
      std::fprintf(stderr, "block %d: %s on %s\n", block++, sw.name, src.name.c_str());
      for (std::size_t i = 0; i < sw.values.size(); ++i) {
        LipSyncSettings s;
        sw.set(s, sw.values[i]);
        char value[32];
        std::snprintf(value, sizeof value, "%g", sw.values[i]);
        row(sw.name, value, src, s, buildUs[i], evalNs[i]);
      }
      std::fprintf(out, "\n\n");
    }
  }
  // The three settings that trade smoothness for timing, together (how the
  // defaults were picked: docs/accuracy.md). Value: maxSpeed/anticipation/carry-over.
  for (const Source& src : sources) {
    std::fprintf(stderr, "block %d: maxSpeed x anticipationRate x carryOverRate on %s\n", block++, src.name.c_str());
    for (const double speed : {12.0, 16.0, 20.0, 24.0})
      for (const double ant : {60.0, 90.0})
        for (const double carry : {60.0, 90.0}) {
          LipSyncSettings s;
          s.maxSpeed = speed;
          s.anticipationRate = ant;
          s.carryOverRate = carry;
          char value[48];
          std::snprintf(value, sizeof value, "%g/%g/%g", speed, ant, carry);
          row("speed/anticipation/carryOver", value, src, s, 0.0, 0.0);
        }
    std::fprintf(out, "\n\n");
  }
  std::fclose(out);
  return 0;
}
