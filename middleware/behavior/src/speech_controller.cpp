#include "marionette/behavior/speech_controller.hpp"

#include <algorithm>
#include <cmath>
#include <charconv>

#include "marionette/behavior/head_motion.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

std::optional<int> parseWordsPerMinute(std::string_view text) noexcept {
  double wpm = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), wpm);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(wpm) || wpm < 1.0 || wpm > 10000.0)
    return std::nullopt;
  return static_cast<int>(std::lround(wpm));
}

speech::SpeechRequest speechRequestOf(const BehaviorRequest& request, std::string& warning) {
  speech::SpeechRequest out;
  out.text = std::string(request.parameter("text"));
  out.voice = std::string(request.parameter("voice"));
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (const std::string_view rate = request.parameter("rate"); !rate.empty()) {
    if (const auto wpm = parseWordsPerMinute(rate)) out.wordsPerMinute = *wpm;
    else note("speech rate '" + std::string(rate) + "' is not a number of words per minute in [1, 10000]; the voice's default is used");
  }
  // "OFFSET:ID OFFSET:ID ...": ids may hold ':' themselves, offsets never do.
  const std::string_view marks = request.parameter("markOffsets");
  std::size_t i = 0;
  while (i < marks.size()) {
    while (i < marks.size() && marks[i] == ' ') ++i;
    std::size_t j = i;
    while (j < marks.size() && marks[j] != ' ') ++j;
    if (j == i) break;
    const std::string item(marks.substr(i, j - i));
    const std::size_t colon = item.find(':');
    std::size_t offset = 0;
    bool ok = colon != std::string::npos && colon > 0 && colon + 1 < item.size() && colon <= 9;
    for (std::size_t k = 0; ok && k < colon; ++k) {
      ok = item[k] >= '0' && item[k] <= '9';
      offset = offset * 10 + static_cast<std::size_t>(item[k] - '0');
    }
    if (ok && offset <= out.text.size())
      out.marks.push_back({item.substr(colon + 1), offset});
    else if (ok)
      note("speech mark '" + item.substr(colon + 1) + "' lies past the end of the text (character " +
           std::to_string(offset) + " of " + std::to_string(out.text.size()) + "); dropped");
    else
      note("speech mark '" + item + "' in the \"markOffsets\" parameter is not CHARACTER:ID; dropped");
    i = j;
  }
  return out;
}

std::string speechFaceNote(const Rig& rig) {
  const RigJoints& j = rig.joints();
  if (j.visemes.empty() && j.jaw < 0)
    return "the character has no viseme morphs and no jaw joint: its audio and viseme events play, its face does not move";
  return {};
}

void applySpeech(const SpeechState& state, float weight, double localTime, const Rig& rig, std::span<float> channels,
                 std::span<float> morphWeights, std::span<Transform> pose) noexcept {
  if (!state.line || channels.size() < static_cast<std::size_t>(speech::kLipChannelCount)) return;
  state.line->curves.evaluate(localTime, channels);
  const RigJoints& j = rig.joints();
  for (const RigJoints::LipMorph& m : j.visemes) {
    if (m.morph < 0 || static_cast<std::size_t>(m.morph) >= morphWeights.size()) continue;
    float& w = morphWeights[static_cast<std::size_t>(m.morph)];
    w = std::clamp(w + weight * m.amount * channels[static_cast<std::size_t>(m.channel)], 0.0f, 1.0f);
  }
  if (j.jaw >= 0 && !j.jawOpenByMorph) {
    const float open = std::clamp(channels[speech::kJawOpenChannel], 0.0f, 1.0f) * weight;
    if (open > 0.0f) rotateInModelFrame(rig.skeleton(), pose, j.jaw, glm::angleAxis(open * kMaxJawOpenRadians, j.leftAxis));
  }
}

}  // namespace marionette
