// Heap allocations per update() of the camera trackers after warm-up: how many, and that
// the count per frame stays flat (a buffer that grows, or a map that keeps adding, would
// show as a count that rises over the frames).
//
// Two counters:
//  - operator new (replaced below, as in allocation_test.cpp): every C++ allocation of the
//    program, ours and the std::vector / cv::Ptr / cv::Mat-header ones inside OpenCV.
//  - malloc (only when the build has no sanitizer; the sanitizers own malloc): malloc,
//    calloc, realloc and the aligned variants, defined in this program and forwarding to
//    glibc's __libc_malloc etc. Definitions in the executable interpose for the shared
//    libraries too, so this sees OpenCV's cv::fastMalloc (every cv::Mat's pixels) and
//    libapriltag's C allocations. operator new here calls __libc_malloc directly: the two
//    counts do not overlap, and the heap is glibc's throughout.
//
// The markerless tracker allocates nothing per frame once warm (asserted, over a sharp and a
// blurred orbit), nor does its occlusion mask once made (asserted). The AprilTag tracker cannot say as much: libapriltag allocates its working
// images, quads and detections on every call (malloc/calloc), and the pose refinement uses
// OpenCV's solvePnP; the assertions there are that the count is bounded (ceilings below) and
// exactly the same for the same frame every time, and that our code's own share is zero.
// Relocalization (ORB, when LOST) is not the steady path and allocates inside OpenCV. The
// counts are printed for docs/benchmarks.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "dense_alignment.hpp"
#include "homography_ransac.hpp"
#include "lucas_kanade.hpp"
#include "marionette_ar/tracking/markerless_tracker.hpp"
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "perspective_warp.hpp"
#include "planar_pose.hpp"
#include "test_data.hpp"
#include "tracking/scenario_run.hpp"
#include "tracking/stress_scenarios.hpp"
#include "tracking/visp_benchmark.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MN_UNDER_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define MN_UNDER_SANITIZER 1
#endif
#endif
#if defined(MARIONETTE_TEST_COUNT_MALLOC) && defined(__GLIBC__) && !defined(MN_UNDER_SANITIZER)
#define MN_COUNT_MALLOC 1
#else
#define MN_COUNT_MALLOC 0
#endif

namespace {
std::atomic<long> g_news{0};
std::atomic<long> g_mallocs{0};
}  // namespace

#if MN_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

// The declarations in <stdlib.h> / <malloc.h> are noexcept in C++ (__THROW).
void* malloc(std::size_t n) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t n) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, n);
}
void* realloc(void* p, std::size_t n) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
void free(void* p) noexcept { __libc_free(p); }
void* memalign(std::size_t alignment, std::size_t n) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) noexcept {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
}  // extern "C"
namespace {
void* rawAlloc(std::size_t n) { return __libc_malloc(n ? n : 1); }
void* rawAlignedAlloc(std::size_t alignment, std::size_t n) { return __libc_memalign(alignment, n ? n : 1); }
void rawFree(void* p) { __libc_free(p); }
}  // namespace
#else
namespace {
void* rawAlloc(std::size_t n) { return std::malloc(n ? n : 1); }
void* rawAlignedAlloc(std::size_t alignment, std::size_t n) {
  return std::aligned_alloc(alignment, (n + alignment - 1) / alignment * alignment);
}
void rawFree(void* p) { std::free(p); }
}  // namespace
#endif

// The executable's own code (linker-defined bounds): our static libraries, this test, and
// every template they instantiate (std::vector growth included). OpenCV, libapriltag and
// libstdc++ are shared libraries outside it (std::string's members too: libstdc++ compiles
// them as extern templates), and so is an allocation OpenCV makes for us (a cv::Mat's header
// is new-ed in libopencv_core even when our code declares the cv::Mat).
extern "C" char __executable_start;
extern "C" char etext;

namespace {
std::atomic<long> g_ownNews{0};
void countNew(const void* caller) {
  g_news.fetch_add(1, std::memory_order_relaxed);
  const auto a = reinterpret_cast<std::uintptr_t>(caller);
  if (a >= reinterpret_cast<std::uintptr_t>(&__executable_start) && a < reinterpret_cast<std::uintptr_t>(&etext))
    g_ownNews.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

// GCC cannot see that these replace the global operators together.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

// noinline: each must see its own caller's address.
__attribute__((noinline)) void* operator new(std::size_t n) {
  countNew(__builtin_return_address(0));
  if (void* p = rawAlloc(n)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void* operator new[](std::size_t n) {
  countNew(__builtin_return_address(0));
  if (void* p = rawAlloc(n)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void* operator new(std::size_t n, std::align_val_t a) {
  countNew(__builtin_return_address(0));
  if (void* p = rawAlignedAlloc(static_cast<std::size_t>(a), n)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void* operator new[](std::size_t n, std::align_val_t a) {
  countNew(__builtin_return_address(0));
  if (void* p = rawAlignedAlloc(static_cast<std::size_t>(a), n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { rawFree(p); }
void operator delete[](void* p) noexcept { rawFree(p); }
void operator delete(void* p, std::size_t) noexcept { rawFree(p); }
void operator delete[](void* p, std::size_t) noexcept { rawFree(p); }
void operator delete(void* p, std::align_val_t) noexcept { rawFree(p); }
void operator delete[](void* p, std::align_val_t) noexcept { rawFree(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { rawFree(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { rawFree(p); }

namespace {

using namespace marionette;
using namespace marionette::ar;
using namespace marionette::ar::synthetic;

ImageView view(const cv::Mat& m) { return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)}; }

struct Counts {
  long news = 0, ownNews = 0, mallocs = 0;
  Counts& operator+=(const Counts& o) {
    news += o.news, ownNews += o.ownNews, mallocs += o.mallocs;
    return *this;
  }
};
Counts now() { return {g_news.load(), g_ownNews.load(), g_mallocs.load()}; }
Counts since(const Counts& c0) {
  const Counts c1 = now();
  return {c1.news - c0.news, c1.ownNews - c0.ownNews, c1.mallocs - c0.mallocs};
}
double perFrame(long total, std::size_t frames) { return static_cast<double>(total) / static_cast<double>(frames); }

// A frame that must allocate nothing: asserted (malloc where this build counts it) and summed.
void expectNoAllocation(const Counts& used, std::size_t frame, long& news, long& mallocs) {
  EXPECT_EQ(used.news, 0) << "frame " << frame;
#if MN_COUNT_MALLOC
  EXPECT_EQ(used.mallocs, 0) << "frame " << frame;
#endif
  news += used.news;
  mallocs += used.mallocs;
}

// AprilTag's per-frame ceilings, about 1.25x what Debian 12's libapriltag 3.3 and OpenCV 4.6
// measure on the development VM (the printed figures; docs/benchmarks.md): libapriltag's
// working images, quads and detections, by malloc.
constexpr long kAprilTagMaxOwnNewPerFrame = 8;
constexpr long kAprilTagMaxNewPerFrame = 130;
constexpr long kAprilTagMaxMallocPerFrame = 8600;

TEST(TrackingAllocation, CountersSeeCppAndOpenCvAllocations) {
  const Counts c0 = now();
  cv::Mat m(64, 64, CV_8UC1);  // header new-ed and pixels cv::fastMalloc-ed inside libopencv_core
  m.setTo(1);
  auto* v = new std::vector<int>(10);  // two operator new calls from this program
  const Counts c = since(c0);
  delete v;
  EXPECT_GE(c.news, 3);
  EXPECT_EQ(c.ownNews, 2);
#if MN_COUNT_MALLOC
  EXPECT_GE(c.mallocs, 1) << "malloc is not interposed for OpenCV's shared libraries";
#else
  GTEST_LOG_(INFO) << "malloc not counted (sanitizer build or not glibc): operator new only";
#endif
}

// The markerless tracker's per-frame path allocates nothing once warm: the warp, pyramids,
// KLT, RANSAC, pose and motion blur are ours (examples/ar/tracking/src), sized at
// construction. Over a sharp orbit and over the blurred one (the template smeared, the KLT
// window grown), frames 12..35, none relocalizing. A frame that adds a keyframe allocates: the
// map grows (the floor around the target as the camera moves, at most PlanarMap::kMaxKeyframes),
// as PTAM's mapping does; such frames are few and counted apart. (36 frames: rendering them is
// most of the test's time, 60 s under the sanitizers at 60 frames.)
TEST(TrackingAllocation, MarkerlessTrackingAllocatesNothingPerFrame) {
  cv::setNumThreads(1);
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  constexpr int kFrames = 36, kWarm = 12;
  const auto rendered = synthetic::renderScenarios(renderer, kFrames, {"orbit", "blur"});
  ASSERT_EQ(rendered.size(), 2u);
  for (const auto& scenario : rendered) {
    const auto& frames = scenario.frames;
    ASSERT_EQ(frames.size(), static_cast<std::size_t>(kFrames));
    Diagnostics d;
    auto tracker = MarkerlessTracker::fromTarget(renderer.camera(), synthetic::standardTargetImage(),
                                                 synthetic::kStandardTargetWidth, MarkerlessSettings{}, d);
    ASSERT_TRUE(tracker) << d.format();
    const double fps = scenario.scenario.fps;
    // Warm-up (the first frame relocalizes; OpenCV's lazy initialisation happens here; the blur
    // scenario turns blurred at 10 %, so its blur path warms up too).
    for (int i = 0; i < kWarm; ++i) (void)tracker->update(view(frames[static_cast<std::size_t>(i)]), i / fps);
    // The rest. Nothing in this loop allocates but update() (fixed-size arrays).
    std::array<Counts, kFrames - kWarm> counts{};
    std::array<bool, kFrames - kWarm> posed{}, relocalized{}, keyframeAdded{}, grows{};
    for (int i = kWarm; i < kFrames; ++i) {
      const ImageView v = view(frames[static_cast<std::size_t>(i)]);
      const auto k = static_cast<std::size_t>(i - kWarm);
      const Counts c0 = now();
      const TrackedPose p = tracker->update(v, i / fps);
      counts[k] = since(c0);
      posed[k] = p.state != TrackingState::Lost;
      relocalized[k] = tracker->lastFrame().relocalized;
      keyframeAdded[k] = tracker->lastFrame().keyframeAdded;
      // A frame that gets the ORB features of a keyframe added earlier grows the map too.
      grows[k] = keyframeAdded[k] || tracker->lastFrame().keyframeFeatures;
    }
    Counts total;
    int keyframeFrames = 0, growingFrames = 0;
    for (std::size_t k = 0; k < counts.size(); ++k) {
      // The steady path: tracking against a keyframe, no relocalization.
      EXPECT_TRUE(posed[k]) << scenario.scenario.name << " frame " << k + kWarm;
      EXPECT_FALSE(relocalized[k]) << scenario.scenario.name << " frame " << k + kWarm;
      if (grows[k]) {
        keyframeFrames += keyframeAdded[k];
        ++growingFrames;
        EXPECT_GT(counts[k].news, 0) << "a keyframe is new memory: the count sees it";
        continue;
      }
      EXPECT_EQ(counts[k].news, 0) << scenario.scenario.name << " frame " << k + kWarm;
#if MN_COUNT_MALLOC
      EXPECT_EQ(counts[k].mallocs, 0) << scenario.scenario.name << " frame " << k + kWarm;
#endif
      total += counts[k];
    }
    // A new floor keyframe once the camera has moved 0.3 of its distance from every other one:
    // the orbit (3 deg a frame) adds 8 over its 150 frames.
    EXPECT_LE(keyframeFrames, 2) << scenario.scenario.name;
    const std::size_t steady = counts.size() - static_cast<std::size_t>(growingFrames);
    std::printf("[ markerless %s ] per update(), frames %d..%d without a new keyframe (%zu; %d added one): %.1f operator new (%.1f ours), %.1f malloc family%s\n",
                scenario.scenario.name.c_str(), kWarm, kFrames - 1, steady, keyframeFrames, perFrame(total.news, steady),
                perFrame(total.ownNews, steady), perFrame(total.mallocs, steady), MN_COUNT_MALLOC ? "" : " (not counted in this build)");
  }
}

TEST(TrackingAllocation, AprilTagPerFrameCountIsBoundedAndConstant) {
  cv::setNumThreads(1);
  const std::string file = vispBenchmarkImage();
  MARIONETTE_REQUIRE_FILE(file);
  cv::Mat rgb = cv::imread(file, cv::IMREAD_COLOR);
  ASSERT_FALSE(rgb.empty()) << file;
  cv::cvtColor(rgb, rgb, cv::COLOR_BGR2RGB);
  Diagnostics d;
  auto tracker = AprilTagTracker::create(vispBenchmarkCamera(), vispBenchmarkTagSettings(), d);
  ASSERT_TRUE(tracker) << d.format();
  const ImageView frame = view(rgb);
  for (int i = 0; i < 5; ++i) (void)tracker->update(frame, i / 30.0);

  std::array<Counts, 40> counts{};
  std::array<bool, 40> tracking{};
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const double seconds = (5.0 + static_cast<double>(k)) / 30.0;
    const Counts c0 = now();
    const TrackedPose p = tracker->update(frame, seconds);
    counts[k] = since(c0);
    tracking[k] = p.state == TrackingState::Tracking;
  }
  for (std::size_t k = 0; k < counts.size(); ++k) {
    EXPECT_TRUE(tracking[k]) << "frame " << k;
    // The same frame, the same work: exactly the same allocations every time.
    EXPECT_EQ(counts[k].news, counts[0].news) << "frame " << k;
    EXPECT_EQ(counts[k].ownNews, counts[0].ownNews) << "frame " << k;
    EXPECT_EQ(counts[k].mallocs, counts[0].mallocs) << "frame " << k;
  }
  std::printf("[ apriltag ] per update(): %ld operator new (%ld from our code), %ld malloc family%s\n",
              counts[0].news, counts[0].ownNews, counts[0].mallocs,
              MN_COUNT_MALLOC ? "" : " (not counted in this build)");
  EXPECT_LE(counts[0].ownNews, kAprilTagMaxOwnNewPerFrame);
  EXPECT_LE(counts[0].news, kAprilTagMaxNewPerFrame);
#if MN_COUNT_MALLOC
  EXPECT_GT(counts[0].mallocs, 0);  // libapriltag's working images at least
  EXPECT_LE(counts[0].mallocs, kAprilTagMaxMallocPerFrame);
#endif
}

// The markerless tracker's own primitives (perspective_warp, lucas_kanade, homography_ransac,
// planar_pose), run as its per-frame path does: the reference warped into the frame from the
// last pose (only the region KLT reads), both pyramids, KLT on 200 corners, RANSAC, the pose
// from the homography and its rms. Every buffer is sized before the loop; after two warm-up
// frames, not one allocation (operator new or malloc) per frame.
struct PrimitivesPipeline {
  static constexpr std::size_t kCorners = 200;
  cv::Matx33d k{600, 0, 319.5, 0, 600, 239.5, 0, 0, 1};
  std::vector<cv::Mat> levels;  // the reference and its pyrDown levels
  cv::Matx33d planeToReference, referenceToPlane;
  std::vector<cv::Point2f> corners, cornerPlane;
  std::uint8_t background = 128;
  cv::Mat templ = cv::Mat(480, 640, CV_8UC1);  // (not braces: cv::Mat{a, b, c} is a 3x1 matrix)
  ImagePyramid templatePyramid, framePyramid;
  LucasKanade klt;
  HomographyRansac ransac;
  std::vector<cv::Point2f> from, to, plane, inlierPlane, inlierImage;
  std::vector<std::uint8_t> status, mask;

  explicit PrimitivesPipeline(const cv::Mat& reference) {
    levels.push_back(reference);
    for (int l = 1; l < 4; ++l) {
      cv::Mat down;
      cv::pyrDown(levels.back(), down);
      levels.push_back(down);
    }
    const double mpp = synthetic::kStandardTargetWidth / reference.cols;
    planeToReference = cv::Matx33d(1 / mpp, 0, reference.cols * 0.5 - 0.5, 0, 1 / mpp, reference.rows * 0.5 - 0.5, 0, 0, 1);
    referenceToPlane = planeToReference.inv();
    cv::goodFeaturesToTrack(reference, corners, 500, 0.01, 8, cv::noArray(), 5);
    for (const cv::Point2f& c : corners) cornerPlane.push_back(applyHomography(referenceToPlane, c));
    background = static_cast<std::uint8_t>(cv::mean(reference)[0]);
    templatePyramid.configure(640, 480, 3);
    framePyramid.configure(640, 480, 3);
    ransac.reserve(kCorners);
    for (auto* v : {&from, &to, &plane, &inlierPlane, &inlierImage}) v->resize(kCorners);
    status.resize(kCorners);
    mask.resize(kCorners);
  }

  // One frame from the pose before; false when it does not hold (the loop's check, not ours).
  bool step(const cv::Mat& frame, PlanarPose& pose, int& inliers) noexcept {
    const cv::Matx33d w0 = planeToImage(k, pose) * referenceToPlane;
    const double scale = homographyScaleAt(w0, cv::Point2f(400, 320));
    int level = 0;
    while (level + 1 < static_cast<int>(levels.size()) && scale < 0.7 / (1 << level)) ++level;
    const double f = 1.0 / (1 << level);
    const cv::Matx33d levelToBase(1 / f, 0, 0.5 / f - 0.5, 0, 1 / f, 0.5 / f - 0.5, 0, 0, 1);
    std::size_t n = 0;
    float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
    for (std::size_t c = 0; c < corners.size() && n < kCorners; ++c) {
      const cv::Point2f p = applyHomography(w0, corners[c]);
      if (!(p.x >= 15 && p.y >= 15 && p.x < 625 && p.y < 465)) continue;
      from[n] = to[n] = p;
      plane[n++] = cornerPlane[c];
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    if (n < 30) return false;
    const int grow = 15 * 8;
    const cv::Rect region = cv::Rect(static_cast<int>(x0) - grow, static_cast<int>(y0) - grow,
                                     static_cast<int>(x1 - x0) + 2 * grow, static_cast<int>(y1 - y0) + 2 * grow) &
                            cv::Rect(0, 0, 640, 480);
    std::memset(templ.data, background, templ.total());
    if (!warpPerspectiveRegion(levels[static_cast<std::size_t>(level)], w0 * levelToBase, templ, region, background))
      return false;
    if (!templatePyramid.buildRegion(templ, region, background) || !framePyramid.build(frame)) return false;
    const std::span<cv::Point2f> found(to.data(), n);
    klt.track(templatePyramid, framePyramid, std::span<const cv::Point2f>(from.data(), n), found,
              std::span<std::uint8_t>(status.data(), n), LucasKanadeOptions{});
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (status[i]) inlierPlane[m] = plane[i], inlierImage[m++] = to[i];
    const std::span<const cv::Point2f> pl(inlierPlane.data(), m), im(inlierImage.data(), m);
    cv::Matx33d h;
    HomographyRansacOptions params;
    params.thresholdPx = 2.0;
    if (!ransac.estimate(pl, im, params, h, std::span<std::uint8_t>(mask.data(), m), inliers)) return false;
    double rms = 0;
    const std::span<const std::uint8_t> used(mask.data(), m);
    if (!planarPoseFromHomography(k, h, pl, im, used, PoseRefineOptions{}, pose, rms)) return false;
    return std::isfinite(reprojectionRms(k, pose, pl, im, used));
  }
};

TEST(TrackingAllocation, PrimitivesAllocateNothingPerFrame) {
  cv::setNumThreads(1);
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  const auto rendered = synthetic::renderScenarios(renderer, 30, {"orbit"});
  ASSERT_EQ(rendered.size(), 1u);
  const cv::Mat reference = cv::imread(synthetic::standardTargetImage(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(reference.empty());
  std::vector<cv::Mat> grey(rendered[0].frames.size());
  for (std::size_t i = 0; i < grey.size(); ++i) cv::cvtColor(rendered[0].frames[i], grey[i], cv::COLOR_RGB2GRAY);
  PrimitivesPipeline pipeline(reference);
  glm::dmat3 r;
  glm::dvec3 t;
  synthetic::worldToOpenCvCamera(rendered[0].scenario.cameraToWorld[0], r, t);
  const cv::Matx33d m(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  PlanarPose pose{rodriguesFromRotation(m), cv::Vec3d(t.x, t.y, t.z)};  // the first frame's, exact
  int inliers = 0;
  for (std::size_t i = 1; i < 3; ++i) ASSERT_TRUE(pipeline.step(grey[i], pose, inliers)) << "warm-up frame " << i;

  std::array<Counts, 27> counts{};
  std::array<int, 27> frameInliers{};
  std::array<bool, 27> held{};
  for (std::size_t i = 3; i < grey.size(); ++i) {
    const Counts c0 = now();
    held[i - 3] = pipeline.step(grey[i], pose, frameInliers[i - 3]);
    counts[i - 3] = since(c0);
  }
  long news = 0, mallocs = 0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    EXPECT_TRUE(held[k]) << "frame " << k + 3;
    EXPECT_GE(frameInliers[k], 100) << "frame " << k + 3;
    EXPECT_EQ(counts[k].news, 0) << "frame " << k + 3;
#if MN_COUNT_MALLOC
    EXPECT_EQ(counts[k].mallocs, 0) << "frame " << k + 3;
#endif
    news += counts[k].news;
    mallocs += counts[k].mallocs;
  }
  // The pose at the end is the last frame's (no drift: every frame is matched to the reference).
  synthetic::worldToOpenCvCamera(rendered[0].scenario.cameraToWorld.back(), r, t);
  EXPECT_LT(cv::norm(pose.tvec - cv::Vec3d(t.x, t.y, t.z)), 0.01);
  std::printf("[ primitives ] warp + pyramids + KLT + RANSAC + pose per frame, frames 3..29: %.1f operator new, "
              "%.1f malloc family%s\n",
              perFrame(news, counts.size()), perFrame(mallocs, counts.size()),
              MN_COUNT_MALLOC ? "" : " (not counted in this build)");
}

// The markerless tracker over a stress sequence from the standard target: the allocations of the
// frames (from the fourth) whose stats `counted` picks, leaving out frames that relocalize or add
// a keyframe (ORB allocates). Returns how many were counted, and prints the per-frame means.
template <class Pick>
int expectNoAllocationOnStressFrames(synthetic::StressClass kind, std::uint64_t seed, int frames, const char* what,
                                     Pick counted) {
  cv::setNumThreads(1);
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  const synthetic::StressSequence sequence = synthetic::stressSequence(renderer, kind, seed, frames);
  const synthetic::RenderedScenario rendered = synthetic::renderStress(renderer, sequence);
  Diagnostics d;
  auto tracker = MarkerlessTracker::fromTarget(renderer.camera(), synthetic::standardTargetImage(),
                                               synthetic::kStandardTargetWidth, MarkerlessSettings{}, d);
  EXPECT_TRUE(tracker) << d.format();
  if (!tracker) return 0;
  int count = 0;
  long news = 0, mallocs = 0;
  for (std::size_t i = 0; i < rendered.frames.size(); ++i) {
    const Counts c0 = now();
    (void)tracker->update(view(rendered.frames[i]), static_cast<double>(i) / rendered.scenario.fps);
    const Counts used = since(c0);
    const auto& st = tracker->lastFrame();
    if (i < 3 || !counted(st) || st.relocalized || st.keyframeAdded || st.keyframeFeatures) continue;
    ++count;
    expectNoAllocation(used, i, news, mallocs);
  }
  std::printf("[ markerless %s ] %d frames: %.1f operator new, %.1f malloc family a frame%s\n", what, count,
              perFrame(news, static_cast<std::size_t>(std::max(1, count))),
              perFrame(mallocs, static_cast<std::size_t>(std::max(1, count))),
              MN_COUNT_MALLOC ? "" : " (not counted in this build)");
  return count;
}

// The tracker's own dense path (the dense alignment inside update(), under a real smear: a
// stress pan, seed 10, whose frames 8-11 and 25-28 are smeared 40-80 px): the frames it measures
// densely allocate nothing either.
TEST(TrackingAllocation, MarkerlessDensePathAllocatesNothingPerFrame) {
  const int dense = expectNoAllocationOnStressFrames(synthetic::StressClass::Pan, 10, 30, "dense",
                                                     [](const MarkerlessTracker::FrameStats& st) { return st.dense; });
  EXPECT_GE(dense, 3) << "the dense path must run on this pan";
}

// Carried poses (a hand over part of the target; docs/tracking.md "Partly hidden targets"): the
// check at the carried pose renders the keyframe into the aligner's reserved samples, nothing else.
TEST(TrackingAllocation, MarkerlessCarriedPosesAllocateNothingPerFrame) {
  // Hands seed 20: 8 carried frames (marionette_tracking_eval --stress 20, session 25).
  const int carried = expectNoAllocationOnStressFrames(synthetic::StressClass::Hands, 20, 40, "carried",
                                                       [](const MarkerlessTracker::FrameStats& st) { return st.carried; });
  EXPECT_GE(carried, 3) << "the carried path must run on this sequence";
}

// The occlusion mask over the target (target_occlusion.hpp) on the `occluder` scenario (a
// rectangle over 20..60 % of the target) and, blurred, on `blur`: the tracker's occlusionMask()
// allocates on its first call (it makes its TargetOcclusion from the map's reference), nothing
// on the frames after, however often it is asked; a tracker never asked makes none (its updates
// allocate nothing, as above). A TargetOcclusion of its own, fed the same frames and the exact
// poses, allocates nothing from its first update on, nor for a target filling the view (worked at
// twice the scale).
TEST(TrackingAllocation, OcclusionMaskAllocatesNothingPerFrame) {
  cv::setNumThreads(1);
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  constexpr int kFrames = 24, kWarm = 10;
  const auto rendered = synthetic::renderScenarios(renderer, kFrames, {"blur", "occluder"});
  ASSERT_EQ(rendered.size(), 2u);
  const synthetic::TargetPyramid reference = synthetic::standardTargetPyramid();
  std::array<double, 9> planeToImage{};
  for (std::size_t k = 0; k < 9; ++k) planeToImage[k] = reference.planeToImage.val[k];
  for (const auto& scenario : rendered) {
    const auto& frames = scenario.frames;
    Diagnostics d;
    auto tracker = MarkerlessTracker::fromTarget(renderer.camera(), synthetic::standardTargetImage(),
                                                 synthetic::kStandardTargetWidth, MarkerlessSettings{}, d);
    ASSERT_TRUE(tracker) << d.format();
    auto occlusion = TargetOcclusion::create(renderer.camera(), view(reference.levels[0]), planeToImage, {}, d);
    ASSERT_TRUE(occlusion) << d.format();
    const double fps = scenario.scenario.fps;
    for (int i = 0; i < kWarm; ++i) (void)tracker->update(view(frames[static_cast<std::size_t>(i)]), i / fps);
    const Counts first0 = now();
    const OcclusionMask* m = tracker->occlusionMask();
    const Counts first = since(first0);
    ASSERT_NE(m, nullptr);
    EXPECT_GT(first.news + first.mallocs, 0) << "the first call makes the TargetOcclusion";
    long news = 0, mallocs = 0, standaloneNews = 0, standaloneMallocs = 0;
    double hidden = 0;
    for (int i = kWarm; i < kFrames; ++i) {
      const ImageView v = view(frames[static_cast<std::size_t>(i)]);
      const TrackedPose p = tracker->update(v, i / fps);
      EXPECT_NE(p.state, TrackingState::Lost) << scenario.scenario.name << " frame " << i;
      const Counts c0 = now();
      m = tracker->occlusionMask();
      m = tracker->occlusionMask();  // asked again: the same mask, not computed again
      expectNoAllocation(since(c0), static_cast<std::size_t>(i), news, mallocs);
      hidden += m->hiddenShare;
      const Counts c1 = now();
      occlusion->update(v, scenario.scenario.cameraToWorld[static_cast<std::size_t>(i)]);
      expectNoAllocation(since(c1), static_cast<std::size_t>(i), standaloneNews, standaloneMallocs);
    }
    if (scenario.scenario.name == "occluder") {
      EXPECT_GT(hidden / (kFrames - kWarm), 0.15);
    }
    if (scenario.scenario.name == "blur") {
      // A target filling the view: worked at twice the scale, upsampled; nothing allocated either.
      for (int k = 0; k < 4; ++k) {
        const glm::dmat4 pose = synthetic::orbitPose(90.0 * k, 60, 0.32);
        cv::Mat frame;
        renderer.render(pose, {}, frame);
        const Counts c0 = now();
        occlusion->update(view(frame), pose);
        expectNoAllocation(since(c0), static_cast<std::size_t>(k), standaloneNews, standaloneMallocs);
        EXPECT_EQ(occlusion->mask().computedScale, 8) << "close view " << k;
      }
    }
    std::printf("[ occlusion %s ] first occlusionMask(): %ld operator new, %ld malloc family; after: %.1f and %.1f per "
                "frame (TargetOcclusion::update: %.1f and %.1f)%s\n",
                scenario.scenario.name.c_str(), first.news, first.mallocs, perFrame(news, kFrames - kWarm),
                perFrame(mallocs, kFrames - kWarm), perFrame(standaloneNews, kFrames - kWarm),
                perFrame(standaloneMallocs, kFrames - kWarm), MN_COUNT_MALLOC ? "" : " (malloc not counted in this build)");
  }
}

// The dense alignment (what the tracker falls back on under a smear), with a smear being
// estimated (12 parameters), from the true pose moved a degree: nothing allocated once reserved.
TEST(TrackingAllocation, DenseAlignmentAllocatesNothingPerFrame) {
  cv::setNumThreads(1);
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  const auto rendered = synthetic::renderScenarios(renderer, 12, {"orbit"});
  ASSERT_EQ(rendered.size(), 1u);
  const synthetic::TargetPyramid reference = synthetic::standardTargetPyramid();
  const DenseTarget target{reference.levels, reference.planeToImage};
  const CameraModel& c = renderer.camera();
  const cv::Matx33d k(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  DenseAligner aligner;
  DenseAlignmentOptions params;
  aligner.reserve(params);
  ImagePyramid pyramid;
  ASSERT_TRUE(pyramid.configure(c.width, c.height, 3));
  std::vector<cv::Mat> grey(rendered[0].frames.size());
  for (std::size_t i = 0; i < grey.size(); ++i) cv::cvtColor(rendered[0].frames[i], grey[i], cv::COLOR_RGB2GRAY);
  long news = 0, mallocs = 0;
  for (std::size_t i = 0; i < grey.size(); ++i) {
    glm::dmat3 r;
    glm::dvec3 t;
    synthetic::worldToOpenCvCamera(rendered[0].scenario.cameraToWorld[i], r, t);
    const cv::Matx33d m(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
    PlanarPose start{rodriguesFromRotation(rotationFromRodrigues(cv::Vec3d(0.012, -0.01, 0.004)) * m),
                     cv::Vec3d(t.x, t.y, t.z)};
    ASSERT_TRUE(pyramid.build(grey[i]));
    DenseAlignment result;
    PlanarPose shifted;
    double score = 0;
    const Counts c0 = now();
    // The re-entry search's probe (a start among several, at the coarse level), then the alignment.
    const bool probed = aligner.probe(k, target, pyramid, cv::Vec3d(0.0, 0.01, 0.0), start, params, shifted, score);
    const bool aligned = aligner.align(k, target, pyramid, cv::Vec3d(0.0, 0.01, 0.0), start, params, result);
    const Counts used = since(c0);
    EXPECT_TRUE(probed) << "frame " << i;
    EXPECT_GT(score, 0.5) << "frame " << i;
    EXPECT_TRUE(aligned) << "frame " << i;
    EXPECT_GT(result.zncc, 0.9) << "frame " << i;
    if (i < 2) continue;  // warm-up
    expectNoAllocation(used, i, news, mallocs);
  }
  std::printf("[ dense ] probe and align per frame, frames 2..11: %.1f operator new, %.1f malloc family%s\n",
              perFrame(news, grey.size() - 2), perFrame(mallocs, grey.size() - 2),
              MN_COUNT_MALLOC ? "" : " (not counted in this build)");
}

}  // namespace
