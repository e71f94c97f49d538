#include "marionette/speech/recorded_speech.hpp"

#include <algorithm>
#include <cmath>

namespace marionette::speech {

namespace {

bool isAsciiAlnum(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }
// Letters (and any byte of a UTF-8 sequence) carry sound; spaces and punctuation do not.
bool sounds(char c) { return isAsciiAlnum(c) || static_cast<unsigned char>(c) >= 0x80; }

}  // namespace

std::string RecordedSpeech::matchKey(std::string_view text) {
  std::string key;
  bool gap = false;
  for (char c : text) {
    if (sounds(c)) {
      if (gap && !key.empty()) key += ' ';
      key += (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
      gap = false;
    } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      gap = true;
    }  // punctuation joins ("don't" = "dont")
  }
  return key;
}

std::string RecordedSpeech::addLine(std::string_view text, const std::filesystem::path& audio,
                                    const std::filesystem::path& alignment, const FileReader& files) {
  WavAudio wav;
  if (!audio.empty())
    if (std::string error = readWav(files, audio, wav); !error.empty()) return error;
  Alignment a = readAlignment(files, alignment);
  if (!a.error.empty()) return a.error;
  return addLine(text, std::move(wav), std::move(a), alignment.string());
}

std::string RecordedSpeech::addLine(std::string_view text, WavAudio audio, Alignment alignment,
                                    std::string_view source) {
  const std::string key = matchKey(text);
  if (key.empty()) return "recorded line '" + std::string(source) + "': its text has no words to match requests by";
  if (!alignment.error.empty()) return alignment.error;
  if (alignment.phonemes.empty()) return "recorded line '" + std::string(source) + "': the alignment has no phonemes";
  if (!audio.samples.empty() && audio.sampleRate <= 0)
    return "recorded line '" + std::string(source) + "': the audio has no sample rate";
  double alignedEnd = 0.0;
  for (const Phoneme& p : alignment.phonemes)
    if (std::isfinite(p.end)) alignedEnd = std::max(alignedEnd, p.end);
  auto u = std::make_shared<Utterance>();
  u->text = std::string(text);
  u->phonemes = std::move(alignment.phonemes);
  u->audio = std::move(audio.samples);
  u->sampleRate = audio.sampleRate;
  u->warnings = std::move(alignment.warnings);
  normalizeTiming(*u);
  if (!u->audio.empty() && !u->phonemes.empty()) {
    const double audioSeconds = static_cast<double>(u->audio.size()) / u->sampleRate;
    // normalizeTiming clamped the phonemes to the audio; say so when that cut real speech.
    if (alignedEnd > audioSeconds + 0.05)
      u->warnings.push_back("recorded line '" + std::string(source) + "': the alignment runs past the audio's end");
  }
  std::lock_guard lock(mutex_);
  for (Line& l : lines_)
    if (l.key == key) {  // a newer recording of the same words replaces the old one
      l.utterance = std::move(u);
      return {};
    }
  lines_.push_back({key, std::move(u)});
  return {};
}

std::size_t RecordedSpeech::lineCount() const {
  std::lock_guard lock(mutex_);
  return lines_.size();
}

SpeechResult RecordedSpeech::synthesize(const SpeechRequest& request) {
  const std::string key = matchKey(request.text);
  std::shared_ptr<const Utterance> found;
  {
    std::lock_guard lock(mutex_);
    for (const Line& l : lines_)
      if (l.key == key) found = l.utterance;
  }
  if (!found) return {nullptr, "no recorded line says \"" + request.text + "\""};
  auto u = std::make_shared<Utterance>(*found);
  u->text = request.text;
  if (!request.marks.empty()) {
    // The voiced span: from the first phoneme that is not a pause to the last.
    double from = 0.0, to = u->duration;
    auto firstVoiced = std::find_if(u->phonemes.begin(), u->phonemes.end(), [](const Phoneme& p) { return !p.cls.pause; });
    auto lastVoiced = std::find_if(u->phonemes.rbegin(), u->phonemes.rend(), [](const Phoneme& p) { return !p.cls.pause; });
    if (firstVoiced != u->phonemes.end()) from = firstVoiced->start, to = lastVoiced->end;
    std::size_t letters = 0;
    for (char c : request.text) letters += sounds(c) ? 1 : 0;
    for (const TextMark& m : request.marks) {
      std::size_t before = 0;
      const std::size_t end = std::min(m.characterOffset, request.text.size());
      for (std::size_t i = 0; i < end; ++i) before += sounds(request.text[i]) ? 1 : 0;
      const double share = letters ? static_cast<double>(before) / static_cast<double>(letters) : 0.0;
      u->marks.push_back({m.id, from + share * (to - from)});
    }
  }
  normalizeTiming(*u);
  return {std::move(u), {}};
}

}  // namespace marionette::speech
