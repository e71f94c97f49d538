// Per-stage cost of the runtime per joint, on the real skeletons of runtime_bench.cpp,
// over 1000 characters' worth of data (each with its own poses and matrices, so the
// caches hold what they hold in a scene of 1000):
//   Stage/Sample/<asset>              one clip sampled into a pose as the runtime does it (rest, then
//                                     its tracks, from the compact keys)
//   Stage/SampleFloat/<asset>         the same from the float keys (the clip before compaction)
//   Stage/Blend3/<asset>              three sampled poses (0.5 / 0.3 / 0.2) summed and finished into
//                                     the character's pose; the sampled poses are hot in the cache,
//                                     as the runtime's shared scratch pose is (8 sets, in turn)
//   Stage/Blend3Reference/<asset>     the same with blendPoses, the scalar definition
//   Stage/BlendOver/<asset>           a sampled pose (walk) copied, another (run) blended over it at
//                                     0.4 (slerp per joint): how locomotion and behavior clips layer
//   Stage/BlendOverAcos/<asset>       the same, one joint at a time with slerp by acos and sin (what
//                                     blendOver did before the series), for a same-run ratio
//   Stage/LocalToModel/<asset>        local pose to model matrices (4-wide on x86-64)
//   Stage/LocalToModelScalar/<asset>  the scalar definition, for a same-run ratio
//   Stage/Palette/<asset>             model * inverse bind
//   Stage/LocalToModelAndPalette/<asset>  both in one pass, with the rig's PaletteBasis (what a
//                                     character runs; the AVX build where the CPU has AVX)
//   Stage/LocalToModelAndPaletteSSE2/<asset>  the same held to the SSE2 build
//   Stage/Memcpy/<asset>              copying the bytes model + palette hold: the floor
// Counter ns_per_joint: nanoseconds per joint per character (one core).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstring>

#include "marionette/animation/animation_clip.hpp"
#include "marionette/animation/blending.hpp"
#include "marionette/animation/pose.hpp"
#include "marionette/animation/sampling.hpp"
#include "bench_assets.hpp"
#include "slerp_acos.hpp"

using namespace marionette;

namespace {

constexpr int kCharacters = 1000;

// Poses and matrices of kCharacters characters, three clips each, sampled at the
// characters' own times (0.013 s apart, as runtime_bench.cpp starts them).
struct StageData {
  const Rig* rig = nullptr;
  const Skeleton* skeleton = nullptr;
  std::vector<const AnimationClip*> clips;
  std::size_t joints = 0;
  std::vector<Transform> poses[3], out;
  std::vector<glm::mat4> model, palette;
  std::vector<SamplingCursor> cursors;

  std::span<Transform> pose(int layer, int c) {
    return std::span<Transform>(poses[layer]).subspan(static_cast<std::size_t>(c) * joints, joints);
  }
  std::span<Transform> result(int c) { return std::span<Transform>(out).subspan(static_cast<std::size_t>(c) * joints, joints); }
  std::span<glm::mat4> models(int c) { return std::span<glm::mat4>(model).subspan(static_cast<std::size_t>(c) * joints, joints); }
  std::span<glm::mat4> palettes(int c) {
    return std::span<glm::mat4>(palette).subspan(static_cast<std::size_t>(c) * joints, joints);
  }
  float time(int layer, int c) const { return wrapClipTime(0.013 * c, clips[layer]->clip.duration, WrapMode::Loop); }
};

StageData* stageData(const std::string& which, std::string& error) {
  static std::map<std::string, StageData> cache;
  if (auto it = cache.find(which); it != cache.end()) return &it->second;
  const test::BenchAsset& b = test::loadBenchAsset(which);
  if (!b.rig) {
    error = b.error;
    return nullptr;
  }
  StageData& d = cache[which];
  d.rig = b.rig.get();
  d.skeleton = &b.rig->skeleton();
  d.joints = d.skeleton->jointCount();
  for (const std::string& name : b.clips) d.clips.push_back(b.rig->findClip(name).get());
  const std::size_t all = d.joints * kCharacters;
  for (auto& p : d.poses) p.resize(all);
  d.out.resize(all);
  d.model.resize(all);
  d.palette.resize(all);
  d.cursors.resize(kCharacters);
  for (int c = 0; c < kCharacters; ++c) {
    d.cursors[static_cast<std::size_t>(c)].reset(d.clips[0]->clip);
    for (int l = 0; l < 3; ++l) sampleClip(d.clips[static_cast<std::size_t>(l)]->clip, d.time(l, c), d.skeleton->restPose, d.pose(l, c));
    localToModel(*d.skeleton, d.pose(0, c), d.models(c));
  }
  return &d;
}

template <class F>
void perJoint(benchmark::State& state, const std::string& which, F&& body) {
  std::string error;
  StageData* d = stageData(which, error);
  if (!d) {
    state.SkipWithError(("cannot load test data: " + error).c_str());
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    for (int c = 0; c < kCharacters; ++c) body(*d, c);
    benchmark::ClobberMemory();
  }
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
  state.counters["ns_per_joint"] = ns / (static_cast<double>(state.iterations()) * kCharacters * static_cast<double>(d->joints));
  state.counters["joints"] = static_cast<double>(d->joints);
}

const float kWeights[3] = {0.5f, 0.3f, 0.2f};

void sampleStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    sampleAnimationClip(*d.clips[0], d.time(0, c), false, d.result(c), &d.cursors[static_cast<std::size_t>(c)]);
  });
}

void sampleFloatStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    sampleClip(d.clips[0]->clip, d.time(0, c), d.skeleton->restPose, d.result(c), &d.cursors[static_cast<std::size_t>(c)]);
  });
}

void blendStage(benchmark::State& state, const std::string& which) {
  BlendAccumulator acc;
  perJoint(state, which, [&acc](StageData& d, int c) {
    acc.reset(d.joints);
    for (int l = 0; l < 3; ++l) acc.addNormal(d.pose(l, c % 8), kWeights[l], {}, d.skeleton->restPose);
    acc.finish(d.skeleton->restPose, d.result(c));
  });
}

void blendReferenceStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    const BlendLayer layers[3] = {
        {d.pose(0, c % 8), kWeights[0]}, {d.pose(1, c % 8), kWeights[1]}, {d.pose(2, c % 8), kWeights[2]}};
    blendPoses(layers, d.skeleton->restPose, d.result(c));
  });
}

void blendOverStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    std::memcpy(d.result(c).data(), d.pose(0, c % 8).data(), d.joints * sizeof(Transform));
    blendOver(d.result(c), d.pose(1, c % 8), 0.4f, {});
  });
}

void blendOverAcosStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    std::memcpy(d.result(c).data(), d.pose(0, c % 8).data(), d.joints * sizeof(Transform));
    const std::span<Transform> out = d.result(c);
    const std::span<const Transform> layer = d.pose(1, c % 8);
    for (std::size_t j = 0; j < out.size(); ++j) {
      out[j].translation = glm::mix(out[j].translation, layer[j].translation, 0.4f);
      out[j].scale = glm::mix(out[j].scale, layer[j].scale, 0.4f);
      out[j].rotation = test::slerpAcos(out[j].rotation, layer[j].rotation, 0.4f);
    }
  });
}

void localToModelStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) { localToModel(*d.skeleton, d.pose(0, c), d.models(c)); });
}

void localToModelScalarStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) { localToModelScalar(*d.skeleton, d.pose(0, c), d.models(c)); });
}

void paletteStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) { skinningPalette(d.models(c), d.skeleton->inverseBind, d.palettes(c)); });
}

void localToModelAndPaletteStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    localToModelAndPalette(*d.skeleton, d.pose(0, c), d.models(c), d.palettes(c), &d.rig->paletteBasis());
  });
}

void localToModelAndPaletteSse2Stage(benchmark::State& state, const std::string& which) {
  setSimdPath(SimdPath::Baseline);
  localToModelAndPaletteStage(state, which);
  setSimdPath(SimdPath::Auto);
}

void localToModelAndPalettePortableStage(benchmark::State& state, const std::string& which) {
  setSimdPath(SimdPath::Portable);  // the AVX build where the CPU has it: the baseline's bits
  localToModelAndPaletteStage(state, which);
  setSimdPath(SimdPath::Auto);
}

void memcpyStage(benchmark::State& state, const std::string& which) {
  perJoint(state, which, [](StageData& d, int c) {
    // Copies a character's model matrices over its palette and back: the bytes the frame writes.
    std::memcpy(d.palettes(c).data(), d.models(c).data(), d.joints * sizeof(glm::mat4));
    std::memcpy(d.result(c).data(), d.pose(0, c).data(), d.joints * sizeof(Transform));
  });
}

}  // namespace

#define MARIONETTE_STAGE(fn, name)                                                                            \
  BENCHMARK_CAPTURE(fn, Pab, std::string("Pab"))->Name("Stage/" name "/Pab")->Unit(benchmark::kMicrosecond); \
  BENCHMARK_CAPTURE(fn, Robot, std::string("RobotExpressive"))                                                \
      ->Name("Stage/" name "/RobotExpressive")                                                                \
      ->Unit(benchmark::kMicrosecond)
MARIONETTE_STAGE(sampleStage, "Sample");
MARIONETTE_STAGE(sampleFloatStage, "SampleFloat");
MARIONETTE_STAGE(blendStage, "Blend3");
MARIONETTE_STAGE(blendReferenceStage, "Blend3Reference");
MARIONETTE_STAGE(blendOverStage, "BlendOver");
MARIONETTE_STAGE(blendOverAcosStage, "BlendOverAcos");
MARIONETTE_STAGE(localToModelStage, "LocalToModel");
MARIONETTE_STAGE(localToModelScalarStage, "LocalToModelScalar");
MARIONETTE_STAGE(paletteStage, "Palette");
MARIONETTE_STAGE(localToModelAndPaletteStage, "LocalToModelAndPalette");
MARIONETTE_STAGE(localToModelAndPaletteSse2Stage, "LocalToModelAndPaletteSSE2");
MARIONETTE_STAGE(localToModelAndPalettePortableStage, "LocalToModelAndPalettePortable");
MARIONETTE_STAGE(memcpyStage, "Memcpy");
