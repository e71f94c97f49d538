// The AprilTag 36h11 tracker against ViSP's ground truth (Debian visp-images-data), on a
// synthetic board warped into a known camera, with bad input, determinism and timing.
//
// ViSP's tag frame, from its data (GroundTruthConventionReprojectsViSPCorners pins it):
// origin at the tag centre, x to the tag image's right, y to its top, z out of the printed
// face (not into it); the corners in the files are at (-s,-s), (s,-s), (s,s), (-s,s), i.e.
// libapriltag's order (bottom-left first). Ours: X right, Y out of the face, Z down. So
// p_visp = A p_ours with x = X, y = -Z, z = Y, and world->camera R_ours = R_visp A.
// The benchmark's sizes (0.25 m, 0.125 m) are the whole tag with its white margin (10
// cells); the black border the tracker measures is 8 cells: 0.2 m and 0.1 m.
// Pixels: ViSP's corner files hold libapriltag's raw corners, whose top-left pixel centre
// is at (0.5, 0.5) (the synthetic board shows it); they are read into OpenCV's convention.
// The benchmark's renderer shares libapriltag's: its principal point (320, 240) is
// (319.5, 239.5) in OpenCV's (its truth reprojects the raw corners with no mean offset).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/apriltag_tracker.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;
using Corners = std::array<glm::dvec2, 4>;

constexpr double kPi = 3.14159265358979323846;
const CameraModel kBenchCamera{.width = 640, .height = 480, .fx = 700, .fy = 700, .cx = 319.5, .cy = 239.5};
const CameraModel kViSPCamera{
    .width = 640, .height = 480, .fx = 615.1674805, .fy = 615.1675415, .cx = 312.1889954, .cy = 243.4373779};
constexpr double kViSPTagSize = 0.053;

std::string bench(const std::string& f) { return test::vispImage("AprilTag/benchmark/640x480/" + f); }

ImageView view(const cv::Mat& m) { return {m.data, m.cols, m.rows, m.channels(), static_cast<std::ptrdiff_t>(m.step)}; }

// The benchmark frame as RGBA (imread gives BGRA).
cv::Mat benchFrame() {
  cv::Mat bgra = cv::imread(bench("tag36_11_640x480.png"), cv::IMREAD_UNCHANGED), rgba;
  EXPECT_EQ(bgra.channels(), 4);
  cv::cvtColor(bgra, rgba, cv::COLOR_BGRA2RGBA);
  return rgba;
}

// A 4x4 row-major matrix file: the world->OpenCV-camera rotation and translation.
bool readCMo(const std::string& path, glm::dmat3& r, glm::dvec3& t) {
  std::ifstream in(path);
  double m[16];
  for (double& v : m)
    if (!(in >> v)) return false;
  for (int i = 0; i < 3; ++i) r[0][i] = m[4 * i], r[1][i] = m[4 * i + 1], r[2][i] = m[4 * i + 2], t[i] = m[4 * i + 3];
  return true;
}

// ViSP tag frame -> ours: R_ours = R_visp A (glm is column-major: A's columns).
glm::dmat3 vispToOurs(const glm::dmat3& rVisp) {
  const glm::dmat3 a(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  return rVisp * a;
}

glm::dvec2 project(const CameraModel& c, const glm::dmat3& r, const glm::dvec3& t, const glm::dvec3& p) {
  const glm::dvec3 q = r * p + t;
  return {c.fx * q.x / q.z + c.cx, c.fy * q.y / q.z + c.cy};
}

// Our tag world's corners in the detection order (bottom-left, bottom-right, top-right, top-left).
std::array<glm::dvec3, 4> tagCorners(double size) {
  const double h = 0.5 * size;
  return {glm::dvec3(-h, 0, h), glm::dvec3(h, 0, h), glm::dvec3(h, 0, -h), glm::dvec3(-h, 0, -h)};
}

// "id" then four "x y" lines (or "36h11_id:_8" style names), by id, in OpenCV's convention.
std::map<int, Corners> readCorners(const std::string& path, bool rowColumn) {
  std::ifstream in(path);
  std::map<int, Corners> out;
  std::string name;
  while (in >> name) {
    const auto digits = name.find_last_not_of("0123456789");
    const int id = std::stoi(digits == std::string::npos ? name : name.substr(digits + 1));
    Corners c;
    for (auto& p : c) {
      in >> p.x >> p.y;
      if (rowColumn) std::swap(p.x, p.y);
      p -= glm::dvec2(0.5);  // libapriltag's pixel centres to OpenCV's
    }
    out[id] = c;
  }
  return out;
}

// The smallest max error over the 4 cyclic shifts and both windings; `inOrder` when that
// is with the same order.
double matchCorners(const Corners& found, const Corners& truth, bool& inOrder) {
  double best = 1e300;
  for (std::size_t k = 0; k < 8; ++k) {
    double worst = 0;
    for (std::size_t i = 0; i < 4; ++i)
      worst = std::max(worst, glm::length(found[i] - truth[k < 4 ? (k + i) % 4 : (k + 4 - i) % 4]));
    if (worst < best) best = worst, inOrder = k == 0;
  }
  return best;
}

glm::dmat3 fromCv(const cv::Matx33d& m) {
  glm::dmat3 g;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g[j][i] = m(i, j);
  return g;
}

glm::dmat3 yawMatrix(double degrees) {  // about +Y
  const double a = degrees * kPi / 180;
  return {glm::dvec3(std::cos(a), 0, -std::sin(a)), glm::dvec3(0, 1, 0), glm::dvec3(std::sin(a), 0, std::cos(a))};
}

double rotationErrorDegrees(const glm::dmat3& a, const glm::dmat3& b) {
  const glm::dmat3 d = glm::transpose(a) * b;
  const double c = std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) * 0.5, -1.0, 1.0);
  return std::acos(c) * 180.0 / kPi;
}

std::unique_ptr<AprilTagTracker> makeTracker(const CameraModel& camera, const AprilTagSettings& s) {
  Diagnostics d;
  auto t = AprilTagTracker::create(camera, s, d);
  EXPECT_TRUE(t) << d.format();
  return t;
}

struct PoseError {
  double cm, degrees, percent;  // translation error, rotation error, translation error / distance
};
PoseError poseError(const glm::dmat4& estimate, const glm::dmat4& truth) {
  const double e = glm::length(glm::dvec3(estimate[3]) - glm::dvec3(truth[3]));
  return {100.0 * e, rotationErrorDegrees(glm::dmat3(estimate), glm::dmat3(truth)),
          100.0 * e / glm::length(glm::dvec3(truth[3]))};
}

// Pins the ViSP convention without the tracker: the ground-truth poses, converted to our
// frame, put our tag corners where ViSP's detection found them, in the same order.
TEST(AprilTagBenchmark, GroundTruthConventionReprojectsViSPCorners) {
  MARIONETTE_REQUIRE_FILE(bench("corners_tag36_11.txt"));
  const auto truth = readCorners(bench("corners_tag36_11.txt"), false);
  ASSERT_EQ(truth.size(), 5u);
  glm::dvec2 mean(0);
  for (int id = 0; id < 5; ++id) {
    MARIONETTE_REQUIRE_FILE(bench("cMo_" + std::to_string(id) + ".txt"));
    glm::dmat3 r;
    glm::dvec3 t;
    ASSERT_TRUE(readCMo(bench("cMo_" + std::to_string(id) + ".txt"), r, t));
    const auto corners = tagCorners(id < 3 ? 0.2 : 0.1);
    double worst = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const glm::dvec2 e = truth.at(id)[i] - project(kBenchCamera, vispToOurs(r), t, corners[i]);
      mean += e / 20.0;
      worst = std::max(worst, glm::length(e));
    }
    std::printf("tag %d: ground truth reprojects ViSP's corners within %.3f px\n", id, worst);
    EXPECT_LT(worst, 0.75) << "tag " << id;  // another frame or size: tens of pixels
  }
  std::printf("mean offset of ViSP's corners from the truth: %+.3f %+.3f px\n", mean.x, mean.y);
  EXPECT_LT(glm::length(mean), 0.25);  // half a pixel per axis with the wrong pixel convention
}

TEST(AprilTagBenchmark, PosesWithinOnePercentOfViSPGroundTruth) {
  MARIONETTE_REQUIRE_FILE(bench("tag36_11_640x480.png"));
  const cv::Mat frame = benchFrame();
  for (int id = 0; id < 5; ++id) {
    glm::dmat3 r;
    glm::dvec3 t;
    ASSERT_TRUE(readCMo(bench("cMo_" + std::to_string(id) + ".txt"), r, t));
    const glm::dmat4 truth = cameraToWorldFromOpenCv(vispToOurs(r), t);
    const double size = id < 3 ? 0.2 : 0.1;
    auto tracker = makeTracker(kBenchCamera, {.tagSize = size, .tagId = id});
    const TrackedPose pose = tracker->update(view(frame), 0.0);
    ASSERT_EQ(pose.state, TrackingState::Tracking) << "tag " << id;
    EXPECT_EQ(pose.inliers, 4);
    const PoseError e = poseError(pose.cameraToWorld, truth);
    const double depthPercent = 100.0 * (glm::length(pose.position()) / glm::length(t) - 1.0);
    std::printf("tag %d at %.3f m: translation error %.3f cm (%.3f %% of the distance; distance %+.3f %%), rotation "
                "error %.3f deg, rms %.3f px\n",
                id, glm::length(t), e.cm, e.percent, depthPercent, e.degrees, pose.reprojectionErrorPx);
    EXPECT_LT(e.percent, 1.0) << "tag " << id;
    EXPECT_LT(e.degrees, 1.0) << "tag " << id;
    // The static helper on the same detection gives the same pose.
    const auto& dets = tracker->detections();
    const auto it = std::find_if(dets.begin(), dets.end(), [&](const auto& d) { return d.id == id; });
    ASSERT_NE(it, dets.end());
    const auto helper = AprilTagTracker::cameraToTag(kBenchCamera, *it, size);
    ASSERT_TRUE(helper);
    EXPECT_LT(glm::length(glm::dvec3((*helper)[3]) - pose.position()), 1e-9);
  }
  // -1 follows the lowest id seen: tag 0.
  auto lowest = makeTracker(kBenchCamera, {.tagSize = 0.2});
  auto tag0 = makeTracker(kBenchCamera, {.tagSize = 0.2, .tagId = 0});
  EXPECT_EQ(lowest->update(view(frame), 0.0).position(), tag0->update(view(frame), 0.0).position());
}

TEST(AprilTagBenchmark, CornersWithinHalfPixelOfViSP) {
  const auto truth = readCorners(bench("corners_tag36_11.txt"), false);
  const cv::Mat rgba = benchFrame();
  cv::Mat grey, rgb;
  cv::cvtColor(rgba, grey, cv::COLOR_RGBA2GRAY);
  cv::cvtColor(rgba, rgb, cv::COLOR_RGBA2RGB);
  for (const cv::Mat* frame : std::array<const cv::Mat*, 3>{&rgba, &rgb, &grey}) {
    auto tracker = makeTracker(kBenchCamera, {});
    (void)tracker->update(view(*frame), 0.0);
    const auto& dets = tracker->detections();
    ASSERT_EQ(dets.size(), 5u) << frame->channels() << " channels";
    double worstAll = 0;
    for (const auto& d : dets) {
      ASSERT_TRUE(truth.count(d.id)) << d.id;
      bool inOrder = false;
      const double worst = matchCorners(d.corners, truth.at(d.id), inOrder);
      worstAll = std::max(worstAll, worst);
      EXPECT_LT(worst, 0.5) << "tag " << d.id;
      EXPECT_TRUE(inOrder) << "tag " << d.id << ": corners not in libapriltag's order";
    }
    std::printf("%d channels: corners within %.3f px of ViSP's\n", frame->channels(), worstAll);
  }
}

// AprilTag.pgm: a real photo of 12 tags. ViSP's detection file gives each corner as
// "row column" (vpImagePoint's i, j); its poses are tx ty tz and theta-u.
TEST(AprilTagViSPPhoto, DetectionsAndPosesMatchGroundTruth) {
  const std::string image = test::vispImage("AprilTag/AprilTag.pgm");
  const std::string detFile = test::vispImage("AprilTag/ground_truth_detection.txt");
  const std::string poseFile = test::vispImage("AprilTag/ground_truth_pose.txt");
  MARIONETTE_REQUIRE_FILE(image);
  MARIONETTE_REQUIRE_FILE(detFile);
  MARIONETTE_REQUIRE_FILE(poseFile);
  const cv::Mat grey = cv::imread(image, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(grey.cols, 640);
  const auto truth = readCorners(detFile, true);
  ASSERT_EQ(truth.size(), 12u);
  std::map<int, std::array<double, 6>> poses;
  std::ifstream in(poseFile);
  for (std::string name; in >> name;) {
    std::array<double, 6> v{};
    for (double& x : v) in >> x;
    poses[std::stoi(name.substr(name.find_last_of('_') + 1))] = v;
  }
  ASSERT_EQ(poses.size(), 12u);

  auto tracker = makeTracker(kViSPCamera, AprilTagSettings{.tagSize = kViSPTagSize});
  (void)tracker->update(view(grey), 0.0);
  const auto dets = tracker->detections();
  ASSERT_EQ(dets.size(), 12u);
  for (const auto& d : dets) {
    ASSERT_TRUE(truth.count(d.id) && poses.count(d.id)) << d.id;
    bool inOrder = false;
    const double cornerError = matchCorners(d.corners, truth.at(d.id), inOrder);
    EXPECT_LT(cornerError, 0.5) << "tag " << d.id;
    EXPECT_TRUE(inOrder) << "tag " << d.id;
    const auto& v = poses.at(d.id);
    cv::Matx33d r;
    cv::Rodrigues(cv::Vec3d(v[3], v[4], v[5]), r);
    const glm::dmat4 gt = cameraToWorldFromOpenCv(vispToOurs(fromCv(r)), glm::dvec3(v[0], v[1], v[2]));
    auto one = makeTracker(kViSPCamera, {.tagSize = kViSPTagSize, .tagId = d.id});
    const TrackedPose pose = one->update(view(grey), 0.0);
    ASSERT_NE(pose.state, TrackingState::Lost) << d.id;
    const PoseError e = poseError(pose.cameraToWorld, gt);
    std::printf("photo tag %d: corners within %.3f px, translation error %.3f cm (%.3f %%), rotation %.3f deg\n", d.id,
                cornerError, e.cm, e.percent, e.degrees);
    EXPECT_LT(e.percent, 1.0) << "tag " << d.id;
    EXPECT_LT(e.degrees, 1.0) << "tag " << d.id;
  }
}

// --- A synthetic board: tags rendered from libapriltag's codes (nearest neighbour, 4x4
// supersampled so that edges land where they are), warped into a camera with an exact pose.
struct BoardScene {
  std::vector<AprilTagBoardTag> tags = {{.id = 0, .size = 0.08, .centre = {-0.06, 0, -0.05}, .yawDegrees = 0},
                                        {.id = 5, .size = 0.08, .centre = {0.06, 0, -0.05}, .yawDegrees = 90},
                                        {.id = 17, .size = 0.06, .centre = {-0.06, 0, 0.06}, .yawDegrees = -135},
                                        {.id = 42, .size = 0.07, .centre = {0.065, 0, 0.06}, .yawDegrees = 30}};
  CameraModel camera{.width = 640, .height = 480, .fx = 600, .fy = 600, .cx = 319.5, .cy = 239.5};
  glm::dmat3 r{1.0};  // world -> OpenCV camera
  glm::dvec3 t{0.0};
  cv::Mat frame;
  glm::dmat4 truth{1.0};

  BoardScene() {
    // The board image: 1 mm pixels, right = +X, down = +Z, pixel (0, 0) at X = -0.15, Z = -0.13.
    constexpr double kMm = 0.001, kX0 = -0.15, kZ0 = -0.13;
    constexpr int kSub = 4;
    cv::Mat board(260, 300, CV_8UC1);
    apriltag_family_t* family = tag36h11_create();
    std::vector<image_u8_t*> bitmaps;  // 10x10: white margin, black border, 6x6 bits
    for (const auto& tag : tags) bitmaps.push_back(apriltag_to_image(family, tag.id));
    for (int v = 0; v < board.rows; ++v)
      for (int u = 0; u < board.cols; ++u) {
        int sum = 0;
        for (int sub = 0; sub < kSub * kSub; ++sub) {
          const glm::dvec3 p(kX0 + (u - 0.5 + (sub % kSub + 0.5) / kSub) * kMm, 0,
                             kZ0 + (v - 0.5 + (sub / kSub + 0.5) / kSub) * kMm);
          int value = 255;
          for (std::size_t i = 0; i < tags.size(); ++i) {
            const glm::dvec3 local = glm::transpose(yawMatrix(tags[i].yawDegrees)) * (p - tags[i].centre);
            const double cell = tags[i].size / 8.0;
            const int col = static_cast<int>(std::floor(local.x / cell + 5.0));
            const int row = static_cast<int>(std::floor(local.z / cell + 5.0));
            if (col >= 0 && col < 10 && row >= 0 && row < 10) value = bitmaps[i]->buf[row * bitmaps[i]->stride + col];
          }
          sum += value;
        }
        board.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>((sum + kSub * kSub / 2) / (kSub * kSub));
      }
    for (image_u8_t* im : bitmaps) {  // Debian's libapriltag does not export image_u8_destroy
      std::free(im->buf);
      std::free(im);
    }
    tag36h11_destroy(family);

    // A camera at `eye` looking at the board's middle, the image's down roughly along +Z.
    const glm::dvec3 eye(0.08, 0.42, 0.2), hint(0.2, 0, 1);
    const glm::dvec3 z = glm::normalize(glm::dvec3(0.01, 0, 0.005) - eye);
    const glm::dvec3 y = glm::normalize(hint - glm::dot(hint, z) * z), x = glm::cross(y, z);
    r = glm::transpose(glm::dmat3(x, y, z));  // rows: the camera's axes
    t = -(r * eye);
    truth = cameraToWorldFromOpenCv(r, t);
    // Board pixel -> world (X, Z) -> image: H = K [r1 r3 t] S.
    const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const cv::Matx33d rt(r[0][0], r[2][0], t.x, r[0][1], r[2][1], t.y, r[0][2], r[2][2], t.z);
    const cv::Matx33d s(kMm, 0, kX0, 0, kMm, kZ0, 0, 0, 1);
    cv::warpPerspective(board, frame, cv::Mat(k * rt * s), cv::Size(camera.width, camera.height), cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT, cv::Scalar(90));
  }

  // Detected corners against where the true camera puts them (OpenCV convention, same order).
  void cornerErrors(const std::vector<AprilTagTracker::Detection>& dets, glm::dvec2& mean, double& worst) const {
    mean = glm::dvec2(0);
    worst = 0;
    int n = 0;
    for (const auto& d : dets) {
      const auto tag = std::find_if(tags.begin(), tags.end(), [&](const auto& bt) { return bt.id == d.id; });
      if (tag == tags.end()) continue;
      const auto local = tagCorners(tag->size);
      for (std::size_t i = 0; i < 4; ++i, ++n) {
        const glm::dvec2 e = d.corners[i] - project(camera, r, t, tag->centre + yawMatrix(tag->yawDegrees) * local[i]);
        mean += e;
        worst = std::max(worst, glm::length(e));
      }
    }
    if (n > 0) mean /= static_cast<double>(n);
  }
};

// The whole board, at every decimation (the default is 2). libapriltag's corners are half a
// pixel off OpenCV's convention; the tracker's are not (edges refined; unrefined,
// decimation leaves a bias of its own).
TEST(AprilTagBoard, SyntheticBoardPoseWithinMillimetre) {
  const BoardScene scene;
  for (float decimate : {1.0f, 1.5f, 2.0f, 3.0f, 4.0f})
    for (bool refine : {true, false}) {
      auto tracker = makeTracker(scene.camera, {.board = scene.tags, .decimate = decimate, .refineEdges = refine});
      const TrackedPose pose = tracker->update(view(scene.frame), 0.0);
      ASSERT_EQ(tracker->detections().size(), 4u) << decimate;
      EXPECT_EQ(pose.state, TrackingState::Tracking);
      EXPECT_EQ(pose.inliers, 16);
      glm::dvec2 mean;
      double worst = 0;
      scene.cornerErrors(tracker->detections(), mean, worst);
      const PoseError e = poseError(pose.cameraToWorld, scene.truth);
      std::printf("decimate %.1f, refine %d: corner bias %+.3f %+.3f px, worst %.3f px; pose %.3f mm %.4f deg, rms "
                  "%.3f px\n",
                  static_cast<double>(decimate), refine ? 1 : 0, mean.x, mean.y, worst, 10.0 * e.cm, e.degrees,
                  pose.reprojectionErrorPx);
      if (!refine && decimate > 1.0f) continue;
      EXPECT_LT(glm::length(mean), 0.1) << decimate;
      EXPECT_LT(worst, 0.3) << decimate;
      EXPECT_LT(e.cm, 0.1) << decimate;
      EXPECT_LT(e.degrees, 0.1) << decimate;
    }
}

TEST(AprilTagBoard, OneBoardTagGivesItsPose) {
  const BoardScene scene;
  // One board tag only (the others are not on this board): the single-tag path, yaw
  // included. TRACKING with a margin >= 2 x the minimum, LIMITED below.
  for (const AprilTagBoardTag& tag : scene.tags)
    for (double minMargin : {30.0, 200.0}) {
      auto single = makeTracker(scene.camera, {.board = {tag}, .minDecisionMargin = minMargin});
      const TrackedPose p = single->update(view(scene.frame), 0.0);
      ASSERT_EQ(single->detections().size(), 4u);  // margins 220 .. 270 here
      EXPECT_EQ(p.state, minMargin < 100 ? TrackingState::Tracking : TrackingState::Limited) << tag.id;
      EXPECT_EQ(p.inliers, 4);
      const PoseError e1 = poseError(p.cameraToWorld, scene.truth);
      if (minMargin < 100)
        std::printf("board tag %d alone: translation error %.3f mm, rotation error %.3f deg\n", tag.id, 10.0 * e1.cm,
                    e1.degrees);
      EXPECT_LT(e1.cm, 0.5);
      EXPECT_LT(e1.degrees, 1.0);
    }
}

// A camera with lens distortion: the pinhole frame resampled through the distortion model.
TEST(AprilTagBoard, DistortedCameraPoseWithinMillimetre) {
  const BoardScene scene;
  CameraModel camera = scene.camera;
  camera.distortion = {-0.25, 0.08, 0.001, -0.0008, 0.0};
  std::vector<cv::Point2f> pixels;  // for every distorted pixel, the pinhole pixel it sees
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) pixels.emplace_back(static_cast<float>(x), static_cast<float>(y));
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Point2f> pinhole;
  cv::undistortPoints(pixels, pinhole, k, camera.distortion, cv::noArray(), k,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-9));
  const cv::Mat map = cv::Mat(pinhole, true).reshape(2, camera.height);
  cv::Mat frame;
  cv::remap(scene.frame, frame, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(90));

  auto tracker = makeTracker(camera, AprilTagSettings{.board = scene.tags});
  const TrackedPose pose = tracker->update(view(frame), 0.0);
  ASSERT_EQ(pose.state, TrackingState::Tracking);
  const PoseError e = poseError(pose.cameraToWorld, scene.truth);
  std::printf("distorted board: translation error %.3f mm, rotation error %.4f deg, rms %.3f px\n", 10.0 * e.cm,
              e.degrees, pose.reprojectionErrorPx);
  EXPECT_LT(e.cm, 0.1);
  EXPECT_LT(e.degrees, 0.1);
  // Ignoring the distortion is measurably worse: the test sees the undistortion.
  auto pinholeTracker = makeTracker(scene.camera, AprilTagSettings{.board = scene.tags});
  const TrackedPose wrong = pinholeTracker->update(view(frame), 0.0);
  if (wrong.state != TrackingState::Lost) {
    const double wrongMm = 10.0 * poseError(wrong.cameraToWorld, scene.truth).cm;
    std::printf("the same frame as a pinhole: translation error %.3f mm, rms %.3f px\n", wrongMm,
                wrong.reprojectionErrorPx);
    EXPECT_GT(wrongMm, 2.0 * (10.0 * e.cm));
  }
}

TEST(AprilTagBadInput, CreateRefusesBadSettingsAndCameras) {
  auto refused = [](const CameraModel& c, const AprilTagSettings& s, const std::string& place) {
    Diagnostics d;
    EXPECT_FALSE(AprilTagTracker::create(c, s, d));
    EXPECT_FALSE(d.ok());
    EXPECT_NE(d.format().find(place), std::string::npos) << d.format();
  };
  CameraModel nanCamera = kBenchCamera;
  nanCamera.fx = std::nan("");  // any problem() of the camera
  refused(nanCamera, {}, "camera");
  refused(CameraModel{}, {}, "camera");
  refused(kBenchCamera, {.tagSize = std::nan("")}, "tagSize");
  refused(kBenchCamera, {.tagSize = 0}, "tagSize");
  refused(kBenchCamera, {.tagSize = -1}, "tagSize");
  refused(kBenchCamera, {.tagId = 587}, "tagId");
  refused(kBenchCamera, {.decimate = 0.5f}, "decimate");
  refused(kBenchCamera, {.sigma = -1}, "sigma");
  refused(kBenchCamera, {.threads = 0}, "threads");
  refused(kBenchCamera, {.maxHamming = 3}, "maxHamming");
  const AprilTagBoardTag ok{.id = 1, .size = 0.1};
  refused(kBenchCamera, {.board = {ok, ok}}, "board[1]");
  refused(kBenchCamera, {.board = {ok, {.id = 2, .size = std::nan("")}}}, "board[1]");
  refused(kBenchCamera, {.board = {{.id = 2, .size = -0.1}}}, "board[0]");
  refused(kBenchCamera, {.board = {{.id = 2, .size = 0.1, .centre = {0, 0.1, 0}}}}, "board[0]");
  refused(kBenchCamera, {.board = {{.id = -1, .size = 0.1}}}, "board[0]");
  // A NaN tag size in the static helper: no pose, no throw.
  EXPECT_FALSE(AprilTagTracker::cameraToTag(kBenchCamera, {}, std::nan("")));
  EXPECT_FALSE(AprilTagTracker::cameraToTag(kBenchCamera, {}, 0.1));  // all corners at one point
}

TEST(AprilTagBadInput, UpdateGivesLostWithoutCrashing) {
  auto tracker = makeTracker(kBenchCamera, {});
  auto lost = [&](const ImageView& v, const char* what) {
    const TrackedPose p = tracker->update(v, 0.0);
    EXPECT_EQ(p.state, TrackingState::Lost) << what;
    EXPECT_TRUE(tracker->detections().empty()) << what;
  };
  lost(ImageView{}, "empty view");
  const std::vector<std::uint8_t> one(4, 0);
  lost(ImageView{one.data(), 1, 1, 1}, "1x1");
  const cv::Mat small(240, 320, CV_8UC1, cv::Scalar(128));
  lost(view(small), "wrong size");
  const cv::Mat black(480, 640, CV_8UC1, cv::Scalar(0)), white(480, 640, CV_8UC3, cv::Scalar::all(255));
  lost(view(black), "black");
  lost(view(white), "saturated");
  lost(ImageView{black.data, 640, 480, 2}, "two channels");
  lost(ImageView{black.data, 640, 480, 1, 100}, "stride shorter than a row");
  // A 1x1 camera is a valid camera; its frames hold no tag.
  auto tiny = makeTracker(CameraModel{.width = 1, .height = 1, .fx = 1, .fy = 1, .cx = 0.5, .cy = 0.5}, {});
  ASSERT_TRUE(tiny);
  EXPECT_EQ(tiny->update(ImageView{one.data(), 1, 1, 1}, 0.0).state, TrackingState::Lost);
  // A good frame after the bad ones still tracks.
  EXPECT_EQ(tracker->update(view(benchFrame()), 0.0).state, TrackingState::Tracking);
  tracker->reset();
  EXPECT_TRUE(tracker->detections().empty());
}

TEST(AprilTagDeterminism, SameFrameGivesIdenticalPoseBits) {
  const cv::Mat frame = benchFrame();
  auto a = makeTracker(kBenchCamera, {.tagSize = 0.2});
  auto b = makeTracker(kBenchCamera, {.tagSize = 0.2});
  const TrackedPose p1 = a->update(view(frame), 0.0);
  const TrackedPose p2 = a->update(view(frame), 1.0);
  const TrackedPose p3 = b->update(view(frame), 0.0);
  ASSERT_EQ(p1.state, TrackingState::Tracking);
  EXPECT_EQ(std::memcmp(&p1.cameraToWorld, &p2.cameraToWorld, sizeof(glm::dmat4)), 0);
  EXPECT_EQ(std::memcmp(&p1.cameraToWorld, &p3.cameraToWorld, sizeof(glm::dmat4)), 0);
  EXPECT_EQ(std::memcmp(&p1.reprojectionErrorPx, &p3.reprojectionErrorPx, sizeof(double)), 0);
}

TEST(AprilTagTiming, MedianUpdateOnTheBenchmarkFrame) {
  const cv::Mat frame = benchFrame();
  auto tracker = makeTracker(kBenchCamera, {.tagSize = 0.2, .decimate = 2.0f, .threads = 1});
  std::vector<double> ms;  // one warm-up run first: libapriltag's worker pool
  (void)tracker->update(view(frame), 0.0);
  for (int i = 0; i < 30; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const TrackedPose p = tracker->update(view(frame), i / 30.0);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    ASSERT_EQ(p.state, TrackingState::Tracking);
  }
  std::nth_element(ms.begin(), ms.begin() + 15, ms.end());
  std::printf("AprilTag update, 640x480 RGBA, decimate 2, 1 thread: median %.2f ms over 30 runs\n", ms[15]);
}

}  // namespace
