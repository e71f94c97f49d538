#include "marionette/bridge/palette_binding.hpp"

#include <cstring>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace marionette::bridge {

namespace {

// The character joint the maps give for engine bone `slot`, or -1; `canonical`
// names the canonical joint it went through.
int throughMaps(const BindMaps& maps, int slot, std::string& canonical) {
  for (int b = 0; b < retarget::kBoneCount; ++b) {
    const auto bone = static_cast<retarget::Bone>(b);
    if (maps.engine.joint(bone) != slot) continue;
    canonical = retarget::boneName(bone);
    return maps.character.joint(bone);
  }
  for (int c = 0; c < retarget::kChainCount; ++c) {
    const auto chain = static_cast<retarget::Chain>(c);
    const std::vector<int>& engineChain = maps.engine.chain(chain);
    for (std::size_t k = 0; k < engineChain.size(); ++k) {
      if (engineChain[k] != slot) continue;
      canonical = std::string(retarget::chainName(chain)) + "[" + std::to_string(k) + "]";
      // Joint k to joint k: a shorter chain on the character leaves the rest unmatched.
      const std::vector<int>& own = maps.character.chain(chain);
      return k < own.size() ? own[k] : -1;
    }
  }
  return -1;
}

void writeIdentity(float* dst, PaletteLayout layout) noexcept {
  const std::size_t per = floatsPerBone(layout);
  std::memset(dst, 0, per * sizeof(float));
  if (layout == PaletteLayout::Mat3x4RowMajor) dst[0] = dst[5] = dst[10] = 1.0f;
  else dst[0] = dst[5] = dst[10] = dst[15] = 1.0f;
}

}  // namespace

std::string BindReport::format() const {
  std::string out;
  for (const std::string& bone : unmatchedBones)
    out += "palette: engine bone '" + bone +
           "' has no character joint of that name nor through the joint maps; its slot gets identity\n";
  for (const std::string& joint : unusedJoints)
    out += "palette: character joint '" + joint + "' drives no engine bone\n";
  return out;
}

PaletteBinding::PaletteBinding(const Skeleton& character, std::span<const std::string> engineBones,
                               const BindMaps* maps)
    : jointCount_(character.jointCount()) {
  slotToJoint_.reserve(engineBones.size());
  for (std::size_t slot = 0; slot < engineBones.size(); ++slot) {
    const std::string& name = engineBones[slot];
    int j = character.findJoint(name);
    if (j >= 0) {
      report_.byName.push_back(name);
    } else if (maps) {
      std::string canonical;
      j = throughMaps(*maps, static_cast<int>(slot), canonical);
      if (j >= 0 && static_cast<std::size_t>(j) < jointCount_)
        report_.throughMaps.push_back({name, canonical, character.names[static_cast<std::size_t>(j)]});
      else
        j = -1;
    }
    if (j < 0) report_.unmatchedBones.push_back(name);
    slotToJoint_.push_back(j);
  }
  std::vector<char> used(jointCount_, 0);
  for (int j : slotToJoint_)
    if (j >= 0) used[static_cast<std::size_t>(j)] = 1;
  for (std::size_t j = 0; j < jointCount_; ++j)
    if (!used[j]) report_.unusedJoints.push_back(character.names[j]);
  buildRuns();
}

PaletteBinding::PaletteBinding(const Skeleton& character) : jointCount_(character.jointCount()) {
  slotToJoint_.resize(jointCount_);
  for (std::size_t i = 0; i < slotToJoint_.size(); ++i) slotToJoint_[i] = static_cast<int>(i);
  report_.byName = character.names;
  buildRuns();
}

void PaletteBinding::buildRuns() {
  runs_.clear();
  for (std::size_t slot = 0; slot < slotToJoint_.size(); ++slot) {
    const int j = slotToJoint_[slot];
    if (!runs_.empty()) {
      Run& last = runs_.back();
      const bool extends = j < 0 ? last.joint < 0
                                 : last.joint >= 0 && j == last.joint + static_cast<int>(last.count);
      if (extends) {
        ++last.count;
        continue;
      }
    }
    runs_.push_back({j, slot, 1});
  }
}

bool PaletteBinding::copy(const TransformBuffer& buffer, std::span<float> out, PaletteFormat format) const noexcept {
  const PaletteLayout layout = format.layout;
  const std::size_t per = floatsPerBone(layout);
  if (out.size() < floatCount(layout) || buffer.jointCount() != jointCount_) return false;
  // A buffer that keeps no skinning matrices makes them here, a few joints at a time.
  const bool make = format.inverseBind && !buffer.skinningStored();
  if (make && !buffer.skinningMatrices(0, {})) return false;  // no inverse binds to make them with
  const std::span<const glm::mat4> source = format.inverseBind ? buffer.skinningMatrices() : buffer.modelMatrices();
  constexpr std::size_t kMade = 16;
  glm::mat4 made[kMade];
  for (const Run& whole : runs_) {
    if (whole.joint < 0) {
      float* dst = out.data() + whole.slot * per;
      for (std::size_t k = 0; k < whole.count; ++k) writeIdentity(dst + k * per, layout);
      continue;
    }
    for (std::size_t done = 0; done < whole.count;) {
      const Run run{whole.joint + static_cast<int>(done), whole.slot + done,
                    make ? std::min(kMade, whole.count - done) : whole.count};
      done += run.count;
      float* dst = out.data() + run.slot * per;
      const glm::mat4* m = made;  // made here, or read from the buffer (never an offset into an empty span)
      if (make) {
        if (!buffer.skinningMatrices(static_cast<std::size_t>(run.joint), {made, run.count})) return false;
      } else {
        m = source.data() + run.joint;
      }
      copyRun(m, run.count, layout, dst);
    }
  }
  return true;
}

void PaletteBinding::copyRun(const glm::mat4* m, std::size_t count, PaletteLayout layout, float* dst) noexcept {
  if (layout == PaletteLayout::Mat4ColumnMajor) {  // glm's own layout: one block per run
    std::memcpy(dst, &m[0][0][0], count * 16 * sizeof(float));
    return;
  }
  // Transposed: dst[row * 4 + col] = m[col][row], for 4 rows (4x4) or 3 (3x4).
  const std::size_t per = floatsPerBone(layout);
  const int rows = layout == PaletteLayout::Mat4RowMajor ? 4 : 3;
  for (std::size_t k = 0; k < count; ++k, dst += per) {
    const float* a = &m[k][0][0];
#if defined(__SSE2__)  // baseline x86-64: four loads, an in-register transpose, three or four stores
    __m128 c0 = _mm_loadu_ps(a), c1 = _mm_loadu_ps(a + 4), c2 = _mm_loadu_ps(a + 8), c3 = _mm_loadu_ps(a + 12);
    _MM_TRANSPOSE4_PS(c0, c1, c2, c3);
    _mm_storeu_ps(dst, c0);
    _mm_storeu_ps(dst + 4, c1);
    _mm_storeu_ps(dst + 8, c2);
    if (rows == 4) _mm_storeu_ps(dst + 12, c3);
#else
    for (int row = 0; row < rows; ++row)
      for (int col = 0; col < 4; ++col) dst[row * 4 + col] = a[col * 4 + row];
#endif
  }
}

}  // namespace marionette::bridge
