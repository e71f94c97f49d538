// Retargeting on real data (docs/accuracy.md, "Retargeting"), run by scripts/accuracy:
//   OUT_DIR/retarget_metrics.csv      every source motion onto every target character,
//                                     without IK, with feet IK, with feet and hands IK:
//                                     run time, end-effector error, foot skating
//   OUT_DIR/retarget_strip_<name>.csv the CMU walk (131_01) as stick figures every
//                                     0.25 s, side view, lengths in character heights
//   OUT_DIR/retarget_feet_<name>.csv  left/right foot height (leg lengths) over time
// Joint maps: the shipped ones (assets/jointmaps, by the file names listed below).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "marionette/io/import.hpp"
#include "marionette/retarget/retarget_metrics.hpp"
#include "marionette/retarget/retargeter.hpp"
#include "retarget_data.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::retarget;

namespace {

double secondsOf(const Retargeter& r, const Clip& clip, Clip& out) {
  std::vector<double> runs;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    out = r.retargetClip(clip);
    runs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(runs.begin(), runs.end());
  return runs[1];
}

// Forward direction of travel of the hips over the clip (XZ), for the side view.
glm::vec2 travelDirection(const Skeleton& s, const JointMap& m, const Clip& clip) {
  std::vector<Transform> a(s.jointCount()), b(s.jointCount());
  sampleClip(clip, 0.0f, s.restPose, a);
  sampleClip(clip, clip.duration, s.restPose, b);
  const glm::vec3 pa(modelMatrixOf(s, a, m.joint(Bone::Hips))[3]), pb(modelMatrixOf(s, b, m.joint(Bone::Hips))[3]);
  glm::vec2 d(pb.x - pa.x, pb.z - pa.z);
  return glm::length(d) > 1e-6f ? glm::normalize(d) : glm::vec2(0.0f, 1.0f);
}

void writeStrip(const std::string& path, const Skeleton& s, const JointMap& m, const Clip& clip, glm::vec2 forward,
                float from, float to, float step) {
  std::ofstream out(path);
  out << "# frame x0 y0 dx dy (side view in character heights, each frame 0.8 to the right; a segment per bone)\n";
  const float h = characterHeight(s, m);
  std::vector<Transform> local(s.jointCount());
  std::vector<glm::mat4> model(s.jointCount());
  // Bones only: no segments from the joints above the hips (the root stays at the
  // origin while the hips travel; IK targets hang there), and feet or hands that do
  // not hang from their limb drawn from it.
  std::vector<int> drawnParent = s.parents;
  for (int a = s.parents[static_cast<std::size_t>(m.joint(Bone::Hips))]; a >= 0; a = s.parents[static_cast<std::size_t>(a)])
    for (std::size_t j = 0; j < s.jointCount(); ++j)
      if (drawnParent[j] == a) drawnParent[j] = -1;
  for (auto [lower, end] : {std::pair{Bone::LeftLowerLeg, Bone::LeftFoot}, std::pair{Bone::RightLowerLeg, Bone::RightFoot},
                            std::pair{Bone::LeftLowerArm, Bone::LeftHand}, std::pair{Bone::RightLowerArm, Bone::RightHand}})
    if (m.joint(lower) >= 0 && m.joint(end) >= 0) drawnParent[static_cast<std::size_t>(m.joint(end))] = m.joint(lower);
  int frame = 0;
  for (float t = from; t <= to + 1e-4f; t += step, ++frame) {
    sampleClip(clip, t, s.restPose, local);
    localToModel(s, local, model);
    float ground = 1e30f;
    for (Bone b : {Bone::LeftFoot, Bone::RightFoot, Bone::LeftToes, Bone::RightToes})
      if (m.joint(b) >= 0) ground = std::min(ground, glm::vec3(model[static_cast<std::size_t>(m.joint(b))][3]).y);
    // Each figure beside the previous one: forward positions relative to its hips.
    const glm::vec3 hips(model[static_cast<std::size_t>(m.joint(Bone::Hips))][3]);
    const float shift = 0.8f * static_cast<float>(frame) - (hips.x * forward.x + hips.z * forward.y) / h;
    for (std::size_t j = 0; j < s.jointCount(); ++j) {
      const int p = drawnParent[j];
      if (p < 0) continue;
      const glm::vec3 a(model[static_cast<std::size_t>(p)][3]), b(model[j][3]);
      const float xa = (a.x * forward.x + a.z * forward.y) / h + shift, xb = (b.x * forward.x + b.z * forward.y) / h + shift;
      out << frame << ' ' << xa << ' ' << (a.y - ground) / h << ' ' << xb - xa << ' ' << (b.y - a.y) / h << '\n';
    }
  }
}

void writeFeet(const std::string& path, const Skeleton& s, const JointMap& m, const Clip& clip) {
  std::ofstream out(path);
  out << "# time left right (foot joint height above its lowest, leg lengths)\n";
  const float leg = restLegLength(s, m);
  std::vector<Transform> local(s.jointCount());
  std::vector<std::array<float, 3>> rows;
  float low[2] = {1e30f, 1e30f};
  for (float t = 0.0f; t <= clip.duration; t += 1.0f / 60.0f) {
    sampleClip(clip, t, s.restPose, local);
    const float l = modelMatrixOf(s, local, m.joint(Bone::LeftFoot))[3].y;
    const float r = modelMatrixOf(s, local, m.joint(Bone::RightFoot))[3].y;
    low[0] = std::min(low[0], l), low[1] = std::min(low[1], r);
    rows.push_back({t, l, r});
  }
  for (const auto& row : rows) out << row[0] << ' ' << (row[1] - low[0]) / leg << ' ' << (row[2] - low[1]) / leg << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "docs/data";
  std::filesystem::create_directories(dir);
  std::vector<test::RetargetSubject> sources, targets;
  std::string error;
  if (!test::loadRetargetSubjects(test::retargetSources(), sources, error) ||
      !test::loadRetargetSubjects(test::retargetTargets(), targets, error)) {
    std::fprintf(stderr, "retarget_work_precision: %s\n", error.c_str());
    return 2;
  }
  std::ofstream csv(dir + "/retarget_metrics.csv");
  // The walk's work-precision points, one gnuplot block per target.
  std::ofstream wp(dir + "/retarget_work_precision.dat");
  wp << "# target ik(0 none, 1 feet, 2 feet+hands) us_per_frame ee_mean skate_ratio\n";
  csv << "source,target,ik,frames,seconds,us_per_frame,ee_mean,ee_max,skate_source,skate_target,skate_ratio,"
         "dir_mean_deg,dir_p95_deg,effectors,segments\n";
  // Every figure with what it covers: the effectors (of hands, feet, head) and segments (of 10)
  // both maps have; a figure over none is n/a.
  std::printf("| source | target | IK | frames | us/frame | end-effector mean | max | effectors | segment directions mean | p95 | segments | skating ratio |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& src : sources) {
    const Clip& clip = src.asset.clips.front();
    for (const auto& dst : targets) {
      for (int ik = 0; ik < 3; ++ik) {
        RetargetOptions o;
        o.sourceHipsReference = standingHipsReference(src.asset.skeleton, src.map, clip, dst.asset.skeleton, dst.map);
        o.ik.feet = ik >= 1;
        o.ik.hands = ik >= 2;
        const Retargeter r = Retargeter::bind(src.asset.skeleton, src.map, dst.asset.skeleton, dst.map, o);
        Clip out;
        const double seconds = secondsOf(r, clip, out);
        const std::size_t frames = out.tracks.empty() ? 0 : out.tracks.front().rotation.keyCount();
        const EffectorError e = endEffectorError(src.asset.skeleton, src.map, clip, dst.asset.skeleton, dst.map, out,
                                                 r.facingAlignment());
        const SkatingComparison sk =
            compareSkating(src.asset.skeleton, src.map, clip, dst.asset.skeleton, dst.map, out);
        const SegmentDirectionError d = segmentDirectionError(src.asset.skeleton, src.map, clip, dst.asset.skeleton,
                                                              dst.map, out, r.facingAlignment());
        const char* mode = ik == 0 ? "none" : ik == 1 ? "feet" : "feet+hands";
        const double us = frames ? seconds * 1e6 / static_cast<double>(frames) : 0.0;
        csv << src.name << ',' << dst.name << ',' << mode << ',' << frames << ',' << seconds << ',' << us << ','
            << e.mean << ',' << e.max << ',' << sk.source << ',' << sk.target << ',' << sk.ratio << ',' << d.meanDegrees
            << ',' << d.p95Degrees << ',' << e.effectors.size() << ',' << d.segments.size() << '\n';
        if (&src == &sources.front())
          wp << dst.name << ' ' << ik << ' ' << us << ' ' << e.mean << ' ' << sk.ratio << (ik == 2 ? "\n\n\n" : "\n");
        auto figure = [](bool measured, const char* format, double v) {
          char b[48];
          std::snprintf(b, sizeof b, format, v);
          return measured ? std::string(b) : std::string("n/a");
        };
        const std::size_t segmentCount = d.segments.size() + d.missing.size();
        std::printf("| %s | %s | %s | %zu | %.2f | %s | %s | %zu of 5 | %s | %s | %zu of %zu | %s |\n", src.name.c_str(),
                    dst.name.c_str(), mode, frames, us, figure(e.samples > 0, "%.1f %%", 100.0 * e.mean).c_str(),
                    figure(e.samples > 0, "%.1f %%", 100.0 * e.max).c_str(), e.effectors.size(),
                    figure(d.samples > 0, "%.2f deg", d.meanDegrees).c_str(),
                    figure(d.samples > 0, "%.2f deg", d.p95Degrees).c_str(), d.segments.size(), segmentCount,
                    figure(sk.contacts > 0 && sk.source > 0.0, "%.2f", sk.ratio).c_str());
      }
    }
  }
  // The CMU walk as stick figures and foot heights, on each target.
  const auto& walk = sources.front();
  const Clip& clip = walk.asset.clips.front();
  const glm::vec2 forward = travelDirection(walk.asset.skeleton, walk.map, clip);
  writeStrip(dir + "/retarget_strip_" + walk.name + ".csv", walk.asset.skeleton, walk.map, clip, forward, 2.0f, 5.0f, 0.25f);
  writeFeet(dir + "/retarget_feet_" + walk.name + ".csv", walk.asset.skeleton, walk.map, clip);
  for (const auto& dst : targets) {
    for (int ik = 0; ik < 2; ++ik) {
      RetargetOptions o;
      o.sourceHipsReference = standingHipsReference(walk.asset.skeleton, walk.map, clip, dst.asset.skeleton, dst.map);
      o.ik.feet = ik == 1;
      const Retargeter r = Retargeter::bind(walk.asset.skeleton, walk.map, dst.asset.skeleton, dst.map, o);
      const Clip out = r.retargetClip(clip);
      const glm::vec2 f = travelDirection(dst.asset.skeleton, dst.map, out);
      const std::string name = dst.name + (ik ? "_feet_ik" : "");
      if (ik == 0) writeStrip(dir + "/retarget_strip_" + name + ".csv", dst.asset.skeleton, dst.map, out, f, 2.0f, 5.0f, 0.25f);
      writeFeet(dir + "/retarget_feet_" + name + ".csv", dst.asset.skeleton, dst.map, out);
    }
  }
  std::fprintf(stderr, "wrote %s/retarget_metrics.csv and the walk's strips and foot traces\n", dir.c_str());
  return 0;
}
