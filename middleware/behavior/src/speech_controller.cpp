#include "marionette/behavior/speech_controller.hpp"

#include <algorithm>
#include <cmath>

#include "marionette/behavior/head_motion.hpp"
#include "marionette/speech/speech_service.hpp"

namespace marionette {

speech::SpeechRequest speechRequestOf(const BehaviorRequest& request, std::string& warning) {
  const SpeechParameters* p = request.as<SpeechParameters>();
  if (!p) return {};
  speech::SpeechRequest out;
  out.text = p->text;
  out.voice = p->voice;
  auto note = [&](const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; };
  if (p->wordsPerMinute != 0) {
    if (p->wordsPerMinute >= kMinWordsPerMinute && p->wordsPerMinute <= kMaxWordsPerMinute)
      out.wordsPerMinute = p->wordsPerMinute;
    else
      note("speech rate '" + std::to_string(p->wordsPerMinute) +
           "' is not a number of words per minute in [1, 10000]; the voice's default is used");
  }
  for (const speech::TextMark& m : p->marks) {
    if (m.characterOffset <= out.text.size())
      out.marks.push_back(m);
    else
      note("speech mark '" + m.id + "' lies past the end of the text (character " + std::to_string(m.characterOffset) +
           " of " + std::to_string(out.text.size()) + "); dropped");
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
