// The synthetic sequences' renderer, scenarios and trajectory metrics (tests/support/tracking).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "test_data.hpp"
#include "tracking/scenario_run.hpp"
#include "tracking/scenarios.hpp"
#include "tracking/synthetic_sequence.hpp"
#include "tracking/trajectory_metrics.hpp"

namespace {

using namespace marionette::ar;
using namespace marionette::ar::synthetic;

CameraModel camera640(double k1 = 0) {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 600;
  c.cx = 319.5;
  c.cy = 239.5;
  c.distortion[0] = k1;
  return c;
}

cv::Mat flat(int w, int h, cv::Vec3b rgb) { return cv::Mat(h, w, CV_8UC3, cv::Scalar(rgb[0], rgb[1], rgb[2])); }

// 8 x 6 squares of 64 px filling the whole target: 7 x 5 inner corners, the centre one at
// the target's centre.
cv::Mat chessboard() {
  cv::Mat m(6 * 64, 8 * 64, CV_8UC3);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x) m.at<cv::Vec3b>(y, x) = ((x / 64 + y / 64) % 2 == 0) ? cv::Vec3b(20, 20, 20)
                                                                                            : cv::Vec3b(235, 235, 235);
  return m;
}

cv::Mat graf1() {
  const std::string path = marionette::test::opencvData("graf1.png");
  EXPECT_TRUE(std::filesystem::exists(path)) << "test data missing: " << path << " (Debian opencv-doc)";
  cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR), rgb;
  if (bgr.empty()) ADD_FAILURE() << "cannot read " << path;
  else cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

glm::dmat4 lookingDown(double x, double height, double z = 0) {
  return lookAtCameraToWorld({x, height, z}, {x, 0, z}, {0, 0, -1});  // image right = +X, down = +Z
}

// Pixels nearer to `c` than to anything 40 levels away, per channel sum.
int countNear(const cv::Mat& rgb, cv::Vec3b c) {
  int n = 0;
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x) {
      const cv::Vec3b p = rgb.at<cv::Vec3b>(y, x);
      if (std::abs(p[0] - c[0]) + std::abs(p[1] - c[1]) + std::abs(p[2] - c[2]) < 40) ++n;
    }
  return n;
}

TEST(SyntheticSequenceCamera, DataFileIsTheUndistortedVga) {
  marionette::Diagnostics d;
  const auto c = readCameraModel(marionette::test::sourceFile("assets/cameras/synthetic_640x480.yml"), d);
  ASSERT_TRUE(c) << d.format();
  EXPECT_EQ(c->width, 640);
  EXPECT_EQ(c->height, 480);
  EXPECT_EQ(c->fx, 600);
  EXPECT_EQ(c->fy, 600);
  EXPECT_EQ(c->cx, 319.5);
  EXPECT_EQ(c->cy, 239.5);
  EXPECT_FALSE(c->hasDistortion());
}

TEST(SyntheticSequenceCamera, LookAtLooksAtTheTarget) {
  for (double k1 : {0.0, -0.2}) {
    const CameraModel cam = camera640(k1);
    const glm::dvec3 eye(0.2, 0.5, 0.4);
    const glm::dmat4 m = lookAtCameraToWorld(eye, glm::dvec3(0), glm::dvec3(0, 1, 0));
    const glm::dvec2 centre = projectWorldPoint(cam, m, glm::dvec3(0));
    EXPECT_NEAR(centre.x, cam.cx, 1e-9);
    EXPECT_NEAR(centre.y, cam.cy, 1e-9);
    EXPECT_NEAR(glm::length(glm::dvec3(m[3]) - eye), 0, 1e-15);
    EXPECT_NEAR(glm::determinant(glm::dmat3(m)), 1, 1e-12);
    const glm::dmat3 gram = glm::transpose(glm::dmat3(m)) * glm::dmat3(m);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(gram[a][b], a == b ? 1 : 0, 1e-12);
    // World up is image up; the camera looks along its -Z.
    EXPECT_LT(projectWorldPoint(cam, m, {0, 0.05, 0}).y, cam.cy - 10);
    EXPECT_NEAR(glm::dot(-glm::dvec3(m[2]), glm::normalize(-eye)), 1, 1e-12);
  }
  // Straight down with +Y as up: still a rotation, the centre still at the principal point.
  const glm::dmat4 down = lookAtCameraToWorld({0, 0.6, 0}, glm::dvec3(0), {0, 1, 0});
  EXPECT_NEAR(glm::determinant(glm::dmat3(down)), 1, 1e-12);
  EXPECT_NEAR(projectWorldPoint(camera640(), down, glm::dvec3(0)).x, 319.5, 1e-9);
}

// The chessboard's inner corners found in the rendered frame sit where projectWorldPoint puts
// them, with and without lens distortion.
TEST(SyntheticSequenceRender, ChessboardCornersLandWhereProjectPointsSays) {
  const glm::dmat4 poses[] = {
      orbitPose(20, 60, 0.6),
      orbitPose(-35, 45, 0.7, 6),
      // The board in the upper-left of the image, where k1 moves it most.
      lookAtCameraToWorld({0.15, 0.55, 0.3}, {0.17, 0, 0.17}, {0, 1, 0}),
  };
  for (double k1 : {0.0, -0.2}) {
    PlanarScene scene{chessboard(), 0.3, flat(16, 16, {255, 255, 255})};
    const SequenceRenderer renderer(scene, camera640(k1));
    double largestLensShift = 0;
    for (const glm::dmat4& pose : poses) {
      cv::Mat rgb, grey;
      renderer.render(pose, {}, rgb);
      cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
      std::vector<cv::Point2f> found;
      ASSERT_TRUE(cv::findChessboardCorners(grey, {7, 5}, found, cv::CALIB_CB_ADAPTIVE_THRESH)) << "k1 " << k1;
      cv::cornerSubPix(grey, found, {5, 5}, {-1, -1}, {cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4});
      double worst = 0;
      for (int r = 1; r <= 5; ++r)
        for (int c = 1; c <= 7; ++c) {
          // Between pixel columns c*64-1 and c*64: at u = c*64 - 0.5.
          const glm::dvec3 world = renderer.targetPixelToWorld(c * 64 - 0.5, r * 64 - 0.5);
          const glm::dvec2 want = projectWorldPoint(renderer.camera(), pose, world);
          largestLensShift = std::max(largestLensShift, glm::length(want - projectWorldPoint(camera640(), pose, world)));
          double nearest = 1e9;
          for (const cv::Point2f& f : found) nearest = std::min(nearest, std::hypot(f.x - want.x, f.y - want.y));
          worst = std::max(worst, nearest);
          if (r == 3 && c == 4) {
            EXPECT_NEAR(glm::length(world), 0, 1e-15) << "the centre corner is the origin";
          }
        }
      EXPECT_LT(worst, 0.2) << "k1 " << k1;
    }
    if (k1 != 0) {
      EXPECT_GT(largestLensShift, 3.0) << "the distorted case must differ from the pinhole one";
    }
  }
}

// A dark target on a white floor: just inside each projected target corner is dark, just
// outside is white.
TEST(SyntheticSequenceRender, TargetCornersAndCentre) {
  for (double k1 : {0.0, -0.2}) {
    PlanarScene scene{flat(400, 300, {30, 30, 30}), 0.3, flat(8, 8, {255, 255, 255})};
    scene.target.at<cv::Vec3b>(150, 200) = {255, 255, 255};
    const SequenceRenderer renderer(scene, camera640(k1));
    const glm::dmat4 pose = orbitPose(25, 55, 0.65, 4);
    cv::Mat rgb;
    renderer.render(pose, {}, rgb);
    const glm::dvec2 centre = projectWorldPoint(renderer.camera(), pose, glm::dvec3(0));
    const double hw = 0.15, hd = renderer.targetDepth() / 2;
    for (const glm::dvec3 corner : {glm::dvec3(-hw, 0, -hd), glm::dvec3(hw, 0, -hd), glm::dvec3(hw, 0, hd),
                                    glm::dvec3(-hw, 0, hd)}) {
      const glm::dvec2 p = projectWorldPoint(renderer.camera(), pose, corner);
      const glm::dvec2 in = p + 2.5 * glm::normalize(centre - p), out = p - 2.5 * glm::normalize(centre - p);
      const auto at = [&](glm::dvec2 q) { return rgb.at<cv::Vec3b>(int(std::lround(q.y)), int(std::lround(q.x)))[1]; };
      EXPECT_LT(at(in), 60) << "k1 " << k1 << " inside corner " << corner.x << "," << corner.z;
      EXPECT_GT(at(out), 200) << "k1 " << k1 << " outside corner " << corner.x << "," << corner.z;
    }
    // The one white pixel at the target's centre brightens the pixel the centre projects to.
    const cv::Vec3b c = rgb.at<cv::Vec3b>(int(std::lround(centre.y)), int(std::lround(centre.x)));
    EXPECT_GT(c[1], 45) << "k1 " << k1;
  }
}

// The photo where a plain cv::warpPerspective by K [r1 r3 t] (built here from the
// conventions, independently of the renderer) puts it: orientation of u and v included.
TEST(SyntheticSequenceRender, PhotoMatchesTheHomographyWarp) {
  const cv::Mat target = graf1();
  ASSERT_FALSE(target.empty());
  const SequenceRenderer renderer({target, 0.3, {}}, camera640());
  const glm::dmat4 pose = orbitPose(30, 50, 0.7, 5);
  glm::dmat3 r;
  glm::dvec3 t;
  worldToOpenCvCamera(pose, r, t);
  const double s = 0.3 / target.cols;
  const cv::Matx33d k(600, 0, 319.5, 0, 600, 239.5, 0, 0, 1);
  const cv::Matx33d rt(r[0].x, r[2].x, t.x, r[0].y, r[2].y, t.y, r[0].z, r[2].z, t.z);
  const cv::Matx33d a(s, 0, (0.5 - target.cols / 2.0) * s, 0, s, (0.5 - target.rows / 2.0) * s, 0, 0, 1);
  cv::Mat warped, mask;
  cv::warpPerspective(target, warped, k * rt * a, {640, 480}, cv::INTER_AREA);
  cv::warpPerspective(cv::Mat(target.size(), CV_8U, cv::Scalar(255)), mask, k * rt * a, {640, 480}, cv::INTER_NEAREST);
  cv::erode(mask, mask, cv::Mat(), {-1, -1}, 4);
  ASSERT_GT(cv::countNonZero(mask), 30000);
  cv::Mat rendered;
  renderer.render(pose, {}, rendered);
  // Filters differ (mip levels against bilinear); blur both to compare the picture itself.
  cv::Mat a1, b1, diff;
  cv::GaussianBlur(rendered, a1, {0, 0}, 2);
  cv::GaussianBlur(warped, b1, {0, 0}, 2);
  cv::absdiff(a1, b1, diff);
  EXPECT_LT(cv::mean(diff, mask)[1], 3.0);
  // Mirrored, the photo would differ a lot: the comparison can tell.
  cv::Mat flipped, f1, diffFlipped;
  cv::flip(target, flipped, 1);
  cv::warpPerspective(flipped, f1, k * rt * a, {640, 480}, cv::INTER_AREA);
  cv::GaussianBlur(f1, f1, {0, 0}, 2);
  cv::absdiff(a1, f1, diffFlipped);
  EXPECT_GT(cv::mean(diffFlipped, mask)[1], 15.0);
}

TEST(SyntheticSequenceRender, SkyAboveTheHorizonFloorBelow) {
  const SequenceRenderer renderer({flat(64, 64, {0, 255, 0}), 0.3, {}}, camera640());
  cv::Mat rgb;
  // Looking away from the target: the plane behind the camera must not show in the sky.
  renderer.render(lookAtCameraToWorld({0, 0.5, 0.5}, {0, 0.5, 2}, {0, 1, 0}), {}, rgb);
  EXPECT_EQ(countNear(rgb.rowRange(0, 230), kSkyRgb), 640 * 230);
  EXPECT_EQ(countNear(rgb.rowRange(250, 480), {128, 128, 128}), 640 * 230);
}

TEST(SyntheticSequenceVisibility, AboveAwayAndHalf) {
  const cv::Vec3b green{40, 200, 40};
  const SequenceRenderer renderer({flat(400, 320, green), 0.3, {}}, camera640());
  EXPECT_DOUBLE_EQ(renderer.visibleTargetFraction(lookingDown(0, 0.6)), 1.0);
  EXPECT_DOUBLE_EQ(renderer.visibleTargetFraction(lookAtCameraToWorld({0, 0.6, 0}, {0, 1.2, 0.1}, {0, 1, 0})), 0.0);
  EXPECT_DOUBLE_EQ(renderer.visibleTargetFraction(lookAtCameraToWorld({0, 0.3, 0.5}, {0, 0.3, 2}, {0, 1, 0})), 0.0);
  // The image's left edge (x = -0.5) over X = 0: the target's -X half is out of view.
  const double h = 0.6, x = (319.5 + 0.5) * h / 600;
  const glm::dmat4 half = lookingDown(x, h);
  EXPECT_NEAR(renderer.visibleTargetFraction(half), 0.5, 0.02);
  // The rendered frame agrees: half of the target's projected area (300 x 240 px at 0.6 m).
  cv::Mat rgb;
  renderer.render(half, {}, rgb);
  EXPECT_NEAR(countNear(rgb, green) / (300.0 * 240.0), 0.5, 0.01);
  renderer.render(lookingDown(0, h), {}, rgb);
  EXPECT_NEAR(countNear(rgb, green) / (300.0 * 240.0), 1.0, 0.01);
}

TEST(SyntheticSequenceEffects, SameSeedSameBytesOtherSeedOtherBytes) {
  const cv::Mat target = graf1();
  ASSERT_FALSE(target.empty());
  const SequenceRenderer renderer({target, 0.3, target, 0.001}, camera640(-0.2));
  FrameEffects fx;
  fx.motionBlurPx = 12;
  fx.motionBlurAngleDeg = 30;
  fx.noiseSigma = 6;
  fx.jpegQuality = 30;
  fx.gainEv = 0.5;
  fx.occluderFraction = 0.3;
  fx.occluderPhase = 0.4;
  fx.noiseSeed = 5;
  const glm::dmat4 pose = orbitPose(10, 40, 0.8);
  cv::Mat a, b, c;
  renderer.render(pose, fx, a);
  renderer.render(pose, fx, b);
  ASSERT_EQ(a.type(), CV_8UC3);
  ASSERT_EQ(a.size(), cv::Size(640, 480));
  ASSERT_TRUE(a.isContinuous() && b.isContinuous());
  EXPECT_EQ(std::memcmp(a.data, b.data, a.total() * 3), 0);
  fx.noiseSeed = 6;
  renderer.render(pose, fx, c);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 640 * 480);
}

TEST(SyntheticSequenceEffects, NoiseHasTheSigma) {
  const SequenceRenderer renderer({flat(64, 64, {100, 100, 100}), 0.3, flat(8, 8, {100, 100, 100})}, camera640());
  FrameEffects fx;
  fx.noiseSigma = 6;
  cv::Mat rgb;
  renderer.render(lookingDown(0, 0.6), fx, rgb);
  cv::Scalar mean, sd;
  cv::meanStdDev(rgb.reshape(1), mean, sd);
  EXPECT_NEAR(mean[0], 100, 0.1);
  EXPECT_NEAR(sd[0], 6, 0.1);
}

TEST(SyntheticSequenceEffects, GainDoublesMidGreyAndSaturates) {
  const SequenceRenderer renderer({flat(300, 300, {64, 64, 64}), 0.3, {}}, camera640());
  const glm::dmat4 pose = lookingDown(0, 0.6);
  cv::Mat plain, up, down;
  renderer.render(pose, {}, plain);
  FrameEffects fx;
  fx.gainEv = 1;
  renderer.render(pose, fx, up);
  fx.gainEv = -1;
  renderer.render(pose, fx, down);
  EXPECT_EQ(plain.at<cv::Vec3b>(240, 320), cv::Vec3b(64, 64, 64));
  EXPECT_EQ(up.at<cv::Vec3b>(240, 320), cv::Vec3b(128, 128, 128));
  EXPECT_EQ(down.at<cv::Vec3b>(240, 320), cv::Vec3b(32, 32, 32));
  EXPECT_EQ(plain.at<cv::Vec3b>(5, 5), cv::Vec3b(128, 128, 128));  // the floor, saturating
  EXPECT_EQ(up.at<cv::Vec3b>(5, 5), cv::Vec3b(255, 255, 255));
}

// A horizontal kernel (0 deg) smears vertical edges only, a 90 deg one horizontal edges.
TEST(SyntheticSequenceEffects, MotionBlurFollowsTheAngle) {
  const SequenceRenderer renderer({chessboard(), 0.3, flat(8, 8, {255, 255, 255})}, camera640());
  const glm::dmat4 pose = lookingDown(0, 0.5);
  auto gradients = [&](double length, double angle) {
    FrameEffects fx;
    fx.motionBlurPx = length;
    fx.motionBlurAngleDeg = angle;
    cv::Mat rgb, grey, gx, gy;
    renderer.render(pose, fx, rgb);
    cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
    cv::Sobel(grey, gx, CV_32F, 1, 0);
    cv::Sobel(grey, gy, CV_32F, 0, 1);
    return std::pair(cv::norm(gx, cv::NORM_L2), cv::norm(gy, cv::NORM_L2));
  };
  const auto sharp = gradients(0, 0), across = gradients(15, 0), down = gradients(15, 90);
  EXPECT_LT(across.first / sharp.first, 0.5);
  EXPECT_GT(across.second / sharp.second, 0.8);
  EXPECT_LT(down.second / sharp.second, 0.5);
  EXPECT_GT(down.first / sharp.first, 0.8);
}

TEST(SyntheticSequenceEffects, OccluderCoversItsShareAndSweeps) {
  const cv::Vec3b green{40, 200, 40};
  const SequenceRenderer renderer({flat(400, 320, green), 0.3, {}}, camera640());
  const glm::dmat4 pose = lookingDown(0, 0.6);
  double meanX[2];
  for (int i = 0; i < 2; ++i) {
    FrameEffects fx;
    fx.occluderFraction = 0.4;
    fx.occluderPhase = i;
    cv::Mat rgb;
    renderer.render(pose, fx, rgb);
    const int target = countNear(rgb, green), occluded = countNear(rgb, kOccluderRgb);
    EXPECT_NEAR(occluded / double(target + occluded), 0.4, 0.02);
    cv::Mat m;
    cv::inRange(rgb, cv::Scalar(kOccluderRgb[0] - 10, kOccluderRgb[1] - 10, kOccluderRgb[2] - 10),
                cv::Scalar(kOccluderRgb[0] + 10, kOccluderRgb[1] + 10, kOccluderRgb[2] + 10), m);
    meanX[i] = cv::moments(m, true).m10 / cv::moments(m, true).m00;
  }
  // 300 px wide target, 120 px wide occluder: its centre at -90 px (phase 0) and +90 px
  // (phase 1), times 1.005 for its height above the plane.
  EXPECT_NEAR(meanX[0], 319.5 - 90 * 0.6 / (0.6 - kOccluderHeight), 1);
  EXPECT_NEAR(meanX[1], 319.5 + 90 * 0.6 / (0.6 - kOccluderHeight), 1);
}

double elevationDeg(const glm::dmat4& m) {
  const glm::dvec3 p(m[3]);
  return std::asin(p.y / glm::length(p)) * 180 / 3.14159265358979323846;
}

const Scenario& byName(const std::vector<Scenario>& all, const std::string& name) {
  for (const Scenario& s : all)
    if (s.name == name) return s;
  throw std::runtime_error("no scenario " + name);
}

TEST(SyntheticSequenceScenarios, CoverWhatTheyPromise) {
  const cv::Mat target = graf1();
  ASSERT_FALSE(target.empty());
  const SequenceRenderer renderer({target, 0.3, {}}, camera640());
  const int n = 150;
  const std::vector<Scenario> all = standardScenarios(renderer, n);
  ASSERT_EQ(all.size(), standardScenarioNames().size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].name, standardScenarioNames()[i]);
    EXPECT_EQ(all[i].fps, 30);
    ASSERT_EQ(all[i].cameraToWorld.size(), std::size_t(n)) << all[i].name;
    ASSERT_EQ(all[i].effects.size(), std::size_t(n));
    ASSERT_EQ(all[i].visibleFraction.size(), std::size_t(n));
    for (int f = 0; f < n; ++f)
      EXPECT_DOUBLE_EQ(all[i].visibleFraction[f], renderer.visibleTargetFraction(all[i].cameraToWorld[f]));
  }
  auto minMax = [](const std::vector<double>& v) { return std::pair(*std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end())); };
  auto each = [&](auto f) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(f(i));
    return minMax(v);
  };
  auto maxTurnDegPerS = [&](const Scenario& s) {
    double worst = 0;
    for (int i = 1; i < n; ++i) worst = std::max(worst, rotationErrorDeg(s.cameraToWorld[i - 1], s.cameraToWorld[i]) * s.fps);
    return worst;
  };

  const Scenario& orbit = byName(all, "orbit");
  const auto dist = each([&](int i) { return glm::length(glm::dvec3(orbit.cameraToWorld[i][3])); });
  EXPECT_GE(dist.first, 0.59);
  EXPECT_LE(dist.second, 0.91);
  const auto el = each([&](int i) { return elevationDeg(orbit.cameraToWorld[i]); });
  EXPECT_GE(el.first, 35);
  EXPECT_LE(el.second, 60);
  EXPECT_EQ(minMax(orbit.visibleFraction).first, 1.0);
  // The target spans about a third to a half of the image's width.
  const auto span = each([&](int i) {
    double lo = 1e9, hi = -1e9;
    for (const glm::dvec3 c : {glm::dvec3(-0.15, 0, -0.12), glm::dvec3(0.15, 0, -0.12), glm::dvec3(0.15, 0, 0.12),
                               glm::dvec3(-0.15, 0, 0.12)}) {
      const double x = projectWorldPoint(renderer.camera(), orbit.cameraToWorld[i], c).x;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    return (hi - lo) / 640;
  });
  EXPECT_GT(span.first, 0.3) << span.second;
  EXPECT_LT(span.second, 0.6) << span.first;

  const Scenario& still = byName(all, "static");
  for (int i = 1; i < n; ++i) {
    EXPECT_EQ(still.cameraToWorld[i], still.cameraToWorld[0]);
    EXPECT_EQ(still.effects[i].noiseSigma, 2);
    EXPECT_NE(still.effects[i].noiseSeed, still.effects[i - 1].noiseSeed);
  }

  const Scenario& fast = byName(all, "fast_turn");
  EXPECT_GE(maxTurnDegPerS(fast), 180);
  EXPECT_LT(minMax(fast.visibleFraction).first, 1.0);
  EXPECT_LE(maxTurnDegPerS(orbit), 60);

  const Scenario& blur = byName(all, "blur");
  // Sharp for the first 10 %, then 9..25 px.
  EXPECT_EQ(blur.effects.front().motionBlurPx, 0.0);
  const auto len = each([&](int i) { return i < n / 10 + 1 ? 17.0 : blur.effects[i].motionBlurPx; });
  EXPECT_GE(len.first, 9);
  EXPECT_LE(len.first, 10);
  EXPECT_LE(len.second, 25);
  EXPECT_GE(len.second, 24);

  for (const FrameEffects& fx : byName(all, "noise_jpeg").effects) {
    EXPECT_EQ(fx.noiseSigma, 6);
    EXPECT_EQ(fx.jpegQuality, 30);
  }

  const Scenario& gain = byName(all, "gain");
  const auto ev = each([&](int i) { return gain.effects[i].gainEv; });
  EXPECT_LT(ev.first, -0.95);
  EXPECT_GT(ev.second, 0.95);
  EXPECT_GE(ev.first, -1);
  EXPECT_LE(ev.second, 1);
  for (int i = 1; i < n; ++i) EXPECT_LT(std::abs(gain.effects[i].gainEv - gain.effects[i - 1].gainEv), 0.06);

  const Scenario& occ = byName(all, "occluder");
  const auto share = each([&](int i) { return occ.effects[i].occluderFraction; });
  EXPECT_GE(share.first, 0.2);
  EXPECT_LE(share.second, 0.6);
  const auto phase = each([&](int i) { return occ.effects[i].occluderPhase; });
  EXPECT_LT(phase.first, 0.05);
  EXPECT_GT(phase.second, 0.95);

  // Whole at the start and the end; 20..50 % in view in the middle half.
  const Scenario& partialScenario = byName(all, "partial");
  EXPECT_EQ(partialScenario.visibleFraction.front(), 1.0);
  EXPECT_EQ(partialScenario.visibleFraction.back(), 1.0);
  const std::vector<double> middle(partialScenario.visibleFraction.begin() + n * 3 / 10,
                                   partialScenario.visibleFraction.begin() + n * 8 / 10);
  const auto partial = minMax(middle);
  EXPECT_GE(partial.first, 0.195);
  EXPECT_LE(partial.second, 0.505);

  const Scenario& grazing = byName(all, "grazing");
  const auto gel = each([&](int i) { return elevationDeg(grazing.cameraToWorld[i]); });
  EXPECT_NEAR(gel.first, 20, 0.1);
  EXPECT_NEAR(gel.second, 50, 0.1);

  const Scenario& lost = byName(all, "lost_regained");
  EXPECT_EQ(lost.visibleFraction.front(), 1.0);
  EXPECT_EQ(lost.visibleFraction.back(), 1.0);
  int invisible = 0, stretches = 0;
  for (int i = 0; i < n; ++i) {
    invisible += lost.visibleFraction[i] == 0;
    stretches += lost.visibleFraction[i] == 0 && (i == 0 || lost.visibleFraction[i - 1] > 0);
  }
  EXPECT_EQ(stretches, 1);
  EXPECT_NEAR(invisible / double(n), 1.0 / 3, 0.05);

  // Deterministic.
  const std::vector<Scenario> again = standardScenarios(renderer, n);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(again[i].cameraToWorld, all[i].cameraToWorld) << all[i].name;
    EXPECT_EQ(again[i].visibleFraction, all[i].visibleFraction) << all[i].name;
  }
}

std::vector<TrackedPose> asTracked(const std::vector<glm::dmat4>& poses, TrackingState state = TrackingState::Tracking) {
  std::vector<TrackedPose> out(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) out[i] = {state, poses[i], 50, 0.5};
  return out;
}

std::vector<glm::dmat4> path(int n) {
  std::vector<glm::dmat4> p;
  for (int i = 0; i < n; ++i) p.push_back(orbitPose(7.0 * i, 40 + i, 0.7, i));
  return p;
}

TEST(SyntheticSequenceMetrics, TruthAgainstItselfAndOffsets) {
  const std::vector<glm::dmat4> truth = path(20);
  const std::vector<double> visible(20, 1.0);
  const TrajectoryReport same = compareTrajectory(asTracked(truth), truth, visible, camera640());
  EXPECT_EQ(same.frames, 20);
  EXPECT_EQ(same.visibleFrames, 20);
  EXPECT_EQ(same.trackedFrames, 20);
  EXPECT_EQ(same.verifiedFrames, 20);
  EXPECT_EQ(same.within2cm, 20);
  EXPECT_EQ(same.ateRmsM, 0);
  EXPECT_EQ(same.ateMaxM, 0);
  EXPECT_NEAR(same.rotationMaxDeg, 0, 1e-6);
  EXPECT_EQ(same.falsePoses, 0);
  EXPECT_EQ(same.framesToRelocalize, -1);

  for (const double offset : {0.01, 0.03, 0.06}) {
    std::vector<TrackedPose> est = asTracked(truth, TrackingState::Limited);
    for (TrackedPose& p : est) p.cameraToWorld[3] += glm::dvec4(0, offset, 0, 0);
    const TrajectoryReport r = compareTrajectory(est, truth, visible, camera640());
    EXPECT_NEAR(r.ateRmsM, offset, 1e-12);
    EXPECT_NEAR(r.ateMaxM, offset, 1e-12);
    EXPECT_EQ(r.verifiedFrames, 0);
    EXPECT_EQ(r.trackedFrames, 20);
    EXPECT_EQ(r.within2cm, offset <= 0.02 ? 20 : 0);
    EXPECT_EQ(r.falsePoses, 0) << "LIMITED poses are never false";
    for (TrackedPose& p : est) p.state = TrackingState::Tracking;
    EXPECT_EQ(compareTrajectory(est, truth, visible, camera640()).falsePoses, offset > 0.05 ? 20 : 0);
  }

  std::vector<TrackedPose> turned = asTracked(truth);
  for (TrackedPose& p : turned) p.cameraToWorld = p.cameraToWorld * glm::rotate(glm::dmat4(1.0), glm::radians(2.0), glm::normalize(glm::dvec3(1, 2, 3)));
  const TrajectoryReport rot = compareTrajectory(turned, truth, visible, camera640());
  EXPECT_NEAR(rot.rotationMeanDeg, 2, 1e-9);
  EXPECT_NEAR(rot.rotationMaxDeg, 2, 1e-9);
  EXPECT_NEAR(rot.ateMaxM, 0, 1e-15);
}

TEST(SyntheticSequenceMetrics, TrackingOutOfViewIsCountedApartAndFalseOnlyWhenOff) {
  const std::vector<glm::dmat4> truth = path(10);
  std::vector<double> visible(10, 0.8);
  visible[3] = visible[4] = visible[5] = 0;
  std::vector<TrackedPose> est = asTracked(truth);
  est[5].state = TrackingState::Limited;
  TrajectoryReport r = compareTrajectory(est, truth, visible, camera640());
  EXPECT_EQ(r.falsePoses, 0);
  EXPECT_EQ(r.trackedOutOfView, 2);
  est[4].cameraToWorld[3].x += 0.06;  // out of view and 6 cm off: false
  EXPECT_EQ(compareTrajectory(est, truth, visible, camera640()).falsePoses, 1);
  est[4] = asTracked(truth)[4];
  r = compareTrajectory(est, truth, visible, camera640());
  EXPECT_EQ(r.visibleFrames, 7);
  EXPECT_EQ(r.within2cm, 7);
  EXPECT_EQ(r.framesToRelocalize, 0);
}

TEST(SyntheticSequenceMetrics, FramesToRelocalize) {
  const std::vector<glm::dmat4> truth = path(30);
  std::vector<double> visible(30, 1.0);
  for (int i = 10; i < 20; ++i) visible[i] = 0;
  std::vector<TrackedPose> est = asTracked(truth);
  for (int i = 10; i < 23; ++i) est[i].state = TrackingState::Lost;
  est[23].state = TrackingState::Limited;
  EXPECT_EQ(compareTrajectory(est, truth, visible, camera640()).framesToRelocalize, 4);
  for (int i = 23; i < 30; ++i) est[i].state = TrackingState::Limited;
  EXPECT_EQ(compareTrajectory(est, truth, visible, camera640()).framesToRelocalize, -1) << "never TRACKING again";
  // Invisible at the start only: nothing to relocalize after.
  std::vector<double> late(30, 1.0);
  for (int i = 0; i < 5; ++i) late[i] = 0;
  EXPECT_EQ(compareTrajectory(asTracked(truth), truth, late, camera640()).framesToRelocalize, -1);
}

TEST(SyntheticSequenceMetrics, JitterOfAStaticCamera) {
  const double h = 0.5;
  const std::vector<glm::dmat4> truth(12, lookingDown(0, h));
  std::vector<TrackedPose> est = asTracked(truth);
  for (int i = 0; i < 12; ++i) est[i].cameraToWorld[3].x += (i % 2 ? 0.001 : -0.001);
  const TrajectoryReport r = compareTrajectory(est, truth, std::vector<double>(12, 1.0), camera640());
  EXPECT_NEAR(r.jitterMm, 1.0, 1e-9);
  EXPECT_NEAR(r.jitterPx, 600 * 0.001 / h, 1e-6);  // the origin moves fx * dx / height pixels
  EXPECT_NEAR(r.ateRmsM, 0.001, 1e-12);
}

TEST(SyntheticSequenceMetrics, NothingTrackedAndMismatchedLengths) {
  const std::vector<glm::dmat4> truth = path(5);
  const std::vector<double> visible(5, 1.0);
  const TrajectoryReport r = compareTrajectory(asTracked(truth, TrackingState::Lost), truth, visible, camera640());
  EXPECT_EQ(r.trackedFrames, 0);
  EXPECT_TRUE(std::isnan(r.ateRmsM));
  EXPECT_TRUE(std::isnan(r.jitterMm));
  const std::string line = formatReport(r);
  EXPECT_NE(line.find("frames 5 visible 5 tracked 0"), std::string::npos) << line;
  EXPECT_NE(line.find("ATE rms n/a"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_THROW((void)compareTrajectory(asTracked(path(4)), truth, visible, camera640()), std::invalid_argument);
  const TrajectoryReport good = compareTrajectory(asTracked(truth), truth, visible, camera640());
  EXPECT_NE(formatReport(good).find("ATE rms 0.0 mm"), std::string::npos) << formatReport(good);
}

}  // namespace

// The scene samples taken four at a time (AVX2, scene_samples_avx2.cpp) give the scalar loop's
// bits, float for float, before the effects and the rounding: on the standard scene (the
// target and the tiled floor, pinhole), through a lens that folds back at the corners (rays
// with no inverse), without a floor, and 641 pixels wide (a scalar tail on every row); from
// views close up (magnified texels, clamped edges), at the horizon (sky, the floor fading into
// its mean), from 40 m (the target past its last level), from the floor itself (no ground
// plane), above and beside the target, rolled,
// with the flat occluder bar and with a hand over the target; one sub-frame (every supersample) and five (each phase).
TEST(SyntheticSequenceRender, WideSceneSamplesGiveTheScalarLoopsBits) {
  if (!sceneSamplesWideAvailable()) {
    std::printf("[ simd ] AVX2 absent: the scalar loop alone ran\n");
    SUCCEED();
    return;
  }
  std::printf("[ simd ] AVX2 present\n");
  const SequenceRenderer standard = standardRenderer();
  const cv::Mat target = cv::imread(standardTargetImage(), cv::IMREAD_COLOR);
  ASSERT_FALSE(target.empty());
  cv::Mat targetRgb, floorRgb;
  cv::cvtColor(target, targetRgb, cv::COLOR_BGR2RGB);
  cv::resize(targetRgb, floorRgb, cv::Size(96, 80), 0, 0, cv::INTER_AREA);
  const SequenceRenderer folded(PlanarScene{targetRgb, 0.4, floorRgb, 0.004}, camera640(-0.8));
  const SequenceRenderer bare(PlanarScene{targetRgb, 0.4, cv::Mat(), 0.002}, camera640());
  CameraModel odd = camera640();  // rows of 1282 supersamples: a scalar tail after the groups of four
  odd.width = 641;
  odd.cx = 320;
  const SequenceRenderer oddWidth(PlanarScene{targetRgb, 0.4, floorRgb, 0.004}, odd);
  cv::RNG rng(40);
  std::vector<glm::dmat4> poses = {
      lookAtCameraToWorld({0, 0.6, 0.5}, {0, 0, 0}, {0, 1, 0}),         // the usual view
      lookAtCameraToWorld({0.02, 0.05, 0.01}, {0.05, 0, 0}, {0, 1, 0}),  // close up: texels magnified
      lookAtCameraToWorld({0, 0.12, 1.5}, {0, 0.05, -30}, {0, 1, 0}),    // the horizon: sky, a fading floor
      lookAtCameraToWorld({0.3, 1.2, 0}, {0, 0, 0}, {1, 0, 0}),          // from above, rolled
      lookAtCameraToWorld({0, 0.4, 40}, {0, 0, 0}, {0, 1, 0}),           // the target past its last level
      lookAtCameraToWorld({0, 0, 1}, {0, 0, 0}, {0, 1, 0}),              // the eye on the floor: no ground
  };
  for (int i = 0; i < 2; ++i) {
    const glm::dvec3 eye(rng.uniform(-1.5, 1.5), rng.uniform(0.05, 2.0), rng.uniform(-1.5, 1.5));
    const glm::dvec3 at(rng.uniform(-0.5, 0.5), 0, rng.uniform(-0.5, 0.5));
    poses.push_back(lookAtCameraToWorld(eye, at, glm::dvec3(rng.uniform(-1, 1), 1, rng.uniform(-1, 1))));
  }
  // A soft-edged, half-transparent "hand" 10 cm above the target.
  cv::Mat handRgba(60, 90, CV_8UC4);
  for (int y = 0; y < handRgba.rows; ++y)
    for (int x = 0; x < handRgba.cols; ++x) {
      const double d = std::hypot((x - 45) / 45.0, (y - 30) / 30.0);
      handRgba.at<cv::Vec4b>(y, x) = {200, 150, 120, cv::saturate_cast<uchar>(255 * std::clamp(1.5 - 1.5 * d, 0.0, 0.8))};
    }
  Occluder hand;
  hand.texture = premultipliedTexture(handRgba);
  hand.centre = {0.05, 0.1, 0.0};
  hand.axisU = {0.003, 0, 0};
  hand.axisV = {0, 0, 0.003};
  int compared = 0, differing = 0;
  double scalarMs = 0, wideMs = 0;  // printed, not judged (speed lives in benchmarks)
  for (const SequenceRenderer* base : {&standard, &folded, &bare, &oddWidth}) {
    SequenceRenderer scalar = *base, wide = *base;
    scalar.useWideSamples(false);
    wide.useWideSamples(true);
    ASSERT_TRUE(wide.wideSamples());
    for (std::size_t p = 0; p < poses.size(); ++p) {
      FrameEffects fx;
      if (p % 3 == 1) fx.occluderFraction = 0.3, fx.occluderPhase = 0.4;
      for (int subFrames : {1, 5}) {
        std::vector<SubFrame> subs;
        const glm::dmat4 nudge = glm::translate(glm::dmat4(1.0), glm::dvec3(0.002, 0, 0.001));
        glm::dmat4 pose = poses[p];
        for (int k = 0; k < subFrames; ++k, pose = nudge * pose) subs.push_back({pose, {}});
        if (p % 3 != 1)  // a hand over the target: the scene behind it composited per sample
          for (SubFrame& sub : subs) sub.occluders = {hand};
        cv::Mat a, b;
        const auto t0 = std::chrono::steady_clock::now();
        scalar.renderLinear(subs, fx, a);
        const auto t1 = std::chrono::steady_clock::now();
        wide.renderLinear(subs, fx, b);
        scalarMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
        wideMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
        ASSERT_EQ(a.size(), b.size());
        ASSERT_EQ(a.type(), b.type());
        ++compared;
        const bool same = std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
        differing += same ? 0 : 1;
        EXPECT_TRUE(same) << "renderer "
                          << (base == &standard ? "standard" : base == &folded ? "folded lens" : base == &bare ? "no floor" : "641 wide")
                          << ", pose " << p << ", " << subFrames << " sub-frame(s): max difference "
                          << cv::norm(a, b, cv::NORM_INF);
      }
    }
  }
  {  // the hand is in view where it is used (the composite path ran)
    cv::Mat without, with;
    standard.renderLinear({SubFrame{poses[0], {}}}, FrameEffects{}, without);
    standard.renderLinear({SubFrame{poses[0], {hand}}}, FrameEffects{}, with);
    EXPECT_GT(cv::norm(without, with, cv::NORM_L1) / static_cast<double>(without.total()), 1.0)
        << "the hand should cover part of view 0";
  }
  std::printf("%d frames compared, %d differ; rendering %.0f ms scalar, %.0f ms wide\n", compared, differing, scalarMs,
              wideMs);
}
