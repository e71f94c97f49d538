// `marionette speak` (espeak-ng -> WAV, viseme and phoneme CSV) and
// `marionette lipsync` (a recorded line's alignment -> viseme CSV).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "commands.hpp"
#include "marionette/speech/alignment_io.hpp"
#include "example_synthesizer.hpp"
#include "marionette/speech/lipsync.hpp"

namespace marionette::cli {

namespace {

using namespace marionette::speech;

// V.csv: "time,<channel>,..." and a row per 1/100 s from 0 to the end, every weight in [0,1].
bool writeVisemeCsv(const std::string& path, const VisemeCurves& curves, const char* command) {
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (!out) {
    std::fprintf(stderr, "marionette %s: error: %s: cannot open for writing\n", command, path.c_str());
    return false;
  }
  std::fputs("time", out);
  for (int c = 0; c < kLipChannelCount; ++c) std::fprintf(out, ",%s", std::string(lipChannelName(c)).c_str());
  std::fputc('\n', out);
  float channels[kLipChannelCount];
  const long rows = static_cast<long>(std::ceil(curves.duration * 100.0 - 1e-9)) + 1;
  for (long k = 0; k < rows; ++k) {
    const double t = static_cast<double>(k) / 100.0;
    curves.evaluate(t, channels);
    std::fprintf(out, "%.2f", t);
    for (float v : channels) std::fprintf(out, ",%.4f", static_cast<double>(v));
    std::fputc('\n', out);
  }
  const bool ok = std::fclose(out) == 0;
  if (!ok) std::fprintf(stderr, "marionette %s: error: %s: write failed\n", command, path.c_str());
  return ok;
}

bool writePhonemeCsv(const std::string& path, const Utterance& u) {
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (!out) {
    std::fprintf(stderr, "marionette speak: error: %s: cannot open for writing\n", path.c_str());
    return false;
  }
  std::fputs("start,end,phoneme\n", out);
  for (const Phoneme& p : u.phonemes) std::fprintf(out, "%.5f,%.5f,%s\n", p.start, p.end, p.name.c_str());
  return std::fclose(out) == 0;
}

int printWarnings(const std::vector<std::string>& warnings, const char* command) {
  for (const std::string& w : warnings) std::fprintf(stderr, "marionette %s: warning: %s\n", command, w.c_str());
  return warnings.empty() ? 0 : 1;
}

// Reads "--name value" options; returns false (after an error message) on a missing value or unknown option.
struct Options {
  std::vector<std::pair<std::string, std::string>> values;
  std::vector<std::string> positional;
  [[nodiscard]] std::string get(const std::string& name) const {
    for (const auto& [n, v] : values)
      if (n == name) return v;
    return {};
  }
};
bool parseOptions(const std::vector<std::string>& args, std::initializer_list<const char*> known, const char* command,
                  Options& out) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.size() > 1 && a[0] == '-') {
      bool ok = false;
      for (const char* k : known) ok |= a == k;
      if (!ok) {
        std::fprintf(stderr, "marionette %s: error: unknown option '%s'\n", command, a.c_str());
        return false;
      }
      if (i + 1 >= args.size()) {
        std::fprintf(stderr, "marionette %s: error: %s needs a value\n", command, a.c_str());
        return false;
      }
      out.values.emplace_back(a, args[++i]);
    } else {
      out.positional.push_back(a);
    }
  }
  return true;
}

}  // namespace

int speakCommand(const std::vector<std::string>& args) {
  Options o;
  const char* usage =
      "usage: marionette speak \"TEXT\" [--voice en-us] [--rate WPM] -o OUT.wav --visemes V.csv [--phonemes P.csv]\n";
  if (!parseOptions(args, {"--voice", "--rate", "-o", "--visemes", "--phonemes"}, "speak", o)) return 2;
  if (o.positional.size() != 1 || o.get("-o").empty() || o.get("--visemes").empty()) {
    std::fputs(usage, stderr);
    return 2;
  }
  SpeechRequest request;
  request.text = o.positional.front();
  request.voice = o.get("--voice");
  if (const std::string rate = o.get("--rate"); !rate.empty()) {
    char* end = nullptr;
    const double wpm = std::strtod(rate.c_str(), &end);
    if (*end != '\0' || !std::isfinite(wpm) || wpm < 1 || wpm > 10000) {
      std::fprintf(stderr, "marionette speak: error: --rate expects words per minute in [1, 10000], got '%s'\n", rate.c_str());
      return 2;
    }
    request.wordsPerMinute = static_cast<int>(std::lround(wpm));
  }
  std::string why;
  auto tts = examples::exampleSynthesizer(&why);
  if (!tts) {
    std::fprintf(stderr, "marionette speak: error: %s\n", why.c_str());
    return 2;
  }
  const SpeechResult said = tts->synthesize(request);
  if (!said.utterance) {
    std::fprintf(stderr, "marionette speak: error: %s\n", said.error.c_str());
    return 2;
  }
  const Utterance& u = *said.utterance;
  if (std::string error = writeWav(o.get("-o"), u.audio, u.sampleRate); !error.empty()) {
    std::fprintf(stderr, "marionette speak: error: %s\n", error.c_str());
    return 2;
  }
  const VisemeCurves curves = buildVisemeCurves(u.phonemes, u.duration);
  if (!writeVisemeCsv(o.get("--visemes"), curves, "speak")) return 2;
  if (!o.get("--phonemes").empty() && !writePhonemeCsv(o.get("--phonemes"), u)) return 2;
  std::printf("speak: %.3f s, %zu phonemes, %d Hz -> %s, %s\n", u.duration, u.phonemes.size(), u.sampleRate,
              o.get("-o").c_str(), o.get("--visemes").c_str());
  return printWarnings(u.warnings, "speak");
}

int lipsyncCommand(const std::vector<std::string>& args) {
  Options o;
  if (!parseOptions(args, {"--audio", "--phones", "--visemes"}, "lipsync", o)) return 2;
  if (!o.positional.empty() || o.get("--phones").empty() || o.get("--visemes").empty()) {
    std::fputs("usage: marionette lipsync [--audio A.wav] --phones P.txt|P.lab|P.tsv --visemes V.csv\n", stderr);
    return 2;
  }
  Utterance u;
  if (const std::string audio = o.get("--audio"); !audio.empty()) {
    WavAudio wav;
    if (std::string error = readWav(audio, wav); !error.empty()) {
      std::fprintf(stderr, "marionette lipsync: error: %s\n", error.c_str());
      return 2;
    }
    u.audio = std::move(wav.samples);
    u.sampleRate = wav.sampleRate;
  }
  Alignment a = readAlignment(o.get("--phones"));
  if (!a.error.empty()) {
    std::fprintf(stderr, "marionette lipsync: error: %s\n", a.error.c_str());
    return 2;
  }
  u.phonemes = std::move(a.phonemes);
  u.warnings = std::move(a.warnings);
  normalizeTiming(u);
  const VisemeCurves curves = buildVisemeCurves(u.phonemes, u.duration);
  if (!writeVisemeCsv(o.get("--visemes"), curves, "lipsync")) return 2;
  std::printf("lipsync: %.3f s, %zu phonemes -> %s\n", u.duration, u.phonemes.size(), o.get("--visemes").c_str());
  return printWarnings(u.warnings, "lipsync");
}

}  // namespace marionette::cli
