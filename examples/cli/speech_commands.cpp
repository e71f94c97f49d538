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

}  // namespace

int speakCommand(const SpeakOptions& o) {
  SpeechRequest request;
  request.text = o.text;
  request.voice = o.voice;
  if (o.wordsPerMinute) request.wordsPerMinute = *o.wordsPerMinute;
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
  if (std::string error = writeWav(o.output, u.audio, u.sampleRate); !error.empty()) {
    std::fprintf(stderr, "marionette speak: error: %s\n", error.c_str());
    return 2;
  }
  const VisemeCurves curves = buildVisemeCurves(u.phonemes, u.duration);
  if (!writeVisemeCsv(o.visemes, curves, "speak")) return 2;
  if (!o.phonemes.empty() && !writePhonemeCsv(o.phonemes, u)) return 2;
  std::printf("speak: %.3f s, %zu phonemes, %d Hz -> %s, %s\n", u.duration, u.phonemes.size(), u.sampleRate,
              o.output.c_str(), o.visemes.c_str());
  return printWarnings(u.warnings, "speak");
}

int lipsyncCommand(const LipSyncOptions& o) {
  Utterance u;
  if (const std::string& audio = o.audio; !audio.empty()) {
    WavAudio wav;
    if (std::string error = readWav(audio, wav); !error.empty()) {
      std::fprintf(stderr, "marionette lipsync: error: %s\n", error.c_str());
      return 2;
    }
    u.audio = std::move(wav.samples);
    u.sampleRate = wav.sampleRate;
  }
  Alignment a = readAlignment(o.phones);
  if (!a.error.empty()) {
    std::fprintf(stderr, "marionette lipsync: error: %s\n", a.error.c_str());
    return 2;
  }
  u.phonemes = std::move(a.phonemes);
  u.warnings = std::move(a.warnings);
  normalizeTiming(u);
  const VisemeCurves curves = buildVisemeCurves(u.phonemes, u.duration);
  if (!writeVisemeCsv(o.visemes, curves, "lipsync")) return 2;
  std::printf("lipsync: %.3f s, %zu phonemes -> %s\n", u.duration, u.phonemes.size(), o.visemes.c_str());
  return printWarnings(u.warnings, "lipsync");
}

}  // namespace marionette::cli
