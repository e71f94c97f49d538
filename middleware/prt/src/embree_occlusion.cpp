// Occlusion rays through Embree 3.
//
// Ray modes measured on RobotExpressive (bind pose as stored, 3,237 triangles), 1024 uniform
// hemisphere rays from every 7th of its 7,214 vertices (1.03 M rays, 51 % occluded), one thread:
//   taskset -c 1 marionette_bench --benchmark_filter=Prt/ --benchmark_repetitions=3
// rays/s, median of 3, CPU time; the 2-vCPU AMD EPYC VM at 2.1 GHz (Embree picks its AVX-512
// kernels at run time), the other vCPU mostly busy with a compile. The quietest run, then the
// range over five runs:
//   rtcOccluded1M, INCOHERENT     17.5 M/s  (13.9 - 18.0)   <- the default
//   rtcOccluded16 (SoA packets)   13.6 M/s  (11.6 - 13.6)
//   rtcOccluded8                  11.9 M/s  ( 9.9 - 11.9)
//   rtcOccluded1 loop              9.6 M/s  ( 9.0 -  9.6)
//   rtcOccluded1M, COHERENT        7.1 M/s  ( 5.7 -  7.1)   (presumably: a hemisphere is no beam)
//   RTC_SCENE_FLAG_ROBUST: 1M incoherent 13.9 M/s (10.9 - 13.9), rtcOccluded1 7.9 M/s: -20 %
//   RTC_SCENE_FLAG_COMPACT         about -35 %      (1M incoherent 10.6 M/s)
//   RTC_BUILD_QUALITY_MEDIUM       same as HIGH within noise (HIGH kept)
//   FTZ/DAZ set around the calls   no change (no denormals here); not done
//   stream chunk of 64 / 256 / 1024 rays: no difference beyond noise; 256 (12 KB of stack)
// Our BVH does 3.2 - 4.2 M/s on the same rays. At ~17 M/s per core, RobotExpressive's 7.4 M
// rays (7,214 vertices x 1024) would take about 0.2 s on 2 cores (extrapolated, not measured).
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "marionette/prt/ray_occlusion.hpp"
#include "traceable_geometry.hpp"

namespace marionette::prt {

namespace {

const char* errorName(RTCError code) noexcept {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognized error code";
}

constexpr const char* kFile = "embree occlusion";

// Where the device's error callback reports while the scene is built.
void reportError(void* userPtr, RTCError code, const char* message) {
  auto* diagnostics = static_cast<Diagnostics*>(userPtr);
  diagnostics->error(kFile, std::string("Embree ") + errorName(code) + ": " + (message ? message : "(no message)"));
}

constexpr float kInf = std::numeric_limits<float>::infinity();

template <class Packet>
void setLane(Packet& p, int lane, const OcclusionRay& r, float tnear, unsigned id) noexcept {
  const auto k = static_cast<std::size_t>(lane);
  p.org_x[k] = r.origin.x;
  p.org_y[k] = r.origin.y;
  p.org_z[k] = r.origin.z;
  p.tnear[k] = tnear;
  p.dir_x[k] = r.direction.x;
  p.dir_y[k] = r.direction.y;
  p.dir_z[k] = r.direction.z;
  p.time[k] = 0.0f;
  p.tfar[k] = r.tfar;
  p.mask[k] = ~0u;
  p.id[k] = id;
  p.flags[k] = 0;
}

class EmbreeOcclusion final : public OcclusionTracer {
 public:
  EmbreeOcclusion(RTCDevice device, RTCScene scene, EmbreeRayMode mode) : device_(device), scene_(scene), mode_(mode) {}
  ~EmbreeOcclusion() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeOcclusion(const EmbreeOcclusion&) = delete;
  EmbreeOcclusion& operator=(const EmbreeOcclusion&) = delete;

  void occluded(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded) const noexcept override {
    const std::size_t n = std::min(rays.size(), occluded.size());
    switch (mode_) {
      case EmbreeRayMode::Single: return single(rays.first(n), occluded);
      case EmbreeRayMode::Packet8: return packets<RTCRay8, 8>(rays.first(n), occluded);
      case EmbreeRayMode::Packet16: return packets<RTCRay16, 16>(rays.first(n), occluded);
      case EmbreeRayMode::StreamCoherent: return stream(rays.first(n), occluded, RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
      case EmbreeRayMode::StreamIncoherent:
        return stream(rays.first(n), occluded, RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
    }
  }
  const char* name() const noexcept override { return "embree"; }

 private:
  RTCDevice device_;
  RTCScene scene_;
  EmbreeRayMode mode_;

  void single(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded) const noexcept {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      float tnear = 0.0f;
      if (!detail::traceable(rays[i], tnear)) {
        occluded[i] = 0;
        continue;
      }
      const OcclusionRay& r = rays[i];
      RTCRay ray{r.origin.x, r.origin.y, r.origin.z, tnear, r.direction.x, r.direction.y, r.direction.z,
                 0.0f,       r.tfar,     ~0u,        0u,    0u};
      rtcOccluded1(scene_, &context, &ray);
      occluded[i] = ray.tfar == -kInf;  // Embree marks a hit by setting tfar to -infinity
    }
  }

  // SoA packets on the stack; untraceable rays are masked off. Embree loads the packet and the
  // valid mask with aligned vector loads: both must be aligned to the packet's width (RTCRay8/16
  // carry their own alignment; the mask needs it said; unaligned, it crashed under ASan).
  template <class Packet, int Width>
  void packets(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded) const noexcept {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    Packet packet{};  // masked-off lanes are still loaded: keep them defined
    alignas(sizeof(int) * Width) std::array<int, Width> valid;
    for (std::size_t begin = 0; begin < rays.size(); begin += Width) {
      for (int lane = 0; lane < Width; ++lane) {
        const std::size_t i = begin + static_cast<std::size_t>(lane);
        float tnear = 0.0f;
        const bool use = i < rays.size() && detail::traceable(rays[i], tnear);
        valid[static_cast<std::size_t>(lane)] = use ? -1 : 0;
        if (use) setLane(packet, lane, rays[i], tnear, static_cast<unsigned>(i));
      }
      if constexpr (Width == 8)
        rtcOccluded8(valid.data(), scene_, &context, &packet);
      else
        rtcOccluded16(valid.data(), scene_, &context, &packet);
      for (int lane = 0; lane < Width && begin + static_cast<std::size_t>(lane) < rays.size(); ++lane) {
        const auto k = static_cast<std::size_t>(lane);
        occluded[begin + k] = valid[k] != 0 && packet.tfar[k] == -kInf;
      }
    }
  }

  // rtcOccluded1M over chunks copied to a stack buffer (Embree wants its RTCRay layout).
  void stream(std::span<const OcclusionRay> rays, std::span<std::uint8_t> occluded, RTCIntersectContextFlags flags) const noexcept {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = flags;
    constexpr std::size_t kChunk = 256;
    std::array<RTCRay, kChunk> buffer;
    std::array<std::uint32_t, kChunk> source;  // buffer slot -> ray index
    std::size_t i = 0;
    while (i < rays.size()) {
      unsigned used = 0;
      for (; i < rays.size() && used < kChunk; ++i) {
        float tnear = 0.0f;
        occluded[i] = 0;
        if (!detail::traceable(rays[i], tnear)) continue;
        const OcclusionRay& r = rays[i];
        buffer[used] = RTCRay{r.origin.x, r.origin.y, r.origin.z, tnear, r.direction.x, r.direction.y, r.direction.z,
                              0.0f,       r.tfar,     ~0u,        used, 0u};
        source[used++] = static_cast<std::uint32_t>(i);
      }
      if (used == 0) continue;
      rtcOccluded1M(scene_, &context, buffer.data(), used, sizeof(RTCRay));
      for (unsigned k = 0; k < used; ++k) occluded[source[k]] = buffer[k].tfar == -kInf;
    }
  }
};

}  // namespace

std::unique_ptr<OcclusionTracer> makeEmbreeOcclusion(const TransferMesh& mesh, Diagnostics& diagnostics,
                                                     const EmbreeOcclusionOptions& options) {
  const std::vector<std::uint32_t> indices = detail::traceableTriangles(mesh, &diagnostics, "embree");

  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) {
    diagnostics.error(kFile, std::string("Embree could not create a device: ") + errorName(rtcGetDeviceError(nullptr)));
    return nullptr;
  }
  const std::size_t errorsBefore = diagnostics.items.size();
  rtcSetDeviceErrorFunction(device, reportError, &diagnostics);
  const auto failed = [&] {
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE && diagnostics.items.size() == errorsBefore)
      diagnostics.error(kFile, "Embree failed without a message");
    for (std::size_t k = errorsBefore; k < diagnostics.items.size(); ++k)
      if (diagnostics.items[k].severity == Severity::Error) return true;
    return false;
  };

  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);  // spatial splits: built once, traced ~10^7 times
  if (!indices.empty()) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    const std::size_t vertexCount = mesh.positions.size();
    // Embree's own buffers (padded for its SIMD loads). Vertices no kept triangle uses may be
    // non-finite; they are zeroed so that nothing Embree reads is NaN.
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertexCount));
    auto* triangles = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), indices.size() / 3));
    if (vertices && triangles) {
      for (std::size_t v = 0; v < vertexCount; ++v) {
        const glm::vec3 p = isFinite(mesh.positions[v]) ? mesh.positions[v] : glm::vec3(0.0f);
        vertices[v * 3] = p.x;
        vertices[v * 3 + 1] = p.y;
        vertices[v * 3 + 2] = p.z;
      }
      std::copy(indices.begin(), indices.end(), triangles);
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(scene, geometry);
    }
    rtcReleaseGeometry(geometry);  // the scene holds it
  }
  rtcCommitScene(scene);
  // Diagnostics may not outlive this call: later errors (none expected from queries) go nowhere.
  const bool bad = failed();
  rtcSetDeviceErrorFunction(device, nullptr, nullptr);
  if (bad) {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return nullptr;
  }
  return std::make_unique<EmbreeOcclusion>(device, scene, options.mode);
}

}  // namespace marionette::prt
