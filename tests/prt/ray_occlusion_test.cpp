// Occlusion rays: Embree against our BVH, and both against geometry with known answers.
#include "marionette/prt/ray_occlusion.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cstdio>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <random>
#include <thread>
#include <utility>

#include "marionette/io/import.hpp"
#include "ray_test_util.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::prt;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Both tracers, built on the same mesh, each with its own diagnostics.
struct Tracers {
  Diagnostics embreeDiagnostics, bvhDiagnostics;
  std::unique_ptr<OcclusionTracer> embree, bvh;
  explicit Tracers(const TransferMesh& mesh, EmbreeOcclusionOptions options = {})
      : embree(makeEmbreeOcclusion(mesh, embreeDiagnostics, options)), bvh(makeBvhOcclusion(mesh, bvhDiagnostics)) {}
  [[nodiscard]] std::array<const OcclusionTracer*, 2> both() const { return {embree.get(), bvh.get()}; }
};

bool occluded(const OcclusionTracer& tracer, const OcclusionRay& ray) {
  std::uint8_t out = 7;
  tracer.occluded({&ray, 1}, {&out, 1});
  return out != 0;
}

// Subdivided icosahedron on the unit sphere: convex, closed, shared vertices.
TransferMesh icosphere(int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  TransferMesh m;
  m.positions = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (glm::vec3& p : m.positions) p = glm::normalize(p);
  m.indices = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
               3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = midpoints.try_emplace(key, static_cast<std::uint32_t>(m.positions.size()));
      if (added) m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
      return it->second;
    };
    std::vector<std::uint32_t> finer;
    for (std::size_t f = 0; f < m.indices.size(); f += 3) {
      const std::uint32_t a = m.indices[f], b = m.indices[f + 1], c = m.indices[f + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    m.indices = std::move(finer);
  }
  m.normals = m.positions;
  m.primitiveVertexOffset = {0};
  return m;
}

TransferMesh oneTriangle() {
  TransferMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.indices = {0, 1, 2};
  m.primitiveVertexOffset = {0};
  return m;
}

}  // namespace

// A ray at a triangle hits it; a segment ending short of it, or starting past it, does not.
TEST(RayOcclusion, KnownOccluder) {
  Tracers tracers(oneTriangle());
  ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
  EXPECT_TRUE(tracers.embreeDiagnostics.items.empty()) << tracers.embreeDiagnostics.format();
  for (const OcclusionTracer* tracer : tracers.both()) {
    SCOPED_TRACE(tracer->name());
    const glm::vec3 target(0.25f, 0.25f, 0.0f), origin(0.25f, 0.25f, 2.0f);
    const glm::vec3 down(0, 0, -1);
    EXPECT_TRUE(occluded(*tracer, {origin, 0.0f, down, kInf}));
    EXPECT_TRUE(occluded(*tracer, {origin, 0.0f, down, 2.1f}));
    EXPECT_FALSE(occluded(*tracer, {origin, 0.0f, down, 1.9f})) << "tfar short of the hit";
    EXPECT_FALSE(occluded(*tracer, {origin, 2.1f, down, kInf})) << "tnear past the hit";
    EXPECT_TRUE(occluded(*tracer, {origin, 1.9f, down, 2.1f}));
    // From behind (both sides count), with a direction that is not unit (t scales with it).
    EXPECT_TRUE(occluded(*tracer, {target - glm::vec3(0, 0, 1), 0.0f, glm::vec3(0, 0, 2), 0.6f}));
    EXPECT_FALSE(occluded(*tracer, {target - glm::vec3(0, 0, 1), 0.0f, glm::vec3(0, 0, 2), 0.4f}));
    EXPECT_FALSE(occluded(*tracer, {origin, 0.0f, glm::normalize(glm::vec3(1, 1, -0.1f)), kInf})) << "misses";
    EXPECT_FALSE(occluded(*tracer, {glm::vec3(0.9f, 0.9f, 2.0f), 0.0f, down, kInf})) << "past the hypotenuse";
    // Rays that cannot be traced are reported unoccluded, never crash.
    EXPECT_FALSE(occluded(*tracer, {glm::vec3(kNaN), 0.0f, down, kInf}));
    EXPECT_FALSE(occluded(*tracer, {origin, 0.0f, glm::vec3(0.0f), kInf}));
    EXPECT_FALSE(occluded(*tracer, {origin, 3.0f, down, 1.0f})) << "tnear > tfar";
    EXPECT_FALSE(occluded(*tracer, {origin, 0.0f, down, kNaN}));
  }
}

// Convex: from every vertex, offset along the geometric normal, no ray into that normal's
// hemisphere can hit the sphere.
TEST(RayOcclusion, ConvexMeshOccludesNothing) {
  const TransferMesh sphere = icosphere(3);
  ASSERT_EQ(sphere.positions.size(), 642u);
  ASSERT_EQ(sphere.indices.size(), 3u * 1280u);
  Tracers tracers(sphere);
  ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
  const std::vector<glm::vec3> normals = geometricVertexNormals(sphere);
  const float offset = rayOriginOffset(sphere);
  std::mt19937 rng(3);
  std::vector<OcclusionRay> rays(256);
  std::vector<std::uint8_t> hit(rays.size());
  std::size_t embreeHits = 0, bvhHits = 0;
  for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
    prt::test::hemisphereRays(sphere.positions[v], normals[v], offset, rng, rays);
    tracers.embree->occluded(rays, hit);
    for (std::uint8_t h : hit) embreeHits += h;
    tracers.bvh->occluded(rays, hit);
    for (std::uint8_t h : hit) bvhHits += h;
  }
  EXPECT_EQ(embreeHits, 0u);
  EXPECT_EQ(bvhHits, 0u);

  // From just inside, every ray is occluded (so that "0 occluded" above is not "never anything").
  std::size_t inward = 0, inwardHits = 0;
  for (std::size_t v = 0; v < sphere.positions.size(); v += 16) {
    prt::test::hemisphereRays(sphere.positions[v], -normals[v], offset, rng, rays);
    for (const OcclusionTracer* tracer : tracers.both()) {
      tracer->occluded(rays, hit);
      for (std::uint8_t h : hit) inwardHits += h;
      inward += rays.size();
    }
  }
  EXPECT_EQ(inwardHits, inward);
}

// Embree against the BVH on a real character: the same answer for at least 99.9 % of rays.
TEST(RayOcclusion, EmbreeAgreesWithBvhOnRobotExpressive) {
  const std::string path = marionette::test::sharedAsset("characters/RobotExpressive.glb");
  MARIONETTE_REQUIRE_FILE(path);
  ImportResult imported = importAsset(path);
  ASSERT_TRUE(imported.ok()) << imported.diagnostics.format();
  // As stored (bind space, 1/100 scale) and skinned to the rest pose (model space, limbs bent),
  // each with and without Embree's robust flag.
  for (auto [space, robust] : {std::pair{SkinnedSpace::AsStored, false}, std::pair{SkinnedSpace::AsStored, true},
                               std::pair{SkinnedSpace::RestPose, false}, std::pair{SkinnedSpace::RestPose, true}}) {
    const char* spaceName = space == SkinnedSpace::AsStored ? "as stored" : "rest pose";
    SCOPED_TRACE(std::string(spaceName) + (robust ? ", robust" : ""));
    Diagnostics d;
    const TransferMesh mesh = bindPoseMesh(*imported.asset, d, {.skinnedSpace = space, .poseModel = {}});
    ASSERT_TRUE(d.ok()) << d.format();
    const std::vector<glm::vec3> normals = geometricVertexNormals(mesh);
    const float offset = rayOriginOffset(mesh);
    Tracers tracers(mesh, {.robust = robust});
    ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
    ASSERT_TRUE(tracers.embreeDiagnostics.ok() && tracers.bvhDiagnostics.ok());

    // 28 rays from every vertex: ~198k rays over the whole body.
    std::mt19937 rng(7);
    std::vector<OcclusionRay> rays(28);
    std::vector<std::uint8_t> a(rays.size()), b(rays.size());
    std::size_t total = 0, occludedCount = 0, disagree = 0, unstable = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      prt::test::hemisphereRays(mesh.positions[v], normals[v], offset, rng, rays);
      tracers.embree->occluded(rays, a);
      tracers.bvh->occluded(rays, b);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        ++total;
        occludedCount += b[i];
        if (a[i] == b[i]) continue;
        ++disagree;
        // A disagreement should be a ray on a knife edge: one whose answer flips when its
        // direction moves by 1e-4 radians. A stable one means a tracer is plainly wrong.
        const glm::vec3 dir = rays[i].direction;
        const glm::vec3 side = glm::normalize(glm::cross(dir, std::abs(dir.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
        const glm::vec3 up = glm::cross(dir, side);
        bool flips = false;
        for (const glm::vec3& nudge : {side, -side, up, -up}) {
          OcclusionRay moved = rays[i];
          moved.direction = glm::normalize(dir + 1e-4f * nudge);
          flips = flips || occluded(*tracers.bvh, moved) != (b[i] != 0);
        }
        unstable += flips ? 1 : 0;
      }
    }
    std::printf("%s, embree (%s) vs bvh: %zu rays, %zu occluded (%.1f %%), %zu disagree (%.4f %%), %zu of them on a knife edge\n",
                spaceName, robust ? "robust" : "default", total, occludedCount, 100.0 * static_cast<double>(occludedCount) / static_cast<double>(total),
                disagree, 100.0 * static_cast<double>(disagree) / static_cast<double>(total), unstable);
    EXPECT_GE(total, 190000u);
    EXPECT_GT(occludedCount, total / 20) << "a character shadows itself: some rays must be occluded";
    EXPECT_LE(disagree * 1000, total) << "more than 0.1 % disagreement";
    EXPECT_EQ(unstable, disagree) << "disagreements on rays that are not grazing anything";
  }
}

// Every Embree ray mode gives the same answers as the default one.
TEST(RayOcclusion, EmbreeModesAgree) {
  const TransferMesh sphere = icosphere(2);
  std::mt19937 rng(11);
  std::vector<OcclusionRay> rays(1000);  // not a multiple of 8 or 16: partial packets
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  for (OcclusionRay& r : rays) {
    r = {glm::vec3(u(rng), u(rng), u(rng)), 0.0f, glm::vec3(u(rng), u(rng), u(rng)), std::abs(u(rng))};
  }
  rays[5].origin.x = kNaN;  // an untraceable ray in the middle of a packet
  Diagnostics d;
  auto reference = makeBvhOcclusion(sphere);
  std::vector<std::uint8_t> expected(rays.size()), got(rays.size());
  reference->occluded(rays, expected);
  std::size_t hits = 0;
  for (std::uint8_t h : expected) hits += h;
  EXPECT_GT(hits, 100u);
  EXPECT_LT(hits, 900u);
  for (EmbreeRayMode mode : {EmbreeRayMode::Single, EmbreeRayMode::Packet8, EmbreeRayMode::Packet16,
                             EmbreeRayMode::StreamCoherent, EmbreeRayMode::StreamIncoherent}) {
    SCOPED_TRACE(static_cast<int>(mode));
    auto tracer = makeEmbreeOcclusion(sphere, d, {.mode = mode});
    ASSERT_TRUE(tracer) << d.format();
    std::fill(got.begin(), got.end(), std::uint8_t{9});
    tracer->occluded(rays, got);
    EXPECT_EQ(got, expected);
  }
}

// Many threads at once on one tracer give what one thread gives.
TEST(RayOcclusion, ConcurrentCallsAgree) {
  const TransferMesh sphere = icosphere(2);
  Tracers tracers(sphere);
  ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
  std::mt19937 rng(5);
  std::vector<OcclusionRay> rays(4096);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (OcclusionRay& r : rays) r = {glm::vec3(u(rng), u(rng), u(rng)), 0.0f, glm::vec3(u(rng), u(rng), u(rng)), kInf};
  for (const OcclusionTracer* tracer : tracers.both()) {
    std::vector<std::uint8_t> serial(rays.size());
    tracer->occluded(rays, serial);
    std::array<std::vector<std::uint8_t>, 4> parallel;
    std::vector<std::thread> threads;
    for (auto& out : parallel) {
      out.resize(rays.size());
      threads.emplace_back([&, tracer] {
        for (int repeat = 0; repeat < 8; ++repeat) tracer->occluded(rays, out);
      });
    }
    for (std::thread& t : threads) t.join();
    for (const auto& out : parallel) EXPECT_EQ(out, serial) << tracer->name();
  }
}

// Bad meshes are reported and traced as far as they can be; never a crash.
TEST(RayOcclusion, BadMeshesAreReported) {
  const OcclusionRay down{glm::vec3(0.25f, 0.25f, 1.0f), 0.0f, glm::vec3(0, 0, -1), kInf};
  {  // empty
    Tracers tracers(TransferMesh{});
    ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
    EXPECT_TRUE(tracers.embreeDiagnostics.hasWarnings());
    EXPECT_TRUE(tracers.bvhDiagnostics.hasWarnings());
    for (const OcclusionTracer* tracer : tracers.both()) EXPECT_FALSE(occluded(*tracer, down)) << tracer->name();
  }
  {  // an out-of-range index: that triangle is dropped, the good one still occludes
    TransferMesh m = oneTriangle();
    m.indices.insert(m.indices.end(), {0, 1, 3});
    m.indices.push_back(2);  // and a stray index
    Tracers tracers(m);
    ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
    std::printf("%s%s", tracers.embreeDiagnostics.format().c_str(), tracers.bvhDiagnostics.format().c_str());
    EXPECT_FALSE(tracers.embreeDiagnostics.ok());
    EXPECT_FALSE(tracers.bvhDiagnostics.ok());
    EXPECT_NE(tracers.bvhDiagnostics.format().find("index past"), std::string::npos);
    for (const OcclusionTracer* tracer : tracers.both()) EXPECT_TRUE(occluded(*tracer, down)) << tracer->name();
  }
  {  // a NaN position: its triangle is dropped
    TransferMesh m = oneTriangle();
    m.positions.push_back({0.5f, kNaN, 0.0f});
    m.normals.push_back({0, 0, 1});
    m.indices.insert(m.indices.end(), {0, 1, 3});
    Tracers tracers(m);
    ASSERT_TRUE(tracers.embree) << tracers.embreeDiagnostics.format();
    EXPECT_NE(tracers.embreeDiagnostics.format().find("non-finite"), std::string::npos);
    EXPECT_NE(tracers.bvhDiagnostics.format().find("non-finite"), std::string::npos);
    for (const OcclusionTracer* tracer : tracers.both()) EXPECT_TRUE(occluded(*tracer, down)) << tracer->name();
  }
  {  // only NaN: nothing left to trace
    TransferMesh m = oneTriangle();
    m.positions[0] = glm::vec3(kNaN);
    Tracers tracers(m);
    ASSERT_TRUE(tracers.embree);
    for (const OcclusionTracer* tracer : tracers.both()) EXPECT_FALSE(occluded(*tracer, down)) << tracer->name();
  }
  {  // span sizes that differ: only the shorter is handled
    Tracers tracers(oneTriangle());
    const std::array<OcclusionRay, 2> rays{down, down};
    std::array<std::uint8_t, 1> out{0};
    for (const OcclusionTracer* tracer : tracers.both()) {
      tracer->occluded(rays, out);
      EXPECT_EQ(out[0], 1) << tracer->name();
    }
  }
}
