// espeak-ng in process (marionette::tts_espeak, built only with MARIONETTE_WITH_TTS).
//
// What espeak-ng 1.51 puts in an event (checked in its source, speech.c
// MarkerEvent, and by experiment): `sample` is the number of output samples
// since the start of the utterance (the samples of the buffers already handed
// to the callback plus the position inside the current one), and
// audio_position is the same instant in whole milliseconds, floor(sample *
// 1000 / rate). So a phoneme starts at sample / rate seconds; "Hello world" at
// 175 wpm: its END event's sample equals the audio's length (16707 samples).
//
// At 450 words per minute and above espeak-ng speeds its speech up with the
// sonic library, and the events are stamped before sonic's buffering: their
// samples go backwards now and then and the last ones fall past the end of the
// audio (measured on a 13-word sentence with 20 ms buffers: 450 wpm 3 steps
// back, up to 5.9 ms, and 27 ms past the end; 900 wpm 14 steps, up to 29 ms,
// and 36 ms past; with 200 ms buffers up to 110 ms back). The engine's emission
// order is still the spoken order, so the backend first fits the starts to a
// non-decreasing sequence in that order (keeping "w 3: l d" from becoming
// "w 3: d l", as a sort would), then normalizeTiming clamps what is past the end.
#include "marionette/tts_espeak/espeak_backend.hpp"

#include "marionette/core/text.hpp"
#include "marionette/speech/text_pieces.hpp"

#include <espeak-ng/speak_lib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace marionette::speech {

namespace {

constexpr const char* kDefaultVoice = "en-us";
constexpr int kDefaultRate = espeakRATE_NORMAL;  // 175 wpm
constexpr int kMinRate = espeakRATE_MINIMUM;     // 80: espeak-ng itself speaks no slower
// espeak-ng accepts any higher rate (through sonic), but beyond ~6x normal the
// speech is no longer intelligible; a larger number is taken as a mistake.
constexpr int kMaxRate = 1000;
constexpr int kSonicRate = 450;
constexpr int kBufferMs = 20;  // from here on espeak-ng's phoneme times are unreliable

// One synthesis' output, filled by the callback.
struct Capture {
  std::vector<std::int16_t> audio;
  struct Raw {
    std::string name;
    std::int64_t sample;
  };
  std::vector<Raw> phonemes;
  std::vector<std::pair<std::string, std::int64_t>> marks;
  std::vector<std::pair<int, std::int64_t>> words;  // (text_position: 1-based code point in the SSML, sample)
};

int onSynth(short* wav, int count, espeak_EVENT* events) {
  if (events == nullptr) return 0;
  auto* capture = static_cast<Capture*>(events->user_data);
  if (capture == nullptr) return 0;
  if (wav != nullptr && count > 0) capture->audio.insert(capture->audio.end(), wav, wav + count);
  for (espeak_EVENT* e = events; e->type != espeakEVENT_LIST_TERMINATED; ++e) {
    if (e->type == espeakEVENT_PHONEME) {
      // Up to 8 bytes, zero-terminated only when shorter.
      capture->phonemes.push_back({std::string(e->id.string, strnlen(e->id.string, sizeof e->id.string)), e->sample});
    } else if (e->type == espeakEVENT_MARK && e->id.name != nullptr) {
      capture->marks.emplace_back(e->id.name, e->sample);
    } else if (e->type == espeakEVENT_WORD) {
      capture->words.emplace_back(e->text_position, e->sample);
    }
  }
  return 0;  // go on
}

// A first-come first-served lock: the engine goes to callers in the order they
// asked. std::mutex makes no such promise, and a long line said in pieces would
// take it back between its pieces before a waiting caller woke.
class FairLock {
 public:
  void lock() {
    std::unique_lock guard(mutex_);
    const std::uint64_t ticket = next_++;
    turn_.wait(guard, [&] { return serving_ == ticket; });
  }
  void unlock() {
    {
      std::lock_guard guard(mutex_);
      ++serving_;
    }
    turn_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable turn_;
  std::uint64_t next_ = 0, serving_ = 0;
};

// espeak-ng keeps global state: one engine for the process, one synthesis at a time.
struct Engine {
  FairLock turn;  // whose turn it is to use the engine
  bool started = false;
  int sampleRate = 0;
  std::string startError;  // set once if the engine could not start; repeated to every caller
  // espeak-ng's wave generator carries its glottal phase and pitch flutter
  // from one synthesis to the next (1.51 has no reset, and Terminate then
  // Initialize hangs), so the same text twice differs by a sample or two.
  // The last results are kept: the same request gives the same utterance.
  std::deque<std::pair<std::string, std::shared_ptr<const Utterance>>> recent;
};
constexpr std::size_t kRecentResults = 32;

Engine& engine() {
  // Never destroyed: a static Scene's speech thread may still use it while statics go.
  static Engine* instance = new Engine();
  return *instance;
}

std::string dataPath() {
  const char* path = nullptr;
  espeak_Info(&path);
  return path != nullptr ? path : "(unknown)";
}

// Under the engine's lock.
void startEngine(Engine& e) {
  if (e.started) return;
  e.started = true;
  // DONT_EXIT: espeak-ng would otherwise end the whole process when its data is missing.
  // 20 ms buffers: with sonic (450 wpm and above) event times are off by up to
  // about half a buffer; measured at 900 wpm, 200 ms buffers put phonemes up to
  // 110 ms backwards, 20 ms buffers up to 29 ms (and 60 ms no better than 20).
  const int rate = espeak_Initialize(AUDIO_OUTPUT_SYNCHRONOUS, kBufferMs, nullptr,
                                     espeakINITIALIZE_PHONEME_EVENTS | espeakINITIALIZE_DONT_EXIT);
  if (rate <= 0) {
    e.startError = "espeak-ng could not start: its data directory '" + dataPath() +
                   "' is missing or incomplete (install espeak-ng-data, or point ESPEAK_DATA_PATH at the "
                   "folder that holds espeak-ng-data)";
    return;
  }
  e.sampleRate = rate;
  espeak_SetSynthCallback(onSynth);
}


// A mark's offset moved back to the start of the UTF-8 sequence it falls in.
std::size_t utf8Boundary(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  while (offset > 0 && offset < text.size() && (static_cast<unsigned char>(text[offset]) & 0xC0) == 0x80) --offset;
  return offset;
}

int codePoints(std::string_view s) {
  int n = 0;
  for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}

// Pool-adjacent-violators: the non-decreasing sequence nearest (least squares)
// to `x`, in place. Then members of a tied block are spread over the gap to the
// next block, so no phoneme ends up with no time at all.
void fitNonDecreasing(std::vector<double>& x, double end) {
  struct Block {
    double sum;
    std::size_t count;
    double mean() const { return sum / static_cast<double>(count); }
  };
  std::vector<Block> blocks;
  for (double v : x) {
    blocks.push_back({v, 1});
    while (blocks.size() > 1 && blocks[blocks.size() - 2].mean() > blocks.back().mean()) {
      blocks[blocks.size() - 2].sum += blocks.back().sum;
      blocks[blocks.size() - 2].count += blocks.back().count;
      blocks.pop_back();
    }
  }
  std::size_t i = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const double from = blocks[b].mean();
    const double to = b + 1 < blocks.size() ? blocks[b + 1].mean() : std::max(from, end);
    const auto n = static_cast<double>(blocks[b].count);
    for (std::size_t k = 0; k < blocks[b].count; ++k) x[i++] = from + (to - from) * static_cast<double>(k) / n;
  }
}

// One piece of the text, [from, to), as SSML with a <mark/> at each of marks[first, last)
// (offsets into the whole text). markPositions gets where each mark starts as espeak-ng
// counts: 1-based code points of the SSML. The engine sees "m<index>", not the caller's
// id: any id works (espeak-ng truncates long mark names), and a mark it reports is matched exactly.
std::string pieceSsml(std::string_view text, std::size_t from, std::size_t to, const std::vector<TextMark>& marks,
                      std::size_t first, std::size_t last, std::vector<int>& markPositions) {
  std::string ssml = "<speak>";
  std::size_t at = from, counted = 0;
  int ssmlCodePoints = 0;
  for (std::size_t i = first; i < last; ++i) {
    const std::size_t offset = std::clamp(marks[i].characterOffset, from, to);
    appendXmlEscaped(ssml, text.substr(at, offset - at));
    at = offset;
    ssmlCodePoints += codePoints(std::string_view(ssml).substr(counted));
    counted = ssml.size();
    markPositions.push_back(ssmlCodePoints + 1);
    ssml += "<mark name=\"m" + std::to_string(i) + "\"/>";
  }
  appendXmlEscaped(ssml, text.substr(at, to - at));
  ssml += "</speak>";
  return ssml;
}

// A voice file name ("en-us", "gmw/en-US") or, failing that, a language
// ("en-gb" names no file: its voice is "gmw/en"). Under the engine's lock.
bool selectVoice(const std::string& voice) {
  if (espeak_SetVoiceByName(voice.c_str()) == EE_OK) return true;
  espeak_VOICE wanted{};
  wanted.languages = voice.c_str();
  return espeak_SetVoiceByProperties(&wanted) == EE_OK;
}

class EspeakBackend final : public SpeechBackend {
 public:
  std::string_view name() const noexcept override { return "espeak-ng"; }

  SpeechResult synthesize(const SpeechRequest& request) override {
    SpeechResult result;
    auto u = std::make_shared<Utterance>();
    u->text = request.text;

    // The line's voice; one the engine lacks (another engine's name: "openmary", "marytts")
    // falls back to the request's fallback voice, else the default, with a warning.
    const std::string fallback = request.fallbackVoice.empty() ? std::string(kDefaultVoice) : request.fallbackVoice;
    std::string voice = request.voice.empty() ? fallback : request.voice;
    int rate = request.wordsPerMinute == 0 ? kDefaultRate : request.wordsPerMinute;
    if (rate < kMinRate || rate > kMaxRate) {
      const int clamped = std::clamp(rate, kMinRate, kMaxRate);
      u->warnings.push_back("espeak-ng: " + std::to_string(rate) + " words per minute is outside [" +
                            std::to_string(kMinRate) + ", " + std::to_string(kMaxRate) + "]; using " +
                            std::to_string(clamped));
      rate = clamped;
    }

    // Marks in text order (stable: marks at one offset keep their order).
    std::vector<TextMark> marks = request.marks;
    for (TextMark& m : marks) m.characterOffset = utf8Boundary(request.text, m.characterOffset);
    std::stable_sort(marks.begin(), marks.end(),
                     [](const TextMark& a, const TextMark& b) { return a.characterOffset < b.characterOffset; });
    Engine& e = engine();
    int sampleRate = 0;
    std::string key;
    {
      std::lock_guard lock(e.turn);
      startEngine(e);
      if (!e.startError.empty()) {
        result.error = e.startError;
        return result;
      }
      if (!selectVoice(voice)) {
        if (voice == fallback || !selectVoice(fallback)) {
          result.error = "espeak-ng has no voice '" + voice + "'" +
                         (voice == fallback ? std::string() : " nor '" + fallback + "'") +
                         " (neither a voice name such as 'en-us' nor a language such as 'en-gb'; voices are listed by "
                         "`espeak-ng --voices`; data in '" + dataPath() + "')";
          return result;
        }
        u->warnings.push_back("espeak-ng has no voice '" + voice + "' (another engine's name?); the line is said with '" +
                              fallback + "' (\"voices\" in the scene or the character's profile maps names to voices)");
        voice = fallback;
      }
      // The voice asked for too: a fallen-back line carries its warning, a line asked in the
      // fallback voice does not.
      key = request.voice + '\n' + voice + '\n' + std::to_string(rate) + '\n' + request.text;
      for (const TextMark& m : marks) key += '\n' + std::to_string(m.characterOffset) + ':' + m.id;
      for (const auto& [k, done] : e.recent)
        if (k == key) {
          result.utterance = done;
          return result;
        }
      sampleRate = e.sampleRate;
    }

    // Said in pieces (text_pieces.hpp): between two pieces the engine goes to whoever
    // asked for it meanwhile, so another scene's short line waits one piece, not this line.
    Capture capture;                                  // the whole line, samples from its start
    std::vector<std::int64_t> markSamples(marks.size(), -1);
    std::size_t recovered = 0, pieceStart = 0, nextMark = 0;
    for (const std::size_t pieceEnd : textPieceEnds(request.text)) {
      const bool lastPiece = pieceEnd == request.text.size();
      std::size_t markEnd = nextMark;
      while (markEnd < marks.size() && (lastPiece || marks[markEnd].characterOffset < pieceEnd)) ++markEnd;
      std::vector<int> markPositions;
      const std::string ssml = pieceSsml(request.text, pieceStart, pieceEnd, marks, nextMark, markEnd, markPositions);
      Capture piece;
      {
        std::lock_guard lock(e.turn);
        // Set for every piece: another caller may have changed them in between.
        if (!selectVoice(voice)) {
          result.error = "espeak-ng has no voice '" + voice +
                         "' (neither a voice name such as 'en-us' nor a language such as 'en-gb'; voices are listed by "
                         "`espeak-ng --voices`; data in '" + dataPath() + "')";
          return result;
        }
        espeak_SetParameter(espeakRATE, rate, 0);
        const espeak_ERROR status = espeak_Synth(ssml.c_str(), ssml.size() + 1, 0, POS_CHARACTER, 0,
                                                 espeakSSML | espeakCHARS_UTF8, nullptr, &piece);
        if (status != EE_OK) {
          result.error = "espeak-ng could not synthesize \"" + request.text.substr(0, 60) +
                         (request.text.size() > 60 ? "...\"" : "\"") + " with voice '" + voice + "' (error " +
                         std::to_string(status) + ")";
          return result;
        }
      }
      const auto offset = static_cast<std::int64_t>(capture.audio.size());
      const auto pieceEndSample = offset + static_cast<std::int64_t>(piece.audio.size());
      capture.audio.insert(capture.audio.end(), piece.audio.begin(), piece.audio.end());
      for (Capture::Raw& p : piece.phonemes) capture.phonemes.push_back({std::move(p.name), p.sample + offset});
      for (const auto& [name, sample] : piece.marks) {
        const std::size_t index = name.size() > 1 ? std::strtoul(name.c_str() + 1, nullptr, 10) : marks.size();
        if (index >= nextMark && index < markEnd && markSamples[index] < 0) markSamples[index] = sample + offset;
      }
      // espeak-ng 1.51 drops a mark that follows a full stop ("dog. <mark/>The"):
      // such a mark gets the start of the next word after it (where espeak-ng puts
      // the marks it does report), or the piece's end when no word follows.
      for (std::size_t i = nextMark; i < markEnd; ++i) {
        if (markSamples[i] >= 0) continue;
        ++recovered;
        markSamples[i] = pieceEndSample;
        for (const auto& [position, sample] : piece.words)
          if (position > markPositions[i - nextMark]) {
            markSamples[i] = sample + offset;
            break;
          }
      }
      pieceStart = pieceEnd;
      nextMark = markEnd;
    }

    u->audio = std::move(capture.audio);
    u->sampleRate = sampleRate;
    const auto audioSamples = static_cast<std::int64_t>(u->audio.size());
    const double duration = static_cast<double>(audioSamples) / sampleRate;

    // The engine's own defect, measured on the raw events before any repair.
    std::size_t backwards = 0;
    std::int64_t worstBack = 0, worstPast = 0, past = 0;
    for (std::size_t i = 0; i < capture.phonemes.size(); ++i) {
      const std::int64_t s = capture.phonemes[i].sample;
      if (i > 0 && s < capture.phonemes[i - 1].sample) {
        ++backwards;
        worstBack = std::max(worstBack, capture.phonemes[i - 1].sample - s);
      }
      if (s > audioSamples) {
        ++past;
        worstPast = std::max(worstPast, s - audioSamples);
      }
    }
    if (backwards > 0 || past > 0) {
      std::ostringstream note;
      note.precision(1);
      note << std::fixed << "espeak-ng defect at " << rate << " wpm" << (rate >= kSonicRate ? " (sonic speed-up)" : "")
           << ": " << backwards << " phoneme time(s) went backwards (by up to "
           << 1000.0 * static_cast<double>(worstBack) / sampleRate << " ms), " << past
           << " lay past the end of the audio (by up to " << 1000.0 * static_cast<double>(worstPast) / sampleRate
           << " ms); repaired keeping the spoken order";
      u->warnings.push_back(note.str());
    }

    std::vector<double> starts;
    starts.reserve(capture.phonemes.size());
    for (const auto& p : capture.phonemes) starts.push_back(static_cast<double>(p.sample) / sampleRate);
    if (backwards > 0) fitNonDecreasing(starts, duration);

    std::map<std::string, bool> warnedUnknown;
    u->phonemes.reserve(capture.phonemes.size());
    for (std::size_t i = 0; i < capture.phonemes.size(); ++i) {
      Phoneme p;
      p.name = capture.phonemes[i].name;
      p.sample = capture.phonemes[i].sample;
      p.start = starts[i];
      p.end = i + 1 < starts.size() ? starts[i + 1] : duration;
      const Classification c = classifyPhoneme(p.name, PhonemeAlphabet::Espeak);
      p.cls = c.cls;
      if (!c.known && !warnedUnknown[p.name]) {
        warnedUnknown[p.name] = true;
        u->warnings.push_back("espeak-ng phoneme '" + p.name + "' is not in the viseme table; shown as its nearest class");
      }
      u->phonemes.push_back(std::move(p));
    }

    for (std::size_t i = 0; i < marks.size(); ++i)
      u->marks.push_back({marks[i].id, static_cast<double>(markSamples[i]) / sampleRate});
    if (recovered > 0)
      u->warnings.push_back("espeak-ng reported no event for " + std::to_string(recovered) +
                            " mark(s) (1.51 drops marks that follow a full stop); timed at the next word's start");

    normalizeTiming(*u);
    result.utterance = std::move(u);
    {
      std::lock_guard lock(e.turn);
      // Another thread may have said the same meanwhile: keep the first, so repeats stay identical.
      for (const auto& [k, done] : e.recent)
        if (k == key) {
          result.utterance = done;
          return result;
        }
      e.recent.emplace_back(std::move(key), result.utterance);
      if (e.recent.size() > kRecentResults) e.recent.pop_front();
    }
    return result;
  }
};

}  // namespace

std::shared_ptr<SpeechBackend> makeEspeakBackend(std::string* whyNot) {
  if (whyNot) whyNot->clear();
  return std::make_shared<EspeakBackend>();
}

void useEspeak(SpeechService& service) { service.setSynthesizer(&makeEspeakBackend); }

}  // namespace marionette::speech
