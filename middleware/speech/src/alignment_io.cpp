// Phoneme alignments (phone lists, HTS labels, Rhubarb TSV) and WAV files.
//
// Alignment policy: a line that cannot be read (a missing column, a word where a
// number belongs, a label without a phone) fails the whole file with
// "source:line: expected ..., found '...'", because guessing what a broken line
// meant would move every lip shape after it. Times that are readable but wrong
// are repaired with a warning naming the line: non-finite times take their
// neighbour's, negative times become 0, an end before its start is swapped,
// rows out of order are sorted, and an overlap ends the earlier phoneme where
// the next begins. A file with no rows is an error.
//
// Rhubarb: each shape lasts until the next one's time. Rhubarb closes its output
// with an X at the end of the recording, so the last row marks that end: it is
// kept with zero length (start == end) rather than given an invented duration.
#include "marionette/core/float_chars.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <system_error>

#include "marionette/speech/alignment_io.hpp"
#include "wav_format.hpp"

namespace marionette::speech {
namespace {

// ---------------------------------------------------------------- text helpers

constexpr std::size_t kMaxWarnings = 100;  // a broken file should not flood the log
constexpr std::uintmax_t kMaxAlignmentBytes = 64u << 20;

// The text as it may be shown in a message: printable ASCII, at most 40 chars.
std::string shown(std::string_view text) {
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (text.size() > 40) out += "...";
  return out + "'";
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> splitFields(std::string_view line, bool csv) {
  std::vector<std::string_view> fields;
  if (csv) {
    std::size_t from = 0;
    while (true) {
      const std::size_t comma = line.find(',', from);
      fields.push_back(trim(line.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from)));
      if (comma == std::string_view::npos) break;
      from = comma + 1;
    }
    return fields;
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// The whole field as a number, or nothing. Non-finite values ("nan", "inf") parse
// and are repaired later; words and trailing junk do not.
std::optional<double> parseNumber(std::string_view field) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = floatFromChars(field.data(), field.data() + field.size(), value);
  if (ec == std::errc::result_out_of_range) {
    return field.front() == '-' ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  }
  if (ec != std::errc() || end != field.data() + field.size()) return std::nullopt;
  return value;
}

bool looksLikeInteger(std::string_view field) {
  if (!field.empty() && (field.front() == '-' || field.front() == '+')) field.remove_prefix(1);
  if (field.empty()) return false;
  return std::all_of(field.begin(), field.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool isRhubarbShape(std::string_view field) {
  if (field.size() != 1) return false;
  const char c = static_cast<char>(field[0] & ~0x20);  // upper case
  return (c >= 'A' && c <= 'H') || c == 'X';
}

// One meaningful line of the file.
struct TextLine {
  std::size_t number = 0;
  std::string_view text;
};

std::vector<TextLine> meaningfulLines(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark
  std::vector<TextLine> lines;
  std::size_t number = 0, from = 0;
  while (from <= text.size()) {
    const std::size_t nl = text.find('\n', from);
    const std::string_view raw = text.substr(from, nl == std::string_view::npos ? std::string_view::npos : nl - from);
    ++number;
    const std::string_view line = trim(raw);
    if (!line.empty() && line.front() != '#') lines.push_back({number, line});
    if (nl == std::string_view::npos) break;
    from = nl + 1;
  }
  return lines;
}

// ---------------------------------------------------------------- rows

struct Row {
  double start = 0.0, end = 0.0;
  std::string name;
  std::size_t line = 0;
};

struct ParseState {
  std::string source;
  std::vector<std::string> warnings;
  std::size_t droppedWarnings = 0;
  std::string error;

  void warn(std::size_t line, const std::string& what) {
    if (warnings.size() >= kMaxWarnings) {
      ++droppedWarnings;
      return;
    }
    warnings.push_back(line > 0 ? source + ":" + std::to_string(line) + ": " + what : source + ": " + what);
  }
  void fail(std::size_t line, const std::string& expected, std::string_view found) {
    if (error.empty())
      error = source + ":" + std::to_string(line) + ": expected " + expected + ", found " + shown(found);
  }
};

AlignmentFormat detectFormat(const std::vector<TextLine>& lines, AlignmentFormat hint) {
  if (hint != AlignmentFormat::Auto) return hint;
  if (lines.empty()) return AlignmentFormat::PhoneList;
  // The first line that starts with a number decides (a CSV header does not).
  for (const TextLine& line : lines) {
    if (line.text.find(',') != std::string_view::npos) return AlignmentFormat::PhoneList;
    const auto fields = splitFields(line.text, false);
    if (!parseNumber(fields[0])) continue;
    if (fields.size() == 2 && isRhubarbShape(fields[1])) return AlignmentFormat::Rhubarb;
    if (fields.size() >= 3 && looksLikeInteger(fields[0]) && looksLikeInteger(fields[1])) {
      const std::string_view label = fields[2];
      const std::size_t dash = label.find('-');
      const bool fullContext = dash != std::string_view::npos && label.find('+', dash) != std::string_view::npos;
      const auto end = parseNumber(fields[1]);
      if (fullContext || (end && *end > 1000.0)) return AlignmentFormat::HtsLabel;  // 100 ns units
    }
    return AlignmentFormat::PhoneList;
  }
  return AlignmentFormat::PhoneList;
}

bool readTime(ParseState& state, const TextLine& line, std::string_view field, const char* what, double& out) {
  const auto value = parseNumber(field);
  if (!value) {
    state.fail(line.number, what, field);
    return false;
  }
  out = *value;
  return true;
}

void readPhoneList(ParseState& state, const std::vector<TextLine>& lines, std::vector<Row>& rows) {
  bool csv = false;
  for (std::size_t i = 0; i < lines.size() && state.error.empty(); ++i) {
    const TextLine& line = lines[i];
    if (i == 0) csv = line.text.find(',') != std::string_view::npos;
    const auto fields = splitFields(line.text, csv);
    // A header ("start,end,phoneme"): a first line whose time columns are not numbers.
    if (i == 0 && fields.size() >= 3 && !parseNumber(fields[0]) && !parseNumber(fields[1])) continue;
    if (fields.size() < 3) {
      state.fail(line.number, "3 columns (start end phone)", line.text);
      return;
    }
    Row row;
    row.line = line.number;
    if (!readTime(state, line, fields[0], "a start time in seconds", row.start) ||
        !readTime(state, line, fields[1], "an end time in seconds", row.end))
      return;
    if (fields[2].empty()) {
      state.fail(line.number, "a phone name in column 3", line.text);
      return;
    }
    if (fields.size() > 3) state.warn(line.number, "columns after the third ignored");
    row.name = std::string(fields[2]);
    rows.push_back(std::move(row));
  }
}

// The phone of an HTS label: between '-' and '+' in a full-context label, the
// whole label in a monophone one. State-level labels end in "[n]".
std::string_view htsPhone(std::string_view label) {
  if (label.size() > 2 && label.back() == ']') {
    const std::size_t open = label.rfind('[');
    if (open != std::string_view::npos) label = label.substr(0, open);
  }
  const std::size_t dash = label.find('-');
  if (dash == std::string_view::npos) return label;
  const std::size_t plus = label.find('+', dash + 1);
  return label.substr(dash + 1, plus == std::string_view::npos ? std::string_view::npos : plus - dash - 1);
}

void readHtsLabel(ParseState& state, const std::vector<TextLine>& lines, std::vector<Row>& rows) {
  std::string_view previousLabel;
  for (const TextLine& line : lines) {
    const auto fields = splitFields(line.text, false);
    if (fields.size() < 3) {
      state.fail(line.number, "3 columns (start end label, times in 100 ns)", line.text);
      return;
    }
    Row row;
    row.line = line.number;
    if (!readTime(state, line, fields[0], "a start time in 100 ns units", row.start) ||
        !readTime(state, line, fields[1], "an end time in 100 ns units", row.end))
      return;
    row.start *= 1e-7;
    row.end *= 1e-7;
    const std::string_view phone = htsPhone(fields[2]);
    if (phone.empty()) {
      state.fail(line.number, "a phone between '-' and '+' in the label", fields[2]);
      return;
    }
    // The states of one phone (state-level labels) become one row.
    std::string_view label = fields[2];
    if (label.back() == ']' && label.rfind('[') != std::string_view::npos) label = label.substr(0, label.rfind('['));
    if (!rows.empty() && label == previousLabel && fields[2] != label && std::abs(rows.back().end - row.start) < 1e-9) {
      rows.back().end = row.end;
      continue;
    }
    previousLabel = label;
    row.name = std::string(phone);
    rows.push_back(std::move(row));
  }
}

void readRhubarb(ParseState& state, const std::vector<TextLine>& lines, std::vector<Row>& rows) {
  for (const TextLine& line : lines) {
    const auto fields = splitFields(line.text, false);
    if (fields.size() < 2) {
      state.fail(line.number, "2 columns (time shape)", line.text);
      return;
    }
    Row row;
    row.line = line.number;
    if (!readTime(state, line, fields[0], "a time in seconds", row.start)) return;
    if (!isRhubarbShape(fields[1])) {
      state.fail(line.number, "a mouth shape A-H or X", fields[1]);
      return;
    }
    row.end = row.start;  // set from the next row below
    row.name = std::string(1, static_cast<char>(fields[1][0] & ~0x20));
    rows.push_back(std::move(row));
  }
}

// Makes the times finite, non-negative, ordered and non-overlapping.
void repairTimes(ParseState& state, std::vector<Row>& rows, bool untilNext) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    Row& r = rows[i];
    if (!std::isfinite(r.start)) {
      r.start = i > 0 ? rows[i - 1].end : 0.0;
      state.warn(r.line, "start time is not a finite number; the previous end is used");
    }
    if (!untilNext && !std::isfinite(r.end)) {
      const double next = i + 1 < rows.size() && std::isfinite(rows[i + 1].start) ? rows[i + 1].start : r.start;
      r.end = next;
      state.warn(r.line, "end time is not a finite number; the next start is used");
    }
    if (r.start < 0.0) {
      state.warn(r.line, "negative start time set to 0");
      r.start = 0.0;
    }
    if (!untilNext && r.end < 0.0) {
      state.warn(r.line, "negative end time set to 0");
      r.end = 0.0;
    }
    if (!untilNext && r.end < r.start) {
      state.warn(r.line, "end time before start time; the two are swapped");
      std::swap(r.start, r.end);
    }
  }
  if (!std::is_sorted(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.start < b.start; })) {
    state.warn(0, "rows are not in time order; sorted by start time");
    std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.start < b.start; });
  }
  if (untilNext) {
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) rows[i].end = rows[i + 1].start;
    if (!rows.empty()) rows.back().end = rows.back().start;
    return;
  }
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    if (rows[i].end > rows[i + 1].start) {
      if (rows[i].end > rows[i + 1].start + 1e-9)  // not for rounding noise
        state.warn(rows[i + 1].line, "starts before the previous phoneme ends; the previous one is cut short");
      rows[i].end = rows[i + 1].start;
    }
    rows[i].end = std::max(rows[i].end, rows[i].start);
  }
}

// Which alphabet the names are written in: the one that knows more of them
// (ARPAbet on a tie, the common case for recorded-line aligners).
PhonemeAlphabet detectAlphabet(const std::vector<Row>& rows) {
  std::size_t arpabet = 0, espeak = 0;
  for (const Row& r : rows) {
    arpabet += classifyPhoneme(r.name, PhonemeAlphabet::Arpabet).known ? 1 : 0;
    espeak += classifyPhoneme(r.name, PhonemeAlphabet::Espeak).known ? 1 : 0;
  }
  return espeak > arpabet ? PhonemeAlphabet::Espeak : PhonemeAlphabet::Arpabet;
}

}  // namespace

Alignment parseAlignment(std::string_view text, std::string_view sourceName, AlignmentFormat format) {
  Alignment out;
  ParseState state;
  state.source = sourceName.empty() ? std::string("<text>") : std::string(sourceName);
  const std::vector<TextLine> lines = meaningfulLines(text);
  if (lines.empty()) {
    out.error = state.source + ": no alignment rows (the file is empty or holds only comments)";
    return out;
  }
  const AlignmentFormat chosen = detectFormat(lines, format);
  std::vector<Row> rows;
  switch (chosen) {
    case AlignmentFormat::HtsLabel: readHtsLabel(state, lines, rows); break;
    case AlignmentFormat::Rhubarb: readRhubarb(state, lines, rows); break;
    default: readPhoneList(state, lines, rows); break;
  }
  if (state.error.empty() && rows.empty())
    state.error = state.source + ": no alignment rows (only a header was found)";
  if (!state.error.empty()) {
    out.error = state.error;
    return out;
  }
  repairTimes(state, rows, chosen == AlignmentFormat::Rhubarb);
  out.alphabet = chosen == AlignmentFormat::Rhubarb ? PhonemeAlphabet::Rhubarb : detectAlphabet(rows);
  out.phonemes.reserve(rows.size());
  for (Row& r : rows) {
    const Classification c = classifyPhoneme(r.name, out.alphabet);
    if (!c.known) state.warn(r.line, "unknown phoneme " + shown(r.name) + "; shown as " +
                                         std::string(visemeName(c.cls.viseme)));
    Phoneme p;
    p.start = r.start;
    p.end = r.end;
    p.name = std::move(r.name);
    p.cls = c.cls;
    out.phonemes.push_back(std::move(p));
  }
  if (state.droppedWarnings > 0)
    state.warnings.push_back(state.source + ": " + std::to_string(state.droppedWarnings) + " more warnings not shown");
  out.warnings = std::move(state.warnings);
  return out;
}

Alignment readAlignment(const std::filesystem::path& file, AlignmentFormat format) {
  return readAlignment(FileReader{}, file, format);
}

Alignment readAlignment(const FileReader& files, const std::filesystem::path& file, AlignmentFormat format) {
  Alignment out;
  std::string text, why;
  if (!readWholeFile(files, file.generic_string(), kMaxAlignmentBytes, text, why)) {
    out.error = file.string() + ": cannot read the alignment (" + why + ")";
    return out;
  }
  if (format == AlignmentFormat::Auto) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    // .lab may hold seconds too (Audacity, wavesurfer); only integer times make it HTS.
    if (ext == ".tsv") {
      const auto lines = meaningfulLines(text);
      if (!lines.empty()) {
        const auto fields = splitFields(lines.front().text, false);
        if (fields.size() == 2) format = AlignmentFormat::Rhubarb;
      }
    } else if (ext == ".lab") {
      const auto lines = meaningfulLines(text);
      if (!lines.empty()) {
        const auto fields = splitFields(lines.front().text, false);
        if (fields.size() >= 3 && looksLikeInteger(fields[0]) && looksLikeInteger(fields[1]))
          format = AlignmentFormat::HtsLabel;
      }
    }
  }
  return parseAlignment(text, file.string(), format);
}

// ---------------------------------------------------------------- WAV

namespace {

constexpr std::uintmax_t kMaxWavBytes = 1u << 30;
constexpr std::uint16_t kFormatPcm = 1;

std::int16_t toInt16(double v) {
  const double r = std::round(v);
  return static_cast<std::int16_t>(std::clamp(r, -32768.0, 32767.0));
}

}  // namespace

std::string readWav(const std::filesystem::path& file, WavAudio& out) { return readWav(FileReader{}, file, out); }

std::string readWav(const FileReader& files, const std::filesystem::path& file, WavAudio& out) {
  out = {};
  const std::string name = file.string();
  std::string text, unread;
  if (!readWholeFile(files, file.generic_string(), kMaxWavBytes, text, unread))
    return name + ": cannot read the WAV file (" + unread + ")";
  const std::span<const unsigned char> bytes(reinterpret_cast<const unsigned char*>(text.data()), text.size());
  detail::WavLayout wav;
  if (std::string why = detail::parseWavLayout(bytes, wav); !why.empty()) return name + ": " + why;
  const detail::WavFormat& format = wav.format;
  const std::size_t bytesPerSample = format.bits / 8u;
  out.sampleRate = static_cast<int>(format.sampleRate);
  out.samples.resize(wav.frames);
  for (std::size_t i = 0; i < wav.frames; ++i) {
    const unsigned char* frame = wav.data + i * format.blockAlign;
    if (format.channels == 1 && format.tag == kFormatPcm && format.bits == 16) {
      out.samples[i] = static_cast<std::int16_t>(frame[0] | (frame[1] << 8));
      continue;
    }
    double sum = 0.0;  // mixed down, scaled to 16 bits
    for (std::size_t c = 0; c < format.channels; ++c) sum += detail::wavSample(frame + c * bytesPerSample, format) * 32768.0;
    out.samples[i] = toInt16(sum / format.channels);
  }
  return {};
}

std::string writeWav(const std::filesystem::path& file, std::span<const std::int16_t> samples, int sampleRate) {
  const std::string name = file.string();
  if (sampleRate <= 0 || sampleRate > 1'000'000)
    return name + ": sample rate " + std::to_string(sampleRate) + " Hz (expected 1 to 1000000)";
  const std::uint64_t dataBytes = static_cast<std::uint64_t>(samples.size()) * 2u;
  if (dataBytes > 0xFFFFFFFFull - 36u) return name + ": too many samples for a WAV file";
  std::vector<unsigned char> bytes;
  bytes.reserve(44 + static_cast<std::size_t>(dataBytes));
  auto put = [&](std::uint32_t v, int n) {
    for (int i = 0; i < n; ++i) bytes.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  auto tag = [&](const char* t) { bytes.insert(bytes.end(), t, t + 4); };
  tag("RIFF");
  put(static_cast<std::uint32_t>(36 + dataBytes), 4);
  tag("WAVE");
  tag("fmt ");
  put(16, 4);
  put(kFormatPcm, 2);
  put(1, 2);  // mono
  put(static_cast<std::uint32_t>(sampleRate), 4);
  put(static_cast<std::uint32_t>(sampleRate) * 2u, 4);  // byte rate
  put(2, 2);                                            // block align
  put(16, 2);
  tag("data");
  put(static_cast<std::uint32_t>(dataBytes), 4);
  for (std::int16_t s : samples) put(static_cast<std::uint16_t>(s), 2);
  std::ofstream outFile(file, std::ios::binary | std::ios::trunc);
  if (!outFile) return name + ": cannot open for writing";
  outFile.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  outFile.close();
  if (!outFile) return name + ": write failed";
  return {};
}

}  // namespace marionette::speech
