// marionette_bench: retargeting a CMU motion (131_01 "Start Walk Stop", 31 joints,
// 120 fps) onto Godette (VRM, 68 joints).
//   Retarget/Online/ik:0|1   one frame: Retargeter::apply on a sampled source pose,
//                            without / with feet IK. Counter us_per_frame. The
//                            issue's target: at most 1.5 us on top of sampling.
//   Retarget/Sample          the plain sampling of the source it sits on, for scale.
//   Retarget/Offline60s      retargetClip of a 60 s, 120 fps clip (7200 frames, the
//                            CMU clip looped) with feet IK. Target: at most 100 ms.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "marionette/animation/sampling.hpp"
#include "marionette/io/import.hpp"
#include "marionette/retarget/retarget_metrics.hpp"
#include "marionette/retarget/retargeter.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::retarget;

namespace {

struct Data {
  Asset source, target;
  JointMap sourceMap, targetMap;
  Clip loop60;  // the source clip looped to 60 s, keys at 120 fps
};

const Data* data(benchmark::State& state) {
  static std::unique_ptr<Data> d = []() -> std::unique_ptr<Data> {
    ImportOptions o;
    o.loadMeshes = false;
    ImportResult s = importAsset(test::sharedAsset("motions/bvh/cmu_131_01_maxfriendly.bvh"), o);
    ImportResult t = importAsset(test::sharedAsset("characters/Godette_vrm_v4.vrm"), o);
    if (!s.ok() || !t.ok() || s.asset->clips.empty()) return nullptr;
    auto out = std::make_unique<Data>();
    out->source = std::move(*s.asset);
    out->target = std::move(*t.asset);
    out->sourceMap = guessJointMap(out->source).map;
    out->targetMap = guessJointMap(out->target).map;
    const Clip& clip = out->source.clips.front();
    const std::size_t n = out->source.skeleton.jointCount();
    out->loop60.name = "loop60";
    out->loop60.tracks.resize(n);
    std::vector<Transform> pose(n);
    for (int k = 0; k <= 60 * 120; ++k) {
      const float time = static_cast<float>(k) / 120.0f;
      sampleClip(clip, std::fmod(time, clip.duration), out->source.skeleton.restPose, pose);
      for (std::size_t j = 0; j < n; ++j) {
        JointTrack& t = out->loop60.tracks[j];
        t.joint = static_cast<int>(j);
        t.rotation.times.push_back(time);
        t.rotation.values.push_back(pose[j].rotation);
        if (j == 0) {
          t.translation.times.push_back(time);
          t.translation.values.push_back(pose[j].translation);
        }
      }
    }
    out->loop60.updateDuration();
    return out;
  }();
  if (!d) state.SkipWithError("cannot load cmu_131_01_maxfriendly.bvh or Godette_vrm_v4.vrm from ../shared/assets");
  return d.get();
}

RetargetOptions optionsFor(const Data& d, bool feetIk) {
  RetargetOptions o;
  o.sourceHipsReference = standingHipsReference(d.source.skeleton, d.sourceMap, d.source.clips.front(), d.target.skeleton, d.targetMap);
  o.ik.feet = feetIk;
  return o;
}

void BM_RetargetOnline(benchmark::State& state) {
  const Data* d = data(state);
  if (!d) return;
  const Retargeter r = Retargeter::bind(d->source.skeleton, d->sourceMap, d->target.skeleton, d->targetMap,
                                        optionsFor(*d, state.range(0) != 0));
  const Clip& clip = d->source.clips.front();
  // 256 sampled poses, applied in turn, so the data is not one hot pose.
  std::vector<std::vector<Transform>> poses(256, std::vector<Transform>(d->source.skeleton.jointCount()));
  for (std::size_t k = 0; k < poses.size(); ++k)
    sampleClip(clip, clip.duration * static_cast<float>(k) / 256.0f, d->source.skeleton.restPose, poses[k]);
  std::vector<Transform> out(d->target.skeleton.jointCount());
  RetargetScratch scratch = r.makeScratch();
  std::size_t k = 0;
  for (auto _ : state) {
    r.apply(poses[k], out, scratch, 1.0f / 60.0f);
    k = (k + 1) & 255;
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["us_per_frame"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1e-6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RetargetOnline)->Name("Retarget/Online")->ArgName("ik")->Arg(0)->Arg(1);

void BM_RetargetSample(benchmark::State& state) {
  const Data* d = data(state);
  if (!d) return;
  const Clip& clip = d->source.clips.front();
  std::vector<Transform> pose(d->source.skeleton.jointCount());
  SamplingCursor cursor;
  cursor.reset(clip);
  float time = 0.0f;
  for (auto _ : state) {
    sampleClip(clip, time, d->source.skeleton.restPose, pose, &cursor);
    time = std::fmod(time + 1.0f / 60.0f, clip.duration);
    benchmark::DoNotOptimize(pose.data());
  }
  state.counters["us_per_frame"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1e-6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RetargetSample)->Name("Retarget/Sample");

void BM_RetargetOffline60s(benchmark::State& state) {
  const Data* d = data(state);
  if (!d) return;
  const Retargeter r =
      Retargeter::bind(d->source.skeleton, d->sourceMap, d->target.skeleton, d->targetMap, optionsFor(*d, true));
  for (auto _ : state) {
    Clip out = r.retargetClip(d->loop60);
    benchmark::DoNotOptimize(out.tracks.data());
  }
  state.SetLabel("7201 frames, feet IK");
}
BENCHMARK(BM_RetargetOffline60s)->Name("Retarget/Offline60s")->Unit(benchmark::kMillisecond);

}  // namespace
