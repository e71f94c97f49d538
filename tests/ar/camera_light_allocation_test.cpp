// Heap allocations per CameraLightEstimator::addFrame: none, from the first frame on (the grid is
// fixed-size arrays inside the object; only the constructor allocates, for a moment). A program
// of its own, since it replaces the global operator new (as tests/scene/allocation_test.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "camera_sweep.hpp"
#include "marionette_ar/camera_light_estimate.hpp"

namespace {
std::atomic<long> g_news{0};
void* counted(std::size_t n) {
  g_news.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

TEST(CameraLightAllocation, AddFrameAllocatesNothing) {
  using namespace marionette;
  constexpr int w = 320, h = 240;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  ar::CameraLightEstimator estimator;
  ar::CameraLightFrame frame;
  frame.image = {rgb.data(), w, h, 0};
  frame.intrinsics = ar::PinholeIntrinsics::fromFovY(w, h, 45.0);
  const long before = g_news.load();
  for (int k = 0; k < 200; ++k) {
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>((i + static_cast<std::size_t>(k) * 31) % 256);
    frame.cameraToWorld = glm::dmat4(test::sweepOrientation(test::kSweepPaths[2], k / 15.0));
    frame.timeSeconds = k / 15.0;
    frame.exposure = 1.0 + 0.5 * (k % 3);
    ASSERT_EQ(estimator.addFrame(frame), ar::LightFrameResult::Accepted);
    (void)ar::cameraMatchedRadiance(estimator.estimate().radiance, frame.exposure, ar::WhiteBalance::GrayWorld);
  }
  frame.cameraToWorld.reset();  // and the rejected frames
  EXPECT_EQ(estimator.addFrame(frame), ar::LightFrameResult::NoPose);
  EXPECT_EQ(g_news.load() - before, 0) << "allocations in 200 frames";
  EXPECT_GT(estimator.estimate().seenFraction, 0.5);
}
