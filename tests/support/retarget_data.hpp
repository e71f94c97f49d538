// The real motions and characters the retargeting measurements use (issue 6):
// sources are the BVH files and Pab FBX clips in ../shared/assets and the BVH
// files of Debian's assimp-testmodels; targets the four characters. Each with
// its joint map: the shipped file in assets/jointmaps when one is named, else
// the guess. Missing data is an error, never a skip.
#pragma once
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/rig/joint_map.hpp"
#include "test_data.hpp"

namespace marionette::test {

struct RetargetFile {
  std::string name;     // short name for tables
  std::string path;     // the file
  std::string mapFile;  // assets/jointmaps/... or "" for the guess
};

struct RetargetSubject {
  std::string name;
  Asset asset;
  retarget::JointMap map;
};

// The CMU walk first: it is the one plotted.
inline std::vector<RetargetFile> retargetSources() {
  return {
      {"cmu_131_01_walk", sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), "assets/jointmaps/cmu_max.json"},
      {"cmu_01_01_jumps", sharedAsset("motions/bvh/cmu_01_01_mbfriendly.bvh"), "assets/jointmaps/cmu_mb.json"},
      {"pirouette", sharedAsset("motions/bvh/pirouette.bvh"), "assets/jointmaps/pirouette.json"},
      {"pab_walk", sharedAsset("motions/fbx/pab_walk.fbx"), "assets/jointmaps/pab.json"},
      {"pab_jog", sharedAsset("motions/fbx/pab_jog.fbx"), "assets/jointmaps/pab.json"},
      {"pab_crossarms", sharedAsset("motions/fbx/pab_crossarms.fbx"), "assets/jointmaps/pab.json"},
      {"assimp_01_01", assimpModel("BVH/01_01.bvh"), "assets/jointmaps/cmu_mb.json"},
      {"assimp_01_03", assimpModel("BVH/01_03.bvh"), "assets/jointmaps/cmu_mb.json"},
      {"boxing_toes", assimpModel("BVH/Boxing_Toes.bvh"), "assets/jointmaps/Boxing_Toes.json"},
  };
}

inline std::vector<RetargetFile> retargetTargets() {
  return {
      {"RobotExpressive", sharedAsset("characters/RobotExpressive.glb"), "assets/jointmaps/RobotExpressive.json"},
      {"Godette", sharedAsset("characters/Godette_vrm_v4.vrm"), "assets/jointmaps/Godette_vrm_v4.json"},
      {"pab_arnaud", sharedAsset("characters/pab_arnaud.fbx"), "assets/jointmaps/pab.json"},
      {"CesiumMan", sharedAsset("characters/CesiumMan.glb"), "assets/jointmaps/CesiumMan.json"},
  };
}

inline bool loadRetargetSubject(const RetargetFile& f, RetargetSubject& out, std::string& error, bool meshes = false) {
  ImportOptions o;
  o.loadMeshes = meshes;
  ImportResult r = importAsset(f.path, o);
  if (!r.ok()) {
    error = f.path + ": cannot import: " + r.diagnostics.format();
    return false;
  }
  retarget::JointMapResult m = f.mapFile.empty() ? retarget::guessJointMap(*r.asset)
                                                 : retarget::loadJointMap(sourceFile(f.mapFile), *r.asset);
  if (!m.diagnostics.ok()) {  // warnings (RobotExpressive has no hand joint) are documented in the maps
    error = f.path + ": joint map: " + m.diagnostics.format();
    return false;
  }
  out.name = f.name;
  out.asset = std::move(*r.asset);
  out.map = std::move(m.map);
  return true;
}

inline bool loadRetargetSubjects(const std::vector<RetargetFile>& files, std::vector<RetargetSubject>& out,
                                 std::string& error) {
  for (const RetargetFile& f : files) {
    RetargetSubject s;
    if (!loadRetargetSubject(f, s, error)) return false;
    if (s.asset.clips.empty() && files.front().path.find("characters/") == std::string::npos) {
      error = f.path + ": no animation";
      return false;
    }
    out.push_back(std::move(s));
  }
  return true;
}

}  // namespace marionette::test
