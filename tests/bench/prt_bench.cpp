// marionette_bench: visibility rays for shadowed PRT on RobotExpressive (7,214 vertices),
// bind pose, 1024 rays per vertex over the hemisphere of its geometric normal (from every
// 7th vertex, 1,031 vertices), one thread. Counter items_per_second = rays per second.
//   Prt/EmbreeOcclusion            the default Embree tracer (the mode picked from below)
//   Prt/EmbreeOcclusion/<mode>     each Embree ray mode, and robust scenes
//   Prt/BvhOcclusion               our BVH (the test oracle), for scale
// Target: shadowed precompute (7,214 x 1024 rays plus sampling and SH) in 2 s on 2 cores,
// so well over 4 M rays/s per core for the rays alone.
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <vector>

#include "../prt/ray_test_util.hpp"
#include "marionette/io/import.hpp"
#include "marionette/prt/ray_occlusion.hpp"
#include "marionette/prt/transfer_mesh.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::prt;

namespace {

constexpr std::size_t kRaysPerVertex = 1024;
constexpr std::size_t kVertexStride = 7;

// Ray batches built once: the benchmark times tracing only.
struct Data {
  TransferMesh mesh;
  std::vector<std::vector<OcclusionRay>> batches;  // one per traced vertex
};

const Data* data(benchmark::State& state) {
  static std::unique_ptr<Data> d = []() -> std::unique_ptr<Data> {
    ImportResult imported = importAsset(marionette::test::sharedAsset("characters/RobotExpressive.glb"));
    if (!imported.ok()) return nullptr;
    auto out = std::make_unique<Data>();
    Diagnostics diagnostics;
    out->mesh = bindPoseMesh(*imported.asset, diagnostics);
    if (!diagnostics.ok()) return nullptr;
    const std::vector<glm::vec3> normals = geometricVertexNormals(out->mesh);
    const float offset = rayOriginOffset(out->mesh);
    std::mt19937 rng(1);
    for (std::size_t v = 0; v < out->mesh.positions.size(); v += kVertexStride) {
      std::vector<OcclusionRay>& batch = out->batches.emplace_back(kRaysPerVertex);
      prt::test::hemisphereRays(out->mesh.positions[v], normals[v], offset, rng, batch);
    }
    return out;
  }();
  if (!d) state.SkipWithError("RobotExpressive.glb missing or unreadable (../shared/assets)");
  return d.get();
}

void traceAll(benchmark::State& state, const Data& d, const OcclusionTracer& tracer) {
  std::vector<std::uint8_t> occluded(kRaysPerVertex);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (const auto& batch : d.batches) {
      tracer.occluded(batch, occluded);
      for (std::uint8_t o : occluded) hits += o;  // ~1 % of the time of the rays
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(d.batches.size() * kRaysPerVertex));
  state.counters["occluded_fraction"] =
      static_cast<double>(hits) / static_cast<double>(state.iterations()) / static_cast<double>(d.batches.size() * kRaysPerVertex);
}

void embree(benchmark::State& state, EmbreeOcclusionOptions options) {
  const Data* d = data(state);
  if (!d) return;
  Diagnostics diagnostics;
  auto tracer = makeEmbreeOcclusion(d->mesh, diagnostics, options);
  if (!tracer) return state.SkipWithError(diagnostics.format().c_str());
  traceAll(state, *d, *tracer);
}

void bvh(benchmark::State& state) {
  const Data* d = data(state);
  if (!d) return;
  auto tracer = makeBvhOcclusion(d->mesh);
  traceAll(state, *d, *tracer);
}

}  // namespace

BENCHMARK_CAPTURE(embree, default, EmbreeOcclusionOptions{})->Name("Prt/EmbreeOcclusion")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, single, EmbreeOcclusionOptions{.mode = EmbreeRayMode::Single})
    ->Name("Prt/EmbreeOcclusion/Single")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, packet8, EmbreeOcclusionOptions{.mode = EmbreeRayMode::Packet8})
    ->Name("Prt/EmbreeOcclusion/Packet8")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, packet16, EmbreeOcclusionOptions{.mode = EmbreeRayMode::Packet16})
    ->Name("Prt/EmbreeOcclusion/Packet16")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, streamCoherent, EmbreeOcclusionOptions{.mode = EmbreeRayMode::StreamCoherent})
    ->Name("Prt/EmbreeOcclusion/StreamCoherent")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, streamIncoherent, EmbreeOcclusionOptions{.mode = EmbreeRayMode::StreamIncoherent})
    ->Name("Prt/EmbreeOcclusion/StreamIncoherent")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, singleRobust, EmbreeOcclusionOptions{.mode = EmbreeRayMode::Single, .robust = true})
    ->Name("Prt/EmbreeOcclusion/SingleRobust")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(embree, robust, EmbreeOcclusionOptions{.robust = true})
    ->Name("Prt/EmbreeOcclusion/Robust")->Unit(benchmark::kMillisecond);
BENCHMARK(bvh)->Name("Prt/BvhOcclusion")->Unit(benchmark::kMillisecond);
