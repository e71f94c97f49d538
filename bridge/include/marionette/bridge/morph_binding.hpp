// MorphBinding: copies a character's morph weights (TransformBuffer::morphWeights,
// in Asset::morphTargets order) into an engine's morph slots, matched by name once
// at bind time. Slots whose name the character lacks are reported and left
// untouched by copy(): the engine may drive them itself (blinks, correctives).
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "marionette/scene/transform_buffer.hpp"

namespace marionette::bridge {

struct MorphBindReport {
  std::vector<std::string> unmatchedSlots;  // engine slots no character morph feeds (left untouched)
  std::vector<std::string> unusedMorphs;    // character morphs no engine slot receives
  // One line per problem, naming the morphs; empty when everything is bound.
  [[nodiscard]] std::string format() const;
};

class MorphBinding {
 public:
  MorphBinding() = default;
  // characterMorphs: the character's morph names (Asset::morphTargets); engineSlots[i]:
  // the name of the engine's morph slot i.
  MorphBinding(std::span<const std::string> characterMorphs, std::span<const std::string> engineSlots);

  [[nodiscard]] std::size_t slotCount() const noexcept { return slotToMorph_.size(); }
  [[nodiscard]] int morphForSlot(std::size_t slot) const noexcept { return slotToMorph_[slot]; }
  [[nodiscard]] const MorphBindReport& report() const noexcept { return report_; }

  // Writes the bound slots of `out` (at least slotCount() floats). Returns false,
  // writing nothing, when `out` is too small or the buffer's morph count is not the
  // bound character's. Per frame: no allocation, no exceptions.
  bool copy(const TransformBuffer& buffer, std::span<float> out) const noexcept;

 private:
  std::vector<int> slotToMorph_;  // -1 = unmatched
  std::size_t morphCount_ = 0;
  MorphBindReport report_;
};

}  // namespace marionette::bridge
