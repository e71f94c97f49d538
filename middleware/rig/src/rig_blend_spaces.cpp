// The rig's blend spaces: made from the profile's definitions with the rig's clips
// and the profile's feet, or added from code (rig.hpp).
#include <algorithm>
#include <cmath>

#include "marionette/rig/rig.hpp"

namespace marionette {

namespace {

// Hip to ankle in the rest pose, through the knee (model units); 0 without a leg.
float restLegLength(const Skeleton& s, const RigJoints::LimbJoints& leg) {
  const int n = static_cast<int>(s.jointCount());
  if (leg.upper < 0 || leg.lower < 0 || leg.end < 0 || std::max({leg.upper, leg.lower, leg.end}) >= n) return 0.0f;
  const std::vector<glm::mat4> rest = s.restModelMatrices();
  const auto at = [&](int j) { return glm::vec3(rest[static_cast<std::size_t>(j)][3]); };
  return glm::distance(at(leg.upper), at(leg.lower)) + glm::distance(at(leg.lower), at(leg.end));
}

}  // namespace

std::shared_ptr<const BlendSpace> Rig::findBlendSpace(std::string_view name) const noexcept {
  for (const auto& s : blendSpaces_)
    if (s->name() == name) return s;
  return nullptr;
}

std::shared_ptr<const BlendSpace> Rig::makeBlendSpace(const BlendSpaceDefinition& definition, std::string& error) const {
  if (error = validateBlendSpaceDefinition(definition); !error.empty()) return nullptr;
  std::vector<BlendSpaceSample> samples;
  for (std::size_t i = 0; i < definition.samples.size(); ++i) {
    const BlendSpaceSampleDefinition& d = definition.samples[i];
    auto clip = findClip(d.clip);
    if (!clip) {
      std::string names;
      for (std::size_t k = 0; k < clips_.size() && k < 12; ++k) names += (k ? ", '" : "'") + clips_[k]->clip.name + "'";
      if (clips_.size() > 12) names += ", ...";
      error = "blend space '" + definition.name + "': sample " + std::to_string(i) + " names the clip '" + d.clip +
              "', which the rig has not (it has " + (names.empty() ? std::string("none") : names) + ")";
      return nullptr;
    }
    samples.push_back({std::move(clip), d.x, d.y});
  }
  BlendSpaceFeet feet;
  feet.left = joints_.leftLeg.end;
  feet.right = joints_.rightLeg.end;
  const float leg = restLegLength(skeleton_, joints_.leftLeg.end >= 0 ? joints_.leftLeg : joints_.rightLeg);
  feet.contacts = footContactOptionsForLeg(leg);
  return BlendSpace::make(definition.name, definition.dimensions, std::move(samples), skeleton_, feet,
                          definition.phaseAligned, error);
}

bool Rig::addBlendSpace(std::shared_ptr<const BlendSpace> space) {
  if (!space) return false;
  for (auto& s : blendSpaces_)
    if (s->name() == space->name()) {
      s = std::move(space);
      return true;
    }
  blendSpaces_.push_back(std::move(space));
  return true;
}

void Rig::makeProfileBlendSpaces() {
  // Spaces from code stay; the profile's are made again for the new profile's clips and feet.
  std::vector<std::shared_ptr<const BlendSpace>> made;
  for (const BlendSpaceDefinition& d : profile_.blendSpaces) {
    std::string error;
    if (auto space = makeBlendSpace(d, error)) made.push_back(std::move(space));
    else profile_.notes.push_back("blendSpaces: " + error + "; left out");
  }
  for (auto& space : made) addBlendSpace(std::move(space));
}

}  // namespace marionette
