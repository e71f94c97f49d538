// Visibility rays for shadowed transfer: does a ray hit any triangle of the mesh?
// Two tracers behind one interface: Embree (fast, the production path) and a small BVH of our
// own (the test oracle for Embree, and a fallback where Embree is unavailable).
#pragma once
#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <span>

#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::prt {

// 32 bytes, no padding: a batch is one contiguous array.
struct OcclusionRay {
  glm::vec3 origin;
  float tnear;
  glm::vec3 direction;  // need not be unit; t is in units of its length
  float tfar;
};

class OcclusionTracer {
 public:
  virtual ~OcclusionTracer() = default;
  // occluded[i] = 1 when ray i hits any triangle at t in [tnear, tfar], else 0 (both sides of a
  // triangle count). Handles min(rays.size(), occluded.size()) rays. A negative tnear counts as
  // 0; a ray with a non-finite or zero direction, a non-finite origin, or tnear > tfar (or NaN)
  // is never occluded.
  // Thread-safe: many threads may call it at once. No heap allocation per call.
  virtual void occluded(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded) const noexcept = 0;
  [[nodiscard]] virtual const char* name() const noexcept = 0;
};

// How the Embree tracer hands rays to Embree. All give the same answers; the default is the
// fastest measured for one vertex's hemisphere batch (see embree_occlusion.cpp for figures).
enum class EmbreeRayMode {
  Single,            // rtcOccluded1 per ray
  Packet8,           // rtcOccluded8, SoA packets of 8
  Packet16,          // rtcOccluded16, SoA packets of 16
  StreamCoherent,    // rtcOccluded1M, RTC_INTERSECT_CONTEXT_FLAG_COHERENT
  StreamIncoherent,  // rtcOccluded1M, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
  Best = StreamIncoherent,
};

struct EmbreeOcclusionOptions {
  EmbreeRayMode mode = EmbreeRayMode::Best;
  // RTC_SCENE_FLAG_ROBUST: no arithmetic shortcuts that can let a ray slip through a shared
  // edge. Off by default: measured about 25 % slower, and on RobotExpressive neither setting
  // disagrees with our BVH on any of 200k test rays.
  bool robust = false;
};

// Embree 3 (one device, a scene with one triangle geometry, RTC_BUILD_QUALITY_HIGH).
// Triangles with an out-of-range index or a non-finite corner are dropped with an error; an
// empty mesh gives a warning and a tracer that never reports occlusion. Returns nullptr with an
// error in `diagnostics` when Embree fails (the device's error message included).
[[nodiscard]] std::unique_ptr<OcclusionTracer> makeEmbreeOcclusion(const TransferMesh& mesh, Diagnostics& diagnostics,
                                                                   const EmbreeOcclusionOptions& options = {});

// Our own BVH (binned SAH, Moller-Trumbore, any-hit traversal), single precision. Bad
// triangles are dropped as for Embree; the overload without diagnostics drops them silently.
[[nodiscard]] std::unique_ptr<OcclusionTracer> makeBvhOcclusion(const TransferMesh& mesh, Diagnostics& diagnostics);
[[nodiscard]] std::unique_ptr<OcclusionTracer> makeBvhOcclusion(const TransferMesh& mesh);

}  // namespace marionette::prt
