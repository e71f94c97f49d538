// Work-precision of the load-time clip optimizer on the Pab walk, jog and
// crossarms clips (../shared/assets/motions/fbx) bound to pab_arnaud.fbx.
// For each tolerance: keys kept, error, and the runtime cost of Sample1
// (1000 characters, one core, median of 7 runs).
//
// Error metric (ACL style): distance in model space between virtual vertices
// rigidly attached to each joint (the joint and 10 cm along each local axis),
// posed by the authored clip and by the optimized clip, every 1/120 s; max,
// p99, and the share under 0.1 mm.
//
// usage: marionette_work_precision OUT.csv
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "marionette/animation/clip_binding.hpp"
#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "pose_error.hpp"
#include "test_paths.hpp"

using namespace marionette;

namespace {
std::string shared(const std::string& rel) { return ::marionette::test::sharedDir() + "/assets/" + rel; }

double sampleMicros(const std::shared_ptr<const Rig>& rig, const std::string& clip) {
  Scene scene;
  for (int i = 0; i < 1000; ++i) {
    PlayOptions o;
    o.startTime = 0.013 * i;
    scene.addCharacter("c" + std::to_string(i), rig)->play(0, clip, o);
  }
  scene.update(1.0 / 60.0);
  std::vector<double> runs;
  for (int r = 0; r < 7; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < 100; ++f) scene.update(1.0 / 60.0);
    runs.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() / 1e5);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
    return 2;
  }
  ImportOptions noMesh;
  noMesh.loadMeshes = false;
  ImportResult character = importAsset(shared("characters/pab_arnaud.fbx"), noMesh);
  if (!character.ok()) {
    std::fputs(character.diagnostics.format().c_str(), stderr);
    return 2;
  }
  auto asset = std::make_shared<Asset>(std::move(*character.asset));
  std::vector<std::pair<std::string, Clip>> clips;
  for (const char* m : {"walk", "jog", "crossarms"}) {
    ImportResult r = importAsset(shared(std::string("motions/fbx/pab_") + m + ".fbx"), noMesh);
    if (!r.ok()) {
      std::fputs(r.diagnostics.format().c_str(), stderr);
      return 2;
    }
    Clip bound = bindClipByName(r.asset->clips.front(), r.asset->skeleton, asset->skeleton);
    bound.name = m;
    clips.emplace_back(m, std::move(bound));
  }
  std::ofstream csv(argv[1]);
  // The errors' coverage (issue 41): the joint-samples they are over (every joint of the three
  // clips, at 120 Hz), in the last column.
  csv << "tolerance,keys,max_error_m,p99_error_m,share_under_0.1mm,sample1_us_per_char,joint_samples\n";
  std::printf("%-10s %8s %12s %12s %10s %10s %14s\n", "tolerance", "keys", "max (m)", "p99 (m)", "<0.1mm", "us/char",
              "joint-samples");
  for (float tol : {0.0f, 1e-6f, 1e-5f, 1e-4f, 1e-3f, 1e-2f}) {
    RigSettings ro;
    ro.optimizeClips = tol > 0.0f;
    ro.tolerances = {tol, tol, tol};
    auto rig = std::make_shared<Rig>(*asset, ro);
    test::PoseErrors e;
    std::size_t keys = 0;
    for (auto& [name, clip] : clips) {
      rig->addClip(clip, asset->skeleton, name);
      const Clip& optimized = rig->findClip(name)->clip;
      for (const JointTrack& jt : optimized.tracks)
        keys += jt.translation.keyCount() + jt.rotation.keyCount() + jt.scale.keyCount();
      test::accumulateVirtualVertexErrors(asset->skeleton, clip, optimized, e);
    }
    const float p99 = e.percentile(0.99);
    const double under = e.shareUnder(1e-4f);
    const double us = sampleMicros(rig, "walk");
    const std::size_t samples = e.perJointSample.size();
    csv << tol << ',' << keys << ',' << e.max << ',' << p99 << ',' << under << ',' << us << ',' << samples << '\n';
    std::printf("%-10g %8zu %12.3g %12.3g %9.1f%% %10.3f %14zu\n", tol, keys, e.max, p99, 100.0 * under, us, samples);
  }
  return 0;
}
