// The real characters and clips the runtime benchmarks play (runtime_bench.cpp,
// stage_bench.cpp): Pab (FBX, 54 joints) with walk / jog / crossarms, and
// RobotExpressive (glTF, 43 joints) with Idle / Walking / Running, from ../shared.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/rig/rig.hpp"
#include "test_paths.hpp"

namespace marionette::test {

struct BenchAsset {
  std::shared_ptr<const Rig> rig;
  std::vector<std::string> clips;  // three clip names to play
  std::string error;
};

inline std::string benchAssetPath(const std::string& rel) { return sharedDir() + "/assets/" + rel; }

inline const BenchAsset& loadBenchAsset(const std::string& which) {
  static std::map<std::string, BenchAsset> cache;
  if (auto it = cache.find(which); it != cache.end()) return it->second;
  BenchAsset& b = cache[which];
  ImportOptions noMesh;
  noMesh.loadMeshes = false;
  if (which == "Pab") {
    ImportResult r = importAsset(benchAssetPath("characters/pab_arnaud.fbx"), noMesh);
    if (!r.ok()) return b.error = r.diagnostics.format(), b;
    auto asset = std::make_shared<Asset>(std::move(*r.asset));
    auto rig = std::make_shared<Rig>(*asset);
    for (const char* m : {"walk", "jog", "crossarms"}) {
      ImportResult c = importAsset(benchAssetPath(std::string("motions/fbx/pab_") + m + ".fbx"), noMesh);
      if (!c.ok() || c.asset->clips.empty()) return b.error = c.diagnostics.format(), b;
      rig->addClip(c.asset->clips.front(), c.asset->skeleton, m);
      b.clips.push_back(m);
    }
    b.rig = rig;
  } else {
    ImportResult r = importAsset(benchAssetPath("characters/RobotExpressive.glb"), noMesh);
    if (!r.ok()) return b.error = r.diagnostics.format(), b;
    b.rig = std::make_shared<Rig>(*r.asset);
    b.clips = {"Idle", "Walking", "Running"};
  }
  return b;
}

}  // namespace marionette::test
