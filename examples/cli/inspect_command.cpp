#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "marionette/io/import.hpp"

namespace marionette::cli {

namespace {
int exitCode(const Diagnostics& d) { return !d.ok() ? 2 : (d.hasWarnings() ? 1 : 0); }

void printTree(const Skeleton& s) {
  std::vector<int> depth(s.jointCount(), 0);
  for (std::size_t i = 0; i < s.jointCount(); ++i) {
    if (s.parents[i] >= 0) depth[i] = depth[s.parents[i]] + 1;
    std::printf("  %3zu %*s%s%s\n", i, depth[i] * 2, "", s.names[i].c_str(), s.skinned[i] ? "" : "  (not skinned)");
  }
}

std::size_t trackCount(const Clip& c) {
  std::size_t n = c.morphTracks.size();
  for (const JointTrack& t : c.tracks)
    n += !t.translation.empty() + !t.rotation.empty() + !t.scale.empty();
  return n;
}
}  // namespace

int inspectCommand(const InspectOptions& o) {
  const std::string& file = o.file;
  const bool json = o.json;
  ImportResult r = importAsset(file, {.isolateThirdPartyParsers = true});  // a tool: isolated
  std::fputs(r.diagnostics.format().c_str(), stderr);
  if (!r.ok()) return 2;
  const Asset& a = *r.asset;
  const Skeleton& s = a.skeleton;
  if (json) {
    nlohmann::ordered_json j;
    j["file"] = file;
    j["joints"] = s.names;
    j["parents"] = s.parents;
    auto& clips = j["clips"] = nlohmann::json::array();
    for (const Clip& c : a.clips) clips.push_back({{"name", c.name}, {"duration", c.duration}, {"tracks", trackCount(c)}});
    j["morphTargets"] = a.morphTargets;
    auto& meshes = j["meshes"] = nlohmann::json::array();
    for (const Mesh& m : a.meshes) {
      std::size_t vertices = 0, triangles = 0;
      for (const MeshPrimitive& p : m.primitives) {
        vertices += p.positions.size();
        triangles += p.indices.size() / 3;
      }
      meshes.push_back({{"name", m.name}, {"primitives", m.primitives.size()}, {"vertices", vertices},
                        {"triangles", triangles}, {"skinned", m.skinned}});
    }
    j["unitScale"] = a.unitScale;
    if (a.hasHumanoid) j["humanoid"] = a.humanoid.bones;
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("%s\n", file.c_str());
    std::printf("skeleton: %zu joints (unit scale %g m per file unit)\n", s.jointCount(), a.unitScale);
    printTree(s);
    std::printf("clips: %zu\n", a.clips.size());
    for (const Clip& c : a.clips) std::printf("  %-32s %8.3f s  %zu tracks\n", c.name.c_str(), c.duration, trackCount(c));
    std::printf("morph targets: %zu\n", a.morphTargets.size());
    for (const std::string& m : a.morphTargets) std::printf("  %s\n", m.c_str());
    std::printf("meshes: %zu\n", a.meshes.size());
    for (const Mesh& m : a.meshes) {
      std::size_t vertices = 0;
      for (const MeshPrimitive& p : m.primitives) vertices += p.positions.size();
      std::printf("  %-32s %zu primitives, %zu vertices%s\n", m.name.c_str(), m.primitives.size(), vertices,
                  m.skinned ? ", skinned" : "");
    }
    if (a.hasHumanoid) std::printf("humanoid: %zu bones mapped\n", a.humanoid.bones.size());
  }
  return exitCode(r.diagnostics);
}

}  // namespace marionette::cli
