// The markerless tracker's allocation-free primitives (examples/ar/tracking/src:
// perspective_warp, lucas_kanade, homography_ransac, planar_pose) against the OpenCV calls
// they replace and against exact truth: graf1 (opencv-doc) warped by known homographies, the
// synthetic sequences' exact poses, and bad input. The zero-allocation check is in
// tests/ar/tracking/tracking_allocation_test.cpp, the timings in tests/bench/tracking_bench.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "hamming_matcher.hpp"
#include "homography_ransac.hpp"
#include "lucas_kanade.hpp"
#include "perspective_warp.hpp"
#include "planar_geometry.hpp"
#include "planar_pose.hpp"
#include "test_data.hpp"
#include "tracking/scenario_run.hpp"

namespace {

using namespace marionette::ar;

const cv::Matx33d kK(600, 0, 319.5, 0, 600, 239.5, 0, 0, 1);
const float kNan = std::numeric_limits<float>::quiet_NaN();

// graf1 in grey, 640x480 (INTER_AREA), the scene of all the image tests.
cv::Mat graf640() { return synthetic::standardTargetGrey(cv::Size(640, 480)); }

cv::Point2f apply(const cv::Matx33d& h, cv::Point2f p) {
  const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1);
  return {static_cast<float>(q[0] / q[2]), static_cast<float>(q[1] / q[2])};
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A small known motion: rotation, scale, shift and a little perspective about the centre.
cv::Matx33d motion(double degrees, double scale, double dx, double dy, double perspective) {
  const double c = std::cos(degrees * CV_PI / 180) * scale, s = std::sin(degrees * CV_PI / 180) * scale;
  const cv::Matx33d toCentre(1, 0, -320, 0, 1, -240, 0, 0, 1), back(1, 0, 320 + dx, 0, 1, 240 + dy, 0, 0, 1);
  return back * cv::Matx33d(c, -s, 0, s, c, 0, perspective, 0, 1) * toCentre;
}

bool sameBits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

// The "wide" cases compare AVX2 with the scalar loops only where the CPU has AVX2 (elsewhere
// both run the scalar ones): said in the log, so that a run without it is seen.
void printSimdPath() {
#if defined(__x86_64__) && defined(__GNUC__)
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx2 = false;
#endif
  std::printf("[ simd ] AVX2 %s: the wide loops %s\n", avx2 ? "present" : "absent",
              avx2 ? "are compared with the scalar ones" : "fall back to the scalar ones (nothing wide is compared)");
}

// With the AVX2 loops (where the CPU has them) and without, at sizes whose rows end inside a
// vector's lanes.
TEST(TrackingPrimitives, PyramidIsCvPyrDownToTheBit) {
  const cv::Mat g = graf640();
  for (const bool wide : {true, false})
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(333, 257), cv::Size(37, 21), cv::Size(18, 9), cv::Size(7, 5),
                              cv::Size(1, 1)}) {
    cv::Mat image;
    cv::resize(g, image, size, 0, 0, cv::INTER_AREA);
    ImagePyramid pyramid;
    ASSERT_TRUE(pyramid.configure(size.width, size.height, 3, wide));
    ASSERT_TRUE(pyramid.build(image));
    ASSERT_EQ(pyramid.levels(), 3);
    cv::Mat expected = image;
    for (int l = 1; l <= 3; ++l) {
      cv::Mat down;
      cv::pyrDown(expected, down);
      expected = down;
      const cv::Mat ours = pyramid.levelMat(l);
      ASSERT_EQ(ours.size(), expected.size()) << size << " level " << l;
      EXPECT_EQ(cv::norm(ours, expected, cv::NORM_INF), 0) << size << " level " << l << " wide " << wide;
    }
  }
}

TEST(TrackingPrimitives, RegionPyramidMatchesTheFullOneInsideTheRegion) {
  cv::Mat image(480, 640, CV_8UC1, cv::Scalar(90));
  const cv::Rect region(200, 120, 240, 200);
  graf640()(region).copyTo(image(region));  // outside the region: the background, as the template
  ImagePyramid full, part, scalar;
  ASSERT_TRUE(full.configure(640, 480, 3));
  ASSERT_TRUE(part.configure(640, 480, 3));
  ASSERT_TRUE(scalar.configure(640, 480, 3, false));
  ASSERT_TRUE(full.build(image));
  ASSERT_TRUE(part.buildRegion(image, region, 90));
  ASSERT_TRUE(scalar.buildRegion(image, region, 90));
  for (int l = 1; l <= 3; ++l)
    EXPECT_EQ(cv::norm(part.levelMat(l), scalar.levelMat(l), cv::NORM_INF), 0) << "AVX2 and scalar, level " << l;
  for (int l = 1; l <= 3; ++l) {
    const int f = 1 << l, inset = 4;  // a few pixels per level near the border may differ
    const cv::Rect inside(region.x / f + inset, region.y / f + inset, region.width / f - 2 * inset,
                          region.height / f - 2 * inset);
    EXPECT_EQ(cv::norm(full.levelMat(l)(inside), part.levelMat(l)(inside), cv::NORM_INF), 0) << "level " << l;
    const cv::Mat corner = part.levelMat(l)(cv::Rect(0, 0, 8, 8));
    EXPECT_EQ(cv::countNonZero(corner != 90), 0) << "outside the region: the background";
  }
  EXPECT_FALSE(part.buildRegion(cv::Mat(10, 10, CV_8UC1), region, 0)) << "another size than configured";
  EXPECT_FALSE(part.build(cv::Mat(480, 640, CV_8UC3))) << "not grey";
}

TEST(TrackingPrimitives, WarpMatchesCvWarpPerspective) {
  const cv::Mat src = graf640();
  const cv::Matx33d h = motion(8, 0.7, 40, -25, 3e-4);
  const cv::Rect region(100, 60, 380, 300);
  cv::Mat ours(480, 640, CV_8UC1, cv::Scalar(7)), theirs(480, 640, CV_8UC1, cv::Scalar(7));
  ASSERT_TRUE(warpPerspectiveRegion(src, h, ours, region, 77));
  const cv::Matx33d shift(1, 0, -region.x, 0, 1, -region.y, 0, 0, 1);
  cv::Mat target = theirs(region);
  cv::warpPerspective(src, target, shift * h, region.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(77));
  cv::Mat diff;
  cv::absdiff(ours, theirs, diff);
  const int total = region.area(), exact = total - cv::countNonZero(diff(region));
  const int within1 = cv::countNonZero(diff(region) <= 1);
  std::printf("[ warp ] %d px: %.3f %% identical, %.3f %% within 1 grey level, max %g\n", total, 100.0 * exact / total,
              100.0 * within1 / total, cv::norm(diff, cv::NORM_INF));
  EXPECT_GE(within1, 0.99 * total);
  EXPECT_LE(cv::norm(diff, cv::NORM_INF), 2);
  EXPECT_EQ(cv::countNonZero(ours != 7) - cv::countNonZero(ours(region) != 7), 0) << "only the region is written";
  EXPECT_GT(cv::countNonZero(ours(region) == 77), 1000) << "the border value where the source ends";
  // Bad input: dst untouched.
  cv::Mat untouched = ours.clone();
  EXPECT_FALSE(warpPerspectiveRegion(src, cv::Matx33d::zeros(), ours, region, 0));
  EXPECT_FALSE(warpPerspectiveRegion(cv::Mat(4, 4, CV_8UC3), h, ours, region, 0));
  EXPECT_FALSE(warpPerspectiveRegion(src, cv::Matx33d(kNan, 0, 0, 0, 1, 0, 0, 0, 1), ours, region, 0));
  EXPECT_EQ(cv::norm(ours, untouched, cv::NORM_INF), 0);
  EXPECT_TRUE(warpPerspectiveRegion(cv::Mat(1, 1, CV_8UC1, cv::Scalar(200)), h, ours, region, 3)) << "a 1x1 source";
  EXPECT_TRUE(warpPerspectiveRegion(src, h, ours, cv::Rect(630, 470, 50, 50), 3)) << "a region past the image";
}

struct KltCase {
  cv::Mat prev, next;
  std::vector<cv::Point2f> from, guess, truth;
};

// The scene: graf1 upsampled 4x (bicubic), the "continuous" image both frames are taken
// from; a frame is its 5x area average (640x480), the moved frame the same of the scene warped
// at 5x resolution (bilinear there: its interpolation error is a fifth of a pixel's here). A
// frame warped at its own resolution would carry the interpolation's phase error (OpenCV's
// bicubic moves features by ~0.05 px), more than the KLT's. Guesses up to 5 px off the truth.
KltCase knownMotion(const cv::Matx33d& h) {
  KltCase c;
  cv::Mat scene, moved;
  cv::resize(graf640(), scene, cv::Size(3200, 2400), 0, 0, cv::INTER_CUBIC);
  const double f = 5;  // scene pixels per frame pixel; frame x = (scene x + 0.5) / f - 0.5
  const cv::Matx33d toFrame(1 / f, 0, 0.5 / f - 0.5, 0, 1 / f, 0.5 / f - 0.5, 0, 0, 1);
  cv::warpPerspective(scene, moved, toFrame.inv() * h * toFrame, scene.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  cv::resize(scene, c.prev, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
  cv::resize(moved, c.next, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(c.prev, corners, 300, 0.01, 8, cv::noArray(), 5);
  cv::RNG rng(7);
  for (const cv::Point2f& p : corners) {
    const cv::Point2f t = apply(h, p);
    if (t.x < 20 || t.y < 20 || t.x > 620 || t.y > 460) continue;
    c.from.push_back(p);
    c.truth.push_back(t);
    c.guess.push_back(t + cv::Point2f(rng.uniform(-5.f, 5.f), rng.uniform(-5.f, 5.f)));
  }
  return c;
}

struct KltScore {
  int found = 0, within005 = 0;
  double medianError = 0;
};

KltScore score(const std::vector<cv::Point2f>& found, const std::vector<unsigned char>& status,
               const std::vector<cv::Point2f>& truth) {
  KltScore s;
  std::vector<double> errors;
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (!status[i]) continue;
    const double e = cv::norm(found[i] - truth[i]);
    ++s.found;
    s.within005 += e < 0.05;
    errors.push_back(e);
  }
  s.medianError = median(errors);
  return s;
}

KltScore runOurs(const KltCase& c, LkGradient gradient, std::vector<cv::Point2f>* out = nullptr, bool simd = true,
                 std::vector<unsigned char>* outStatus = nullptr, int window = 15, bool wide = true) {
  ImagePyramid a, b;
  a.configure(c.prev.cols, c.prev.rows, 3);
  b.configure(c.next.cols, c.next.rows, 3);
  a.build(c.prev);
  b.build(c.next);
  LucasKanade lk;
  std::vector<cv::Point2f> to = c.guess;
  std::vector<unsigned char> status(to.size());
  LucasKanadeOptions params;
  params.gradient = gradient;
  params.simd = simd;
  params.wide = wide;
  params.window = window;
  lk.track(a, b, c.from, to, status, params);
  if (out) *out = to;
  if (outStatus) *outStatus = status;
  return score(to, status, c.truth);
}

KltScore runOpenCv(const KltCase& c) {
  std::vector<cv::Point2f> to = c.guess;
  std::vector<unsigned char> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(c.prev, c.next, c.from, to, status, error, cv::Size(15, 15), 3,
                           cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  return score(to, status, c.truth);
}

TEST(TrackingPrimitives, KltRecoversKnownMotionAsWellAsOpenCv) {
  // A shift, then rotation and scale that KLT's shift-only window model follows less closely.
  for (const cv::Matx33d& h : {motion(0, 1, 6.3, -4.7, 0), motion(1, 1.01, 9.2, 3.1, 1e-5), motion(3, 0.97, -14, 8, 2e-5)}) {
    const KltCase c = knownMotion(h);
    ASSERT_GT(c.from.size(), 150u);
    const KltScore ours = runOurs(c, LkGradient::Scharr), central = runOurs(c, LkGradient::Central), cv = runOpenCv(c);
    std::printf("[ klt ] %zu points: found / within 0.05 px / median error px: ours (Scharr) %d / %d / %.4f, "
                "ours (central) %d / %d / %.4f, OpenCV %d / %d / %.4f\n",
                c.from.size(), ours.found, ours.within005, ours.medianError, central.found, central.within005,
                central.medianError, cv.found, cv.within005, cv.medianError);
    EXPECT_GE(ours.found, cv.found);
    EXPECT_GE(ours.within005, static_cast<int>(0.98 * cv.within005));
    EXPECT_LE(ours.medianError, 1.1 * cv.medianError);
    if (h(0, 1) == 0) {  // a pure shift, KLT's own model: a twentieth of a pixel
      EXPECT_LT(ours.medianError, 0.05);
      EXPECT_GE(ours.within005, static_cast<int>(0.8 * static_cast<double>(c.from.size())));
    }
  }
}

// The AVX2 warp (where the CPU has it) and the scalar loop give the same bits: over the
// tracker's kind of view, across the source's edges and corners (the gathers' fast path needs
// columns to spare and a row below), outside it, for tiny and strided sources, and for
// homographies that put the horizon in the region (w through 0, huge and NaN-free clamps).
TEST(TrackingPrimitives, WarpWideAndScalarLoopsGiveTheSameBits) {
  printSimdPath();
  const cv::Mat g = graf640();
  cv::Mat strided(300, 400, CV_8UC1, cv::Scalar(0));
  g(cv::Rect(0, 0, 397, 300)).copyTo(strided(cv::Rect(0, 0, 397, 300)));
  const cv::Mat sources[] = {g, g(cv::Rect(10, 20, 397, 301)), strided(cv::Rect(0, 0, 397, 300)),
                             g(cv::Rect(0, 0, 1, 1)).clone(), g(cv::Rect(0, 0, 3, 2)).clone(), g(cv::Rect(5, 5, 4, 7)).clone()};
  cv::RNG rng(7);
  int compared = 0, inside = 0;
  for (const cv::Mat& src : sources) {
    std::vector<cv::Matx33d> homographies = {motion(8, 0.7, 40, -25, 3e-4), motion(0, 1, 0, 0, 0), motion(30, 2.5, -300, 200, 0),
                                             motion(5, 1, 0, 0, 4e-3), motion(-12, 0.5, 100, 50, -3e-3)};
    for (int i = 0; i < 20; ++i)
      homographies.push_back(motion(rng.uniform(-180., 180.), rng.uniform(0.2, 4.), rng.uniform(-400., 400.),
                                    rng.uniform(-300., 300.), rng.uniform(-5e-3, 5e-3)));
    for (const cv::Matx33d& h : homographies)
      for (const cv::Rect region : {cv::Rect(0, 0, 640, 480), cv::Rect(3, 1, 37, 5), cv::Rect(601, 470, 100, 100)}) {
        cv::Mat wide(480, 640, CV_8UC1, cv::Scalar(9)), scalar(480, 640, CV_8UC1, cv::Scalar(9));
        const bool a = warpPerspectiveRegion(src, h, wide, region, 77, true);
        const bool b = warpPerspectiveRegion(src, h, scalar, region, 77, false);
        ASSERT_EQ(a, b);
        ASSERT_EQ(cv::norm(wide, scalar, cv::NORM_INF), 0) << src.size() << " region " << region << " h " << h;
        ++compared;
        inside += cv::countNonZero(scalar != 77) > 1000;
      }
  }
  EXPECT_EQ(compared, 6 * 25 * 3);
  EXPECT_GT(inside, 40) << "views that show the source, not only its border";
}

// KLT's arithmetic is integer (fixed point, as OpenCV's): the AVX2 loops (where the CPU has
// them), the SSE2 loops and the portable ones give the same bits, at the windows the tracker
// uses, at windows whose padded rows end halfway through sixteen lanes, and at the image's border.
TEST(TrackingPrimitives, KltSimdAndPortableLoopsGiveTheSameBits) {
  printSimdPath();
  KltCase c = knownMotion(motion(1, 1.01, 9.2, 3.1, 1e-5));
  ASSERT_GT(c.from.size(), 150u);
  // Points at and past the border too: the reflect-101 copy.
  for (const cv::Point2f p : {cv::Point2f(1.5f, 1.5f), cv::Point2f(638.2f, 240.7f), cv::Point2f(320.3f, 478.9f)}) {
    c.from.push_back(p);
    c.guess.push_back(p + cv::Point2f(0.7f, -0.4f));
    c.truth.push_back(p);
  }
  for (const LkGradient gradient : {LkGradient::Scharr, LkGradient::Central})
  for (int window : {3, 7, 9, 15, 17, 21, 25, 33, 49, 55, 61})
  for (const bool wide : {true, false}) {
    std::vector<cv::Point2f> simd, portable;
    std::vector<unsigned char> simdStatus, portableStatus;
    runOurs(c, gradient, &simd, true, &simdStatus, window, wide);
    runOurs(c, gradient, &portable, false, &portableStatus, window);
    ASSERT_EQ(simd.size(), portable.size());
    int found = 0;
    for (std::size_t i = 0; i < simd.size(); ++i) {
      EXPECT_EQ(simdStatus[i], portableStatus[i]) << "window " << window << " wide " << wide << " point " << i;
      EXPECT_EQ(std::memcmp(&simd[i], &portable[i], sizeof(cv::Point2f)), 0)
          << "window " << window << " wide " << wide << " point " << i;
      found += simdStatus[i];
    }
    EXPECT_GT(found, 150) << "window " << window;
  }
}

// The tracker's own situation: the reference warped into the frame from a pose one frame
// old, the frame rendered with exact poses, the truth where the true pose projects the corners.
TEST(TrackingPrimitives, KltOnTheSyntheticSequenceMatchesOpenCv) {
  const synthetic::SequenceRenderer renderer = synthetic::standardRenderer();
  const auto rendered = synthetic::renderScenarios(renderer, 12, {"orbit"});
  ASSERT_EQ(rendered.size(), 1u);
  cv::Mat reference = cv::imread(synthetic::standardTargetImage(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(reference.empty());
  std::vector<cv::Mat> levels{reference};
  for (int l = 1; l < 4; ++l) {
    cv::Mat d;
    cv::pyrDown(levels.back(), d);
    levels.push_back(d);
  }
  const double mpp = synthetic::kStandardTargetWidth / reference.cols;
  const cv::Matx33d planeToRef(1 / mpp, 0, reference.cols * 0.5 - 0.5, 0, 1 / mpp, reference.rows * 0.5 - 0.5, 0, 0, 1);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(reference, corners, 500, 0.01, 8, cv::noArray(), 5);
  const auto poseOf = [&](std::size_t i) {
    glm::dmat3 r;
    glm::dvec3 t;
    synthetic::worldToOpenCvCamera(rendered[0].scenario.cameraToWorld[i], r, t);
    const cv::Matx33d m(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
    return PlanarPose{rodriguesFromRotation(m), cv::Vec3d(t.x, t.y, t.z)};
  };
  ImagePyramid tp, fp;
  tp.configure(640, 480, 3);
  fp.configure(640, 480, 3);
  LucasKanade lk;
  std::vector<double> oursErr, cvErr;
  int oursFound = 0, cvFound = 0, tried = 0;
  for (std::size_t i = 1; i < rendered[0].frames.size(); ++i) {
    cv::Mat frame;
    cv::cvtColor(rendered[0].frames[i], frame, cv::COLOR_RGB2GRAY);
    const cv::Matx33d g = planeToImageHomography(kK, poseOf(i - 1)), gTrue = planeToImageHomography(kK, poseOf(i));
    const cv::Matx33d w0 = g * planeToRef.inv();
    const double scale = homographyScaleAt(w0, cv::Point2f(400, 320));
    int level = 0;
    while (level + 1 < 4 && scale < 0.7 / (1 << level)) ++level;
    const double f = 1.0 / (1 << level);
    const cv::Matx33d levelToBase(1 / f, 0, 0.5 / f - 0.5, 0, 1 / f, 0.5 / f - 0.5, 0, 0, 1);
    std::vector<cv::Point2f> from, truth;
    for (const cv::Point2f& c : corners) {
      const cv::Point2f p = apply(w0, c), t = apply(gTrue * planeToRef.inv(), c);
      if (p.x < 15 || p.y < 15 || p.x > 625 || p.y > 465 || from.size() >= 200) continue;
      from.push_back(p);
      truth.push_back(t);
    }
    cv::Mat templ(480, 640, CV_8UC1, cv::Scalar(cv::mean(reference)[0]));
    ASSERT_TRUE(warpPerspectiveRegion(levels[static_cast<std::size_t>(level)], w0 * levelToBase, templ,
                                      cv::Rect(0, 0, 640, 480), static_cast<std::uint8_t>(cv::mean(reference)[0])));
    tp.build(templ);
    fp.build(frame);
    std::vector<cv::Point2f> ours = from, theirs = from;
    std::vector<unsigned char> status(from.size()), cvStatus;
    std::vector<float> error;
    lk.track(tp, fp, from, ours, status, LucasKanadeOptions{});
    cv::calcOpticalFlowPyrLK(templ, frame, from, theirs, cvStatus, error, cv::Size(15, 15), 3,
                             cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 0.01),
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    tried += static_cast<int>(from.size());
    for (std::size_t k = 0; k < from.size(); ++k) {
      if (status[k]) ++oursFound, oursErr.push_back(cv::norm(ours[k] - truth[k]));
      if (cvStatus[k]) ++cvFound, cvErr.push_back(cv::norm(theirs[k] - truth[k]));
    }
  }
  const double mo = median(oursErr), mc = median(cvErr);
  std::printf("[ klt sequence ] %d tried: ours %d found, median error %.4f px; OpenCV %d found, median %.4f px\n", tried,
              oursFound, mo, cvFound, mc);
  EXPECT_GE(oursFound, cvFound);
  EXPECT_LE(mo, 1.1 * mc);
  EXPECT_LT(mo, 1.0);  // both ~0.5 px: the template (a pyramid level, bilinear) is not the rendered frame
}

TEST(TrackingPrimitives, KltGivesAClearStatusOnBadInput) {
  cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(100));
  const cv::Mat textured = graf640();
  ImagePyramid f, t;
  ASSERT_TRUE(f.configure(640, 480, 3));
  ASSERT_TRUE(t.configure(640, 480, 3));
  f.build(flat);
  t.build(textured);
  LucasKanade lk;
  std::vector<cv::Point2f> from{{320, 240}, {-100, 50}, {kNan, 10}, {300, 200}, {700, 900}};
  std::vector<cv::Point2f> to{{320, 240}, {-100, 50}, {10, 10}, {kNan, 200}, {700, 900}};
  std::vector<unsigned char> status(from.size(), 7);
  EXPECT_EQ(lk.track(f, f, from, to, status, {}), 0) << "no texture";
  for (unsigned char s : status) EXPECT_EQ(s, 0);
  status.assign(from.size(), 7);
  EXPECT_EQ(lk.track(t, t, from, to, status, {}), 1) << "only the first point is inside and finite";
  EXPECT_EQ(status[0], 1);
  EXPECT_NEAR(to[0].x, 320, 1e-3);
  // A guess that runs off the image, a 1x1 image, mismatched sizes, a bad window.
  std::vector<cv::Point2f> off{{320, 240}}, guess{{5000, 240}};
  std::vector<unsigned char> one(1, 7);
  EXPECT_EQ(lk.track(t, t, off, guess, one, {}), 0);
  EXPECT_EQ(one[0], 0);
  ImagePyramid tiny;
  ASSERT_TRUE(tiny.configure(1, 1, 3));
  cv::Mat pixel(1, 1, CV_8UC1, cv::Scalar(9));
  ASSERT_TRUE(tiny.build(pixel));
  std::vector<cv::Point2f> zero{{0, 0}}, zeroTo{{0, 0}};
  EXPECT_EQ(lk.track(tiny, tiny, zero, zeroTo, one, {}), 0);
  EXPECT_EQ(lk.track(tiny, t, zero, zeroTo, one, {}), 0) << "pyramids of different sizes";
  LucasKanadeOptions even;
  even.window = 14;
  EXPECT_EQ(lk.track(t, t, off, zeroTo, one, even), 0);
  EXPECT_EQ(one[0], 0);
}

// Plane points (X, Z) over a 0.3 x 0.24 m target and their pixels under a pose.
struct PlaneScene {
  PlanarPose pose;
  std::vector<cv::Point2f> plane, image;
};

PlaneScene planeScene(int n, double noisePx, double outlierShare, std::uint64_t seed, double elevationDeg = 50) {
  PlaneScene s;
  const glm::dmat4 c2w = synthetic::orbitPose(30, elevationDeg, 0.7, 5);
  glm::dmat3 r;
  glm::dvec3 t;
  synthetic::worldToOpenCvCamera(c2w, r, t);
  const cv::Matx33d m(r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1], r[0][2], r[1][2], r[2][2]);
  s.pose = PlanarPose{rodriguesFromRotation(m), cv::Vec3d(t.x, t.y, t.z)};
  cv::RNG rng(seed);
  s.plane.resize(static_cast<std::size_t>(n));
  for (auto& p : s.plane) p = cv::Point2f(rng.uniform(-0.15f, 0.15f), rng.uniform(-0.12f, 0.12f));
  s.image.resize(s.plane.size());
  projectPlanePoints(kK, s.pose, s.plane, s.image);
  for (std::size_t i = 0; i < s.image.size(); ++i) {
    if (i < static_cast<std::size_t>(outlierShare * n)) {  // far off: 20..120 px in a random direction
      const double a = rng.uniform(0.0, 2 * CV_PI), d = rng.uniform(20.0, 120.0);
      s.image[i] += cv::Point2f(static_cast<float>(d * std::cos(a)), static_cast<float>(d * std::sin(a)));
    } else {
      s.image[i] += cv::Point2f(static_cast<float>(rng.gaussian(noisePx)), static_cast<float>(rng.gaussian(noisePx)));
    }
  }
  return s;
}

// The largest distance between where two homographies put the points of the target.
double transferError(const cv::Matx33d& a, const cv::Matx33d& b) {
  double worst = 0;
  for (double x = -0.15; x <= 0.15; x += 0.01)
    for (double z = -0.12; z <= 0.12; z += 0.01)
      worst = std::max(worst, cv::norm(apply(a, cv::Point2f(float(x), float(z))) - apply(b, cv::Point2f(float(x), float(z)))));
  return worst;
}

TEST(TrackingPrimitives, RansacFindsTheHomographyAndFlagsTheOutliers) {
  HomographyRansac ransac;
  ransac.reserve(400);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const PlaneScene s = planeScene(200, 0.5, 0.3, seed);
    const cv::Matx33d truth = planeToImageHomography(kK, s.pose);
    cv::Matx33d h;
    std::vector<unsigned char> mask(s.plane.size());
    int inliers = 0;
    ASSERT_TRUE(ransac.estimate(s.plane, s.image, {.thresholdPx = 2.0}, h, mask, inliers));
    std::vector<unsigned char> cvMask;
    const cv::Matx33d hcv(cv::findHomography(s.plane, s.image, cv::RANSAC, 2.0, cvMask, 500, 0.995));
    int outliersFlagged = 0, inliersKept = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) (i < 60 ? outliersFlagged : inliersKept) += (i < 60) != (mask[i] != 0);
    std::printf("[ ransac ] seed %d: %d inliers (OpenCV %d), transfer error vs truth %.3f px (OpenCV %.3f px), "
                "%d / 60 outliers flagged, %d / 140 inliers kept\n",
                int(seed), inliers, cv::countNonZero(cvMask), transferError(h, truth), transferError(hcv, truth),
                outliersFlagged, inliersKept);
    EXPECT_LT(transferError(h, truth), 0.5);
    EXPECT_EQ(outliersFlagged, 60);
    EXPECT_GE(inliersKept, 133);  // 2 px at sigma 0.5: all but a few
    EXPECT_EQ(inliers, std::count(mask.begin(), mask.end(), 1));
  }
  // Noise-free: exact.
  const PlaneScene s = planeScene(50, 0, 0, 9);
  cv::Matx33d h;
  std::vector<unsigned char> mask(s.plane.size());
  int inliers = 0;
  ASSERT_TRUE(ransac.estimate(s.plane, s.image, {}, h, mask, inliers));
  EXPECT_EQ(inliers, 50);
  EXPECT_LT(transferError(h, planeToImageHomography(kK, s.pose)), 1e-3);
}

TEST(TrackingPrimitives, RansacRefusesDegenerateInput) {
  HomographyRansac ransac;
  ransac.reserve(100);
  cv::Matx33d h = cv::Matx33d::eye();
  std::vector<unsigned char> mask(100, 9);
  int inliers = -1;
  std::vector<cv::Point2f> line, pixels;
  for (float i = 0; i < 40; ++i) {
    line.emplace_back(0.01f * i, 0.02f * i - 0.1f);
    pixels.emplace_back(100.f + 5.f * i, 50.f + 3.f * i);
  }
  EXPECT_FALSE(ransac.estimate(line, pixels, {}, h, mask, inliers)) << "collinear";
  EXPECT_EQ(inliers, 0);
  EXPECT_EQ(std::count(mask.begin(), mask.begin() + 40, 0), 40);
  const PlaneScene s = planeScene(3, 0, 0, 4);
  EXPECT_FALSE(ransac.estimate(s.plane, s.image, {}, h, mask, inliers)) << "3 points";
  const PlaneScene big = planeScene(101, 0, 0, 4);
  std::vector<unsigned char> bigMask(101);
  EXPECT_FALSE(ransac.estimate(big.plane, big.image, {}, h, bigMask, inliers)) << "more than reserved";
  PlaneScene nan = planeScene(30, 0, 0, 5);
  for (std::size_t i = 0; i < 27; ++i) nan.image[i].x = kNan;
  EXPECT_FALSE(ransac.estimate(nan.plane, nan.image, {}, h, mask, inliers)) << "3 finite pairs of 30";
  nan = planeScene(30, 0, 0, 5);
  nan.image[3].y = kNan;
  ASSERT_TRUE(ransac.estimate(nan.plane, nan.image, {}, h, mask, inliers)) << "one NaN pair among 30";
  EXPECT_EQ(mask[3], 0);
  EXPECT_EQ(inliers, 29);
  for (double v : h.val) EXPECT_TRUE(std::isfinite(v));
  std::vector<cv::Point2f> shorter(s.image.begin(), s.image.end() - 1);
  EXPECT_FALSE(ransac.estimate(s.plane, shorter, {}, h, mask, inliers)) << "sizes differ";
}

void expectPosesNear(const PlanarPose& a, const PlanarPose& b, double metres, double radians, const char* what) {
  const cv::Matx33d d = rotationFromRodrigues(a.rvec) * rotationFromRodrigues(b.rvec).t();
  const double angle = cv::norm(rodriguesFromRotation(d));
  EXPECT_LT(cv::norm(a.tvec - b.tvec), metres) << what;
  EXPECT_LT(angle, radians) << what;
}

TEST(TrackingPrimitives, PoseMatchesIppeAndLevenbergMarquardt) {
  for (const double noise : {0.0, 0.7}) {
    for (const double elevation : {60.0, 35.0, 15.0}) {
      const PlaneScene s = planeScene(120, noise, 0, 11 + static_cast<std::uint64_t>(elevation));
      std::vector<cv::Point3f> object;
      for (const cv::Point2f& p : s.plane) object.emplace_back(p.x, 0.f, p.y);
      cv::Vec3d rvec, tvec;
      ASSERT_TRUE(cv::solvePnP(object, s.image, kK, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE));
      cv::solvePnPRefineLM(object, s.image, kK, cv::noArray(), rvec, tvec,
                           cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 1e-9));
      const PlanarPose opencv{rvec, tvec};
      HomographyRansac ransac;
      ransac.reserve(200);
      cv::Matx33d h;
      ASSERT_TRUE(ransac.fit(s.plane, s.image, {}, 10, h));
      PlanarPose ours;
      double rms = 0;
      ASSERT_TRUE(planarPoseFromHomography(kK, h, s.plane, s.image, {}, {}, ours, rms));
      const double cvRms = reprojectionRms(kK, opencv, s.plane, s.image, {});
      std::printf("[ pose ] noise %.1f px, elevation %.0f deg: rms ours %.6f px, OpenCV %.6f px; |dt| %.2e m, "
                  "truth |dt| %.2e m\n",
                  noise, elevation, rms, cvRms, cv::norm(ours.tvec - opencv.tvec), cv::norm(ours.tvec - s.pose.tvec));
      if (noise == 0) {
        expectPosesNear(ours, opencv, 1e-6, 1e-6, "noise-free: as OpenCV");
        expectPosesNear(ours, s.pose, 1e-6, 1e-6, "noise-free: the truth");
        EXPECT_LT(rms, 1e-4);
      } else {
        expectPosesNear(ours, opencv, 1e-6, 1e-6, "noisy: the same least-squares minimum as OpenCV");
        expectPosesNear(ours, s.pose, 5e-3, 5e-3, "noisy: near the truth");
        EXPECT_LE(rms, cvRms * (1 + 1e-9) + 1e-12);
      }
    }
  }
}

TEST(TrackingPrimitives, PoseTakesTheBetterOfTheTwoCandidates) {
  // A fronto-parallel, far, small target: IPPE's two poses nearly tie; the one with the
  // smaller error must come out, and both candidates image the centre alike.
  const PlaneScene s = planeScene(60, 0.0, 0, 21, 88);
  HomographyRansac ransac;
  ransac.reserve(100);
  cv::Matx33d h;
  ASSERT_TRUE(ransac.fit(s.plane, s.image, {}, 10, h));
  PlanarPose c[2];
  ASSERT_EQ(planarPoseCandidates(kK, h, cv::Point2f(0, 0), c), 2);
  cv::Point2f a[1], b[1];
  const cv::Point2f centre[1] = {cv::Point2f(0, 0)};
  projectPlanePoints(kK, c[0], centre, a);
  projectPlanePoints(kK, c[1], centre, b);
  EXPECT_LT(cv::norm(a[0] - b[0]), 1e-6);
  PlanarPose ours;
  double rms = 0;
  ASSERT_TRUE(planarPoseFromHomography(kK, h, s.plane, s.image, {}, {}, ours, rms));
  expectPosesNear(ours, s.pose, 1e-6, 1e-6, "the right one of the two");
}

TEST(TrackingPrimitives, PoseRefusesBadInput) {
  const PlaneScene s = planeScene(10, 0, 0, 3);
  const cv::Matx33d h = planeToImageHomography(kK, s.pose);
  PlanarPose out{cv::Vec3d(1, 2, 3), cv::Vec3d(4, 5, 6)};
  double rms = -1;
  const std::span<const cv::Point2f> three(s.plane.data(), 3), threeImage(s.image.data(), 3);
  EXPECT_FALSE(planarPoseFromHomography(kK, h, three, threeImage, {}, {}, out, rms)) << "3 points";
  std::vector<cv::Point2f> nan = s.image;
  nan[6].y = kNan;
  EXPECT_FALSE(planarPoseFromHomography(kK, h, s.plane, nan, {}, {}, out, rms)) << "NaN";
  std::vector<unsigned char> mask(10, 0);
  mask[0] = mask[1] = mask[2] = mask[3] = 1;
  EXPECT_TRUE(planarPoseFromHomography(kK, h, s.plane, nan, mask, {}, out, rms)) << "the NaN masked out";
  PlanarPose behind{s.pose.rvec, -s.pose.tvec};
  EXPECT_FALSE(refinePlanarPose(kK, s.plane, s.image, {}, {}, behind)) << "behind the camera";
  EXPECT_FALSE(planarPoseFromHomography(kK, cv::Matx33d::zeros(), s.plane, s.image, {}, {}, out, rms));
  EXPECT_TRUE(std::isnan(reprojectionRms(kK, s.pose, {}, {}, {})));
  std::vector<cv::Point2f> projected(1);
  const cv::Point2f behindPoint[1] = {cv::Point2f(0, 0)};
  projectPlanePoints(kK, PlanarPose{cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, -1)}, behindPoint, projected);
  EXPECT_TRUE(std::isnan(projected[0].x));
}

TEST(TrackingPrimitives, ProjectionIsCvProjectPoints) {
  const PlaneScene s = planeScene(50, 0, 0, 8);
  EXPECT_LT(cv::norm(planeToImage(kK, s.pose) - planeToImageHomography(kK, s.pose), cv::NORM_INF), 1e-9);
  std::vector<cv::Point3f> object;
  for (const cv::Point2f& p : s.plane) object.emplace_back(p.x, 0.f, p.y);
  std::vector<cv::Point2f> theirs, ours(s.plane.size());
  cv::projectPoints(object, s.pose.rvec, s.pose.tvec, kK, cv::noArray(), theirs);
  projectPlanePoints(kK, s.pose, s.plane, ours);
  for (std::size_t i = 0; i < ours.size(); ++i) EXPECT_LT(cv::norm(ours[i] - theirs[i]), 1e-4);
}

TEST(TrackingPrimitives, RodriguesRoundTripsNearZeroAndPi) {
  cv::RNG rng(3);
  std::vector<cv::Vec3d> cases{{0, 0, 0}, {1e-12, 0, 0}, {0, -3e-9, 1e-9}, {1e-5, 2e-5, -1e-5},
                               {CV_PI, 0, 0}, {0, -CV_PI, 0}, {0, 0, CV_PI - 1e-9}};
  const cv::Vec3d axis = cv::normalize(cv::Vec3d(1, -2, 0.5));
  cases.push_back(axis * CV_PI);
  cases.push_back(axis * (CV_PI - 1e-7));
  for (int i = 0; i < 200; ++i) {
    const cv::Vec3d a = cv::normalize(cv::Vec3d(rng.gaussian(1), rng.gaussian(1), rng.gaussian(1)));
    cases.push_back(a * rng.uniform(0.0, CV_PI));
  }
  for (const cv::Vec3d& r : cases) {
    const cv::Matx33d ours = rotationFromRodrigues(r);
    cv::Matx33d theirs;
    cv::Rodrigues(r, theirs);
    EXPECT_LT(cv::norm(ours - theirs, cv::NORM_INF), 1e-12) << r;
    EXPECT_LT(cv::norm(ours * ours.t() - cv::Matx33d::eye(), cv::NORM_INF), 1e-14) << r;
    const cv::Vec3d back = rodriguesFromRotation(ours);
    // At pi, r and -r are the same rotation.
    const double d = std::min(cv::norm(back - r), cv::norm(r) > 3.14 ? cv::norm(back + r) : 1e9);
    EXPECT_LT(d, cv::norm(r) > 3.14 ? 1e-7 : 1e-12) << r << " -> " << back;
    EXPECT_LT(cv::norm(rotationFromRodrigues(back) - ours, cv::NORM_INF), 1e-12) << r;
  }
}

TEST(TrackingPrimitives, NearestRotationIsThePolarFactor) {
  cv::RNG rng(5);
  for (int i = 0; i < 50; ++i) {
    const cv::Matx33d r = rotationFromRodrigues(cv::Vec3d(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)));
    cv::Matx33d m = r;
    for (double& v : m.val) v += rng.gaussian(0.05);
    cv::Mat w, u, vt;
    cv::SVD::compute(cv::Mat(m), w, u, vt);
    const cv::Matx33d expected(cv::Mat(u * vt));
    EXPECT_LT(cv::norm(nearestRotation(m) - expected, cv::NORM_INF), 1e-9);
    EXPECT_LT(cv::norm(nearestRotation(r) - r, cv::NORM_INF), 1e-12);
  }
}

TEST(TrackingPrimitives, SameInputGivesTheSameBits) {
  const KltCase c = knownMotion(motion(1, 1.01, 9.2, 3.1, 1e-5));
  std::vector<cv::Point2f> first, second;
  runOurs(c, LkGradient::Scharr, &first);
  runOurs(c, LkGradient::Scharr, &second);
  ASSERT_EQ(first.size(), second.size());
  EXPECT_TRUE(sameBits(first.data(), second.data(), first.size() * sizeof(cv::Point2f)));

  const PlaneScene s = planeScene(200, 0.5, 0.3, 1);
  HomographyRansac ransac;
  ransac.reserve(200);
  cv::Matx33d h1, h2;
  std::vector<unsigned char> m1(200), m2(200);
  int n1 = 0, n2 = 0;
  ASSERT_TRUE(ransac.estimate(s.plane, s.image, {}, h1, m1, n1));
  ASSERT_TRUE(ransac.estimate(s.plane, s.image, {}, h2, m2, n2));
  EXPECT_TRUE(sameBits(h1.val, h2.val, sizeof(h1.val)));
  EXPECT_EQ(m1, m2);
  PlanarPose p1, p2;
  double r1 = 0, r2 = 0;
  ASSERT_TRUE(planarPoseFromHomography(kK, h1, s.plane, s.image, m1, {}, p1, r1));
  ASSERT_TRUE(planarPoseFromHomography(kK, h1, s.plane, s.image, m1, {}, p2, r2));
  EXPECT_TRUE(sameBits(&p1, &p2, sizeof(p1)));
  EXPECT_TRUE(sameBits(&r1, &r2, sizeof(r1)));

  cv::Mat a(480, 640, CV_8UC1, cv::Scalar(0)), b(480, 640, CV_8UC1, cv::Scalar(0));
  ASSERT_TRUE(warpPerspectiveRegion(c.prev, motion(5, 0.8, 3, 4, 1e-4), a, cv::Rect(0, 0, 640, 480), 5));
  ASSERT_TRUE(warpPerspectiveRegion(c.prev, motion(5, 0.8, 3, 4, 1e-4), b, cv::Rect(0, 0, 640, 480), 5));
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0);
}

}  // namespace

// The share of the image a target covers (the floor around it makes the rest: map extension,
// issue 40): a camera looking straight down sees a w x h target as fx w / d by fy h / d pixels;
// tilted towards the horizon, the sky (rays that meet the plane behind the camera) counts for
// nothing, however the homography maps it.
namespace {
double bruteForceShare(const cv::Matx33d& K, const CameraModel& camera, const PlanarPose& pose, double w, double h) {
  const cv::Matx33d g = planeToImageHomography(K, pose), toPlane = g.inv();
  int inside = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const cv::Vec3d q = toPlane * cv::Vec3d(x, y, 1);
      const double px = q[0] / q[2], pz = q[1] / q[2];
      inside += (g * cv::Vec3d(px, pz, 1))[2] > 0 && std::abs(px) <= w / 2 && std::abs(pz) <= h / 2;
    }
  return static_cast<double>(inside) / (camera.width * camera.height);
}
}  // namespace

TEST(TrackingPrimitives, TargetImageShareIsTheShareOfPixelsOnTheTarget) {
  CameraModel camera;
  camera.width = 640, camera.height = 480, camera.fx = camera.fy = 600, camera.cx = 319.5, camera.cy = 239.5;
  const double w = 0.3, h = 0.2;
  // Straight down from d: camera x = X, y = Z, z = d - Y.
  for (const double d : {0.5, 0.8, 1.5}) {
    PlanarPose down;
    down.rvec = rodriguesFromRotation(cv::Matx33d(1, 0, 0, 0, 0, 1, 0, -1, 0));
    down.tvec = cv::Vec3d(0, 0, d);
    const double expected = std::min(1.0, 600 * w / d / 640) * std::min(1.0, 600 * h / d / 480);
    EXPECT_NEAR(targetImageShare(kK, camera, down, w, h), expected, 0.04) << d;
    EXPECT_NEAR(targetImageShare(kK, camera, down, w, h), bruteForceShare(kK, camera, down, w, h), 0.03) << d;
  }
  // 80 deg from straight down, 1 m above the plane: the top of the image is sky.
  const double tilt = 80 * 3.14159265358979323846 / 180;
  const cv::Matx33d down(1, 0, 0, 0, 0, 1, 0, -1, 0);
  const cv::Matx33d pitch(1, 0, 0, 0, std::cos(tilt), -std::sin(tilt), 0, std::sin(tilt), std::cos(tilt));
  PlanarPose oblique;
  oblique.rvec = rodriguesFromRotation(pitch * down);
  oblique.tvec = pitch * cv::Vec3d(0, 0, 1.0);
  const double grid = targetImageShare(kK, camera, oblique, 40, 40);  // a plane 40 m wide: all of the ground in view
  EXPECT_NEAR(grid, bruteForceShare(kK, camera, oblique, 40, 40), 0.05);
  EXPECT_GT(grid, 0.2);
  EXPECT_LT(grid, 0.8) << "the sky is not the target";
}

// Relocalization's matcher against OpenCV's brute force (cv::BFMatcher, NORM_HAMMING, k = 2) on
// random ORB-sized descriptors, with duplicates planted so that ties occur: the nearest and
// second-nearest distances are OpenCV's, the nearest row the lowest of those at that distance.
// (It read each descriptor through a 32-byte copy: the words must be the same ones.)
TEST(TrackingPrimitives, HammingMatcherIsBruteForceToTheBit) {
  cv::RNG rng(11);
  cv::Mat query(300, 32, CV_8UC1), train(450, 32, CV_8UC1);
  rng.fill(query, cv::RNG::UNIFORM, 0, 256);
  rng.fill(train, cv::RNG::UNIFORM, 0, 256);
  // Near copies (one bit flipped) of the first 60 queries in the train set, and a tie: query 100
  // copied exactly into train rows 420 and 200 (the lower one wins).
  for (int i = 0; i < 60; ++i) {
    query.row(i).copyTo(train.row(3 * i));
    train.at<std::uint8_t>(3 * i, i % 32) ^= static_cast<std::uint8_t>(1u << (i % 8));
  }
  query.row(100).copyTo(train.row(420));
  query.row(100).copyTo(train.row(200));
  std::vector<HammingMatch> ours;
  ours.reserve(static_cast<std::size_t>(query.rows));
  matchNearestTwo(query, train, ours);
  ASSERT_EQ(ours.size(), static_cast<std::size_t>(query.rows));
  std::vector<std::vector<cv::DMatch>> theirs;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(query, train, theirs, 2);
  ASSERT_EQ(theirs.size(), ours.size());
  for (int q = 0; q < query.rows; ++q) {
    const HammingMatch& m = ours[static_cast<std::size_t>(q)];
    ASSERT_EQ(theirs[static_cast<std::size_t>(q)].size(), 2u);
    EXPECT_EQ(m.query, q);
    EXPECT_EQ(m.distance, static_cast<int>(theirs[static_cast<std::size_t>(q)][0].distance)) << q;
    EXPECT_EQ(m.second, static_cast<int>(theirs[static_cast<std::size_t>(q)][1].distance)) << q;
    int lowest = -1;
    for (int t = 0; t < train.rows && lowest < 0; ++t)
      if (cv::norm(query.row(q), train.row(t), cv::NORM_HAMMING) == m.distance) lowest = t;
    EXPECT_EQ(m.train, lowest) << q;
  }
  EXPECT_EQ(ours[0].distance, 1);  // the planted near copies are found
  EXPECT_EQ(ours[0].train, 0);
  EXPECT_EQ(ours[100].train, 200);
  EXPECT_EQ(ours[100].distance, 0);
  EXPECT_EQ(ours[100].second, 0);
  // One train row: no second (257, past any distance).
  matchNearestTwo(query, train.rowRange(5, 6), ours);
  ASSERT_EQ(ours.size(), static_cast<std::size_t>(query.rows));
  EXPECT_EQ(ours[7].train, 0);
  EXPECT_EQ(ours[7].second, 257);
  // Wrong shapes give nothing.
  matchNearestTwo(query.colRange(0, 16), train.colRange(0, 16), ours);
  EXPECT_TRUE(ours.empty());
}
