// The error metric of the accuracy tests, in the style of ACL: the distance in
// model space between virtual vertices rigidly attached to each joint (the
// joint itself and 10 cm along each local axis), posed by a reference clip and
// by an approximation of it, sampled every 1/120 s over the reference clip.
#pragma once
#include <algorithm>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"

namespace marionette::test {

struct PoseErrors {
  std::vector<float> perJointSample;  // worst virtual vertex per joint per sample, metres
  float max = 0.0f;

  // Value below which a share p of the samples lie (p in [0, 1]).
  [[nodiscard]] float percentile(double p) const {
    if (perJointSample.empty()) return 0.0f;
    std::vector<float> v = perJointSample;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
  }
  [[nodiscard]] double shareUnder(float threshold) const {
    if (perJointSample.empty()) return 1.0;
    const auto n = std::count_if(perJointSample.begin(), perJointSample.end(), [&](float e) { return e < threshold; });
    return static_cast<double>(n) / static_cast<double>(perJointSample.size());
  }
};

// Adds the errors of `approx` against `reference` to `out`.
inline void accumulateVirtualVertexErrors(const Skeleton& s, const Clip& reference, const Clip& approx, PoseErrors& out) {
  const std::size_t n = s.jointCount();
  std::vector<Transform> pa(n), pb(n);
  std::vector<glm::mat4> ma(n), mb(n);
  const glm::vec4 offsets[4] = {{0, 0, 0, 1}, {0.1f, 0, 0, 1}, {0, 0.1f, 0, 1}, {0, 0, 0.1f, 1}};
  for (double t = 0.0; t <= reference.duration + 1e-9; t += 1.0 / 120.0) {
    sampleClip(reference, static_cast<float>(t), s.restPose, pa);
    sampleClip(approx, static_cast<float>(t), s.restPose, pb);
    localToModel(s, pa, ma);
    localToModel(s, pb, mb);
    for (std::size_t j = 0; j < n; ++j) {
      float worst = 0.0f;
      for (const glm::vec4& o : offsets) worst = std::max(worst, glm::length(glm::vec3(ma[j] * o - mb[j] * o)));
      out.max = std::max(out.max, worst);
      out.perJointSample.push_back(worst);
    }
  }
}

// The real clips the clip accuracy tests measure, in ../shared/assets: RobotExpressive,
// CesiumMan, and (with Assimp) the Pab motions and CMU 01_01.
inline std::vector<std::string> accuracyClipFiles() {
  std::vector<std::string> files = {"characters/RobotExpressive.glb", "characters/CesiumMan.glb"};
#ifdef MARIONETTE_HAS_ASSIMP
  for (const char* f : {"motions/fbx/pab_walk.fbx", "motions/fbx/pab_jog.fbx", "motions/fbx/pab_crossarms.fbx",
                        "motions/bvh/cmu_01_01_mbfriendly.bvh"})
    files.push_back(f);
#endif
  return files;
}

// Imports one of them without meshes, in metres (CMU's BVH units scaled).
inline ImportResult importAccuracyClips(const std::string& path) {
  ImportOptions o;
  o.loadMeshes = false;
  if (path.find("cmu_") != std::string::npos) o.extraScale = 0.056444f;  // CMU units to metres
  return importAsset(path, o);
}

}  // namespace marionette::test
