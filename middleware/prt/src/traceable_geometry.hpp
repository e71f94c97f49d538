// What both occlusion tracers accept from a TransferMesh and from a ray, checked in one place
// so that Embree and the BVH agree on bad input.
#pragma once
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "marionette/core/finite.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/ray_occlusion.hpp"
#include "marionette/prt/transfer_mesh.hpp"

namespace marionette::prt::detail {

// The mesh's triangles (3 indices each) whose indices are in range and whose corners are
// finite. Dropped triangles are counted in one error; an empty result is a warning. `tracer`
// names the caller in the messages. `diagnostics` may be null (then nothing is reported).
std::vector<std::uint32_t> traceableTriangles(const TransferMesh& mesh, Diagnostics* diagnostics, const char* tracer);


// A ray can be traced when its origin and (non-zero) direction are finite and
// tnear <= tfar (tfar may be +infinity). A negative tnear is taken as 0 in both tracers (a
// segment starts at its origin). Anything else is never occluded.
inline bool traceable(const OcclusionRay& r, float& tnear) noexcept {
  tnear = r.tnear > 0.0f ? r.tnear : 0.0f;
  return isFinite(r.origin) && isFinite(r.direction) &&
         (r.direction.x != 0.0f || r.direction.y != 0.0f || r.direction.z != 0.0f) && std::isfinite(tnear) &&
         tnear <= r.tfar;  // false for a NaN tfar
}

}  // namespace marionette::prt::detail
