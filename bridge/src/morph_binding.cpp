#include "marionette/bridge/morph_binding.hpp"

#include <algorithm>

namespace marionette::bridge {

std::string MorphBindReport::format() const {
  std::string out;
  for (const std::string& slot : unmatchedSlots)
    out += "morphs: engine slot '" + slot + "' has no character morph of that name; left untouched\n";
  for (const std::string& morph : unusedMorphs)
    out += "morphs: character morph '" + morph + "' feeds no engine slot\n";
  return out;
}

MorphBinding::MorphBinding(std::span<const std::string> characterMorphs, std::span<const std::string> engineSlots)
    : morphCount_(characterMorphs.size()) {
  std::vector<char> used(morphCount_, 0);
  slotToMorph_.reserve(engineSlots.size());
  for (const std::string& slot : engineSlots) {
    const auto it = std::find(characterMorphs.begin(), characterMorphs.end(), slot);
    const int m = it == characterMorphs.end() ? -1 : static_cast<int>(it - characterMorphs.begin());
    if (m < 0) report_.unmatchedSlots.push_back(slot);
    else used[static_cast<std::size_t>(m)] = 1;
    slotToMorph_.push_back(m);
  }
  for (std::size_t m = 0; m < morphCount_; ++m)
    if (!used[m]) report_.unusedMorphs.push_back(characterMorphs[m]);
}

bool MorphBinding::copy(const TransformBuffer& buffer, std::span<float> out) const noexcept {
  if (out.size() < slotToMorph_.size() || buffer.morphCount() != morphCount_) return false;
  const std::span<const float> weights = buffer.morphWeights();
  for (std::size_t slot = 0; slot < slotToMorph_.size(); ++slot)
    if (const int m = slotToMorph_[slot]; m >= 0) out[slot] = weights[static_cast<std::size_t>(m)];
  return true;
}

}  // namespace marionette::bridge
