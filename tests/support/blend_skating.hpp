// Foot skating of a blend space as a user would measure it: a character plays the
// space at a parameter point, and each foot's world place is read from its transform
// buffer every frame. A foot is planted on a frame when its clips' own contact analysis says so: the weights of the clips whose foot is in
// contact at the time the space samples them sum to 1/2 or more (detectFootContacts,
// BlendSpace::Sample::contacts; the same for a space with and without phase alignment,
// each at its own sampling times). Skating is a planted foot's horizontal speed over the
// ground (no gtest here: the tests and tools share it).
//
// The ground: with root motion the character travels by the clips' own root motion
// (a planted foot should then stand still in the world); clips in place travel at
// the blend's ground speed, the clips' ground speeds weighted by cycle
// (sum w_i v_i d_i / sum w_i d_i: the stride of the blended cycle over its duration).
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "marionette/behavior/locomotion.hpp"
#include "marionette/scene/character.hpp"

namespace marionette::test {

struct BlendSkating {
  double travelSpeed = 0.0;  // model units / s
  double meanSpeed = 0.0;    // model units / s, over planted frames of both feet
  double p95Speed = 0.0, worstSpeed = 0.0;
  double slidePerContact = 0.0;  // model units a planted foot moves, per contact (mean)
  int plantedFrames = 0, contacts = 0;
  [[nodiscard]] double ratio() const { return travelSpeed > 0.0 ? meanSpeed / travelSpeed : 0.0; }
};

// `groundSpeeds`: per sample of the space, its clip's ground speed (model units / s), used
// for clips in place (rootMotion false). `cycles` measured after one cycle of warm-up.
inline BlendSkating measureBlendSkating(const std::shared_ptr<const Rig>& rig, const std::shared_ptr<const BlendSpace>& space,
                                        float x, float y, bool rootMotion, const std::vector<float>& groundSpeeds,
                                        int cycles = 4, double dt = 1.0 / 120.0) {
  Character c("skater", rig);
  PlayOptions o;
  o.rootMotion = rootMotion;
  c.playBlend(0, space, o, x, y);
  const auto w = c.layerBlendWeights(0);
  double stride = 0.0, duration = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double d = space->samples()[i].duration;
    stride += w[i] * (i < groundSpeeds.size() ? groundSpeeds[i] : 0.0f) * d;
    duration += w[i] * d;
  }
  const double groundSpeed = duration > 0.0 ? stride / duration : 0.0;
  const int feet[2] = {rig->joints().leftLeg.end, rig->joints().rightLeg.end};
  std::vector<glm::vec3> place[2];
  double travelled = 0.0;
  glm::vec3 start(0.0f);
  std::vector<char> plantedAt[2];
  const int frames = static_cast<int>(std::ceil((cycles + 1) * space->cycleDuration(w) / dt));
  const int warm = static_cast<int>(std::ceil(space->cycleDuration(w) / dt));
  for (int f = 0; f < frames; ++f) {
    c.update(dt);
    if (!rootMotion) travelled += groundSpeed * dt;  // the ground moves under a clip in place
    if (f == warm) start = c.position();
    if (f < warm) continue;
    const glm::mat4 world = c.worldMatrix();
    for (int k = 0; k < 2; ++k) {
      glm::vec3 p = glm::vec3(world * c.transformBuffer().modelMatrices()[static_cast<std::size_t>(feet[k])][3]);
      p.z += static_cast<float>(travelled);
      place[k].push_back(p);
      float inContact = 0.0f;
      for (std::size_t i = 0; i < w.size(); ++i) {
        const auto& sample = space->samples()[i];
        const double clipPhase = space->clipTime(i, c.layerTime(0)) / sample.duration;
        if (w[i] > 0.0f && marionette::inContact(sample.contacts[k], static_cast<float>(clipPhase - std::floor(clipPhase))))
          inContact += w[i];
      }
      plantedAt[k].push_back(inContact >= 0.5f);
    }
  }
  BlendSkating out;
  const double measured = (frames - 1 - warm) * dt;
  const glm::vec3 end = c.position();
  out.travelSpeed = rootMotion ? std::hypot(end.x - start.x, end.z - start.z) / measured : groundSpeed;
  std::vector<double> speeds;
  double slide = 0.0;
  for (int k = 0; k < 2; ++k) {
    bool was = false;
    for (std::size_t f = 1; f < place[k].size(); ++f) {
      const bool planted = plantedAt[k][f] && plantedAt[k][f - 1];
      if (planted) {
        const double d = std::hypot(place[k][f].x - place[k][f - 1].x, place[k][f].z - place[k][f - 1].z);
        speeds.push_back(d / dt);
        slide += d;
        out.contacts += was ? 0 : 1;
      }
      was = planted;
    }
  }
  out.plantedFrames = static_cast<int>(speeds.size());
  if (!speeds.empty()) {
    double sum = 0.0;
    for (double s : speeds) sum += s;
    out.meanSpeed = sum / static_cast<double>(speeds.size());
    std::sort(speeds.begin(), speeds.end());
    out.p95Speed = speeds[static_cast<std::size_t>(0.95 * static_cast<double>(speeds.size() - 1))];
    out.worstSpeed = speeds.back();
    out.slidePerContact = out.contacts ? slide / out.contacts : 0.0;
  }
  return out;
}

}  // namespace marionette::test
