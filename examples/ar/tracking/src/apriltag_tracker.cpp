#include "marionette_ar/tracking/apriltag_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace marionette::ar {

namespace {

constexpr int kTag36h11Codes = 587;
constexpr double kTrackingRmsPx = 2.0;
constexpr double kLimitedRmsPx = 4.0;
// Below this the detector is not called: no tag fits, and libapriltag's decimation of a
// tiny image is not worth trusting.
constexpr int kMinFrameSide = 16;

// libapriltag's corner order is its ideal tag's (-1, 1), (1, 1), (1, -1), (-1, -1) with x
// right and y down the tag image: bottom-left, bottom-right, top-right, top-left. That
// ideal frame (z into the face) is exactly the one SOLVEPNP_IPPE_SQUARE wants its object
// points in, in this order. Our world-aligned tag frame has x = X, y = Z, z = -Y.
const cv::Matx33d kWorldToIdeal(1, 0, 0,   //
                                0, 0, 1,   //
                                0, -1, 0);

std::array<cv::Point3d, 4> idealCorners(double size) {
  const double h = 0.5 * size;
  return {cv::Point3d(-h, h, 0), cv::Point3d(h, h, 0), cv::Point3d(h, -h, 0), cv::Point3d(-h, -h, 0)};
}

// A board tag's corners in the world, in the detection's order.
std::array<cv::Point3d, 4> boardCorners(const AprilTagBoardTag& tag) {
  const double yaw = tag.yawDegrees * (3.14159265358979323846 / 180.0);
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::array<cv::Point3d, 4> out = idealCorners(tag.size);
  for (cv::Point3d& p : out) {
    const cv::Vec3d local = kWorldToIdeal.t() * cv::Vec3d(p.x, p.y, p.z);  // in X, Y=0, Z
    p = cv::Point3d(tag.centre.x + c * local[0] + s * local[2], 0.0, tag.centre.z - s * local[0] + c * local[2]);
  }
  return out;
}

cv::Matx33d intrinsics(const CameraModel& camera) {
  return {camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1};
}

// Corner pixels to ideal-pinhole pixels (same K, no distortion): PnP then runs undistorted.
template <class Out>
void undistortCorners(const CameraModel& camera, const cv::Matx33d& k, const AprilTagTracker::Detection& d,
                      Out& out, std::size_t at) {
  std::array<cv::Point2d, 4> raw;
  for (std::size_t i = 0; i < 4; ++i) raw[i] = cv::Point2d(d.corners[i].x, d.corners[i].y);
  if (camera.hasDistortion()) {
    std::array<cv::Point2d, 4> undistorted;
    // More iterations than the default 5: strong distortion at the image edge needs them.
    cv::undistortPoints(raw, undistorted, k, camera.distortion, cv::noArray(), k,
                        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 1e-6));
    raw = undistorted;
  }
  for (std::size_t i = 0; i < 4; ++i) out[at + i] = raw[i];
}

bool finiteMat(const cv::Mat& m) { return cv::checkRange(m); }

double rmsPx(cv::InputArray object, cv::InputArray image, const cv::Matx33d& k, const cv::Mat& rvec,
             const cv::Mat& tvec, std::vector<cv::Point2d>& projected) {
  cv::projectPoints(object, rvec, tvec, k, cv::noArray(), projected);
  const cv::Mat img = image.getMat();
  double sum = 0;
  for (std::size_t i = 0; i < projected.size(); ++i) {
    const cv::Point2d e = projected[i] - img.at<cv::Point2d>(static_cast<int>(i));
    sum += e.dot(e);
  }
  return projected.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(projected.size()));
}

// rvec/tvec (world -> OpenCV camera) to camera-to-world, renderer axes.
glm::dmat4 toCameraToWorld(const cv::Mat& rvec, const cv::Mat& tvec, const cv::Matx33d& objectToWorld) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  const cv::Matx33d worldToCamera = r * objectToWorld.t();
  glm::dmat3 rg;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) rg[c][row] = worldToCamera(row, c);
  return cameraToWorldFromOpenCv(rg, glm::dvec3(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
}

// One square tag, in the ideal frame: IPPE_SQUARE, then Levenberg-Marquardt.
bool solveSquare(const std::array<cv::Point3d, 4>& object, const std::array<cv::Point2d, 4>& image,
                 const cv::Matx33d& k, cv::Mat& rvec, cv::Mat& tvec) {
  if (!cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE_SQUARE)) return false;
  cv::solvePnPRefineLM(object, image, k, cv::noArray(), rvec, tvec);
  return finiteMat(rvec) && finiteMat(tvec) && tvec.at<double>(2) > 0;
}

}  // namespace

struct AprilTagTracker::Impl {
  CameraModel camera;
  AprilTagSettings settings;
  cv::Matx33d k;
  apriltag_family_t* family = nullptr;
  apriltag_detector_t* detector = nullptr;
  cv::Mat grey;  // the frame as libapriltag reads it, allocated once
  std::vector<Detection> detections;
  // PnP buffers, sized for the whole board at creation and reused.
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image, projected;
  cv::Mat rvec = cv::Mat(3, 1, CV_64F), tvec = cv::Mat(3, 1, CV_64F);  // not braces: initializer_list

  ~Impl() {
    if (detector != nullptr) apriltag_detector_destroy(detector);
    if (family != nullptr) tag36h11_destroy(family);
  }

  bool toGrey(const ImageView& frame);
  void detect();
  TrackedPose singleTag();
  TrackedPose board();
};

bool AprilTagTracker::Impl::toGrey(const ImageView& frame) {
  // cv::Mat wants a mutable pointer; the frame is only read.
  const cv::Mat src(frame.height, frame.width, CV_8UC(frame.channels), const_cast<std::uint8_t*>(frame.pixels),
                    static_cast<std::size_t>(frame.rowBytes()));
  // Into `grey` as allocated: same size and type, so OpenCV does not reallocate.
  switch (frame.channels) {
    case 1: src.copyTo(grey); break;
    case 3: cv::cvtColor(src, grey, cv::COLOR_RGB2GRAY); break;
    case 4: cv::cvtColor(src, grey, cv::COLOR_RGBA2GRAY); break;
    default: return false;
  }
  return true;
}

void AprilTagTracker::Impl::detect() {
  detections.clear();
  image_u8_t im{grey.cols, grey.rows, static_cast<std::int32_t>(grey.step[0]), grey.data};
  // libapriltag allocates its own working images and results on every call (and OpenCV's
  // solvers their temporaries); this file's buffers are sized at creation and reused.
  zarray_t* found = apriltag_detector_detect(detector, &im);
  if (found == nullptr) return;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* d = nullptr;
    zarray_get(found, i, &d);
    if (d->decision_margin < settings.minDecisionMargin || d->hamming > settings.maxHamming) continue;
    Detection out;
    out.id = d->id;
    // libapriltag puts the top-left pixel's centre at (0.5, 0.5) (also after decimation:
    // it maps corners back that way); OpenCV and the camera model put it at (0, 0).
    for (std::size_t c = 0; c < 4; ++c) out.corners[c] = glm::dvec2(d->p[c][0] - 0.5, d->p[c][1] - 0.5);
    out.decisionMargin = d->decision_margin;
    out.hamming = d->hamming;
    detections.push_back(out);
  }
  apriltag_detections_destroy(found);
  // By id, then the best margin first; the same id twice keeps only its best.
  std::sort(detections.begin(), detections.end(), [](const Detection& a, const Detection& b) {
    return a.id != b.id ? a.id < b.id : a.decisionMargin > b.decisionMargin;
  });
  detections.erase(std::unique(detections.begin(), detections.end(),
                               [](const Detection& a, const Detection& b) { return a.id == b.id; }),
                   detections.end());
}

TrackedPose AprilTagTracker::Impl::singleTag() {
  TrackedPose pose;
  const auto it = settings.tagId < 0 ? detections.begin()
                                     : std::find_if(detections.begin(), detections.end(),
                                                    [&](const Detection& d) { return d.id == settings.tagId; });
  if (it == detections.end()) return pose;
  const std::array<cv::Point3d, 4> obj = idealCorners(settings.tagSize);
  std::array<cv::Point2d, 4> img;
  undistortCorners(camera, k, *it, img, 0);
  if (!solveSquare(obj, img, k, rvec, tvec)) return pose;
  pose.reprojectionErrorPx = rmsPx(obj, img, k, rvec, tvec, projected);
  pose.inliers = 4;
  pose.state = pose.reprojectionErrorPx < kTrackingRmsPx  ? TrackingState::Tracking
               : pose.reprojectionErrorPx < kLimitedRmsPx ? TrackingState::Limited
                                                          : TrackingState::Lost;
  if (pose.state != TrackingState::Lost) pose.cameraToWorld = toCameraToWorld(rvec, tvec, kWorldToIdeal.t());
  return pose;
}

TrackedPose AprilTagTracker::Impl::board() {
  TrackedPose pose;
  object.clear();
  image.clear();
  const Detection* only = nullptr;
  const AprilTagBoardTag* onlyTag = nullptr;
  for (const Detection& d : detections) {
    const auto tag = std::find_if(settings.board.begin(), settings.board.end(),
                                  [&](const AprilTagBoardTag& t) { return t.id == d.id; });
    if (tag == settings.board.end()) continue;
    const std::array<cv::Point3d, 4> corners = boardCorners(*tag);
    object.insert(object.end(), corners.begin(), corners.end());
    image.resize(image.size() + 4);
    undistortCorners(camera, k, d, image, image.size() - 4);
    only = &d;
    onlyTag = &*tag;
  }
  const std::size_t tags = object.size() / 4;
  if (tags == 0) return pose;
  if (tags == 1) {
    // IPPE_SQUARE in the tag's ideal frame gives the start; LM then runs in the world.
    std::array<cv::Point2d, 4> img;
    std::copy(image.begin(), image.end(), img.begin());
    if (!solveSquare(idealCorners(onlyTag->size), img, k, rvec, tvec)) return pose;
    const double yaw = onlyTag->yawDegrees * (3.14159265358979323846 / 180.0);
    const cv::Matx33d yawRotation(std::cos(yaw), 0, std::sin(yaw), 0, 1, 0, -std::sin(yaw), 0, std::cos(yaw));
    // world -> ideal: p_ideal = W2I * Ry^T * (p_world - centre).
    const cv::Matx33d worldToIdeal = kWorldToIdeal * yawRotation.t();
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    const cv::Matx33d rw = r * worldToIdeal;
    const cv::Vec3d centre(onlyTag->centre.x, onlyTag->centre.y, onlyTag->centre.z);
    const cv::Vec3d tw = cv::Vec3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)) - rw * centre;
    cv::Rodrigues(rw, rvec);
    for (int i = 0; i < 3; ++i) tvec.at<double>(i) = tw[i];
  } else if (!cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE)) {
    return pose;
  }
  cv::solvePnPRefineLM(object, image, k, cv::noArray(), rvec, tvec);
  if (!finiteMat(rvec) || !finiteMat(tvec)) return pose;
  pose.reprojectionErrorPx = rmsPx(object, image, k, rvec, tvec, projected);
  pose.inliers = static_cast<int>(object.size());
  const bool strong = tags >= 2 || only->decisionMargin >= 2.0 * settings.minDecisionMargin;
  pose.state = pose.reprojectionErrorPx < kTrackingRmsPx  ? (strong ? TrackingState::Tracking : TrackingState::Limited)
               : pose.reprojectionErrorPx < kLimitedRmsPx ? TrackingState::Limited
                                                          : TrackingState::Lost;
  if (pose.state != TrackingState::Lost) pose.cameraToWorld = toCameraToWorld(rvec, tvec, cv::Matx33d::eye());
  return pose;
}

AprilTagTracker::AprilTagTracker(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
AprilTagTracker::~AprilTagTracker() = default;

std::unique_ptr<AprilTagTracker> AprilTagTracker::create(const CameraModel& camera, const AprilTagSettings& settings,
                                                         Diagnostics& diagnostics) {
  const std::size_t before = diagnostics.items.size();
  auto fail = [&](const std::string& place, const std::string& message) { diagnostics.error(place, message); };
  if (const std::string p = camera.problem(); !p.empty()) fail("camera", p);
  if (settings.board.empty()) {
    if (!(settings.tagSize > 0) || !std::isfinite(settings.tagSize))
      fail("AprilTagSettings.tagSize", "tag size " + std::to_string(settings.tagSize) + " is not a positive length");
    if (settings.tagId < -1 || settings.tagId >= kTag36h11Codes)
      fail("AprilTagSettings.tagId", "tag id " + std::to_string(settings.tagId) + " is outside -1 .. 586");
  }
  std::set<int> ids;
  for (std::size_t i = 0; i < settings.board.size(); ++i) {
    const AprilTagBoardTag& t = settings.board[i];
    const std::string place = "AprilTagSettings.board[" + std::to_string(i) + "]";
    if (t.id < 0 || t.id >= kTag36h11Codes) fail(place, "tag id " + std::to_string(t.id) + " is outside 0 .. 586");
    if (!ids.insert(t.id).second) fail(place, "tag id " + std::to_string(t.id) + " is listed twice");
    if (!(t.size > 0) || !std::isfinite(t.size))
      fail(place, "tag size " + std::to_string(t.size) + " is not a positive length");
    if (!std::isfinite(t.centre.x) || !std::isfinite(t.centre.z) || t.centre.y != 0.0)
      fail(place, "tag centre must be finite and on the board plane Y=0");
    if (!std::isfinite(t.yawDegrees)) fail(place, "tag yaw is not finite");
  }
  if (!(settings.decimate >= 1.0f) || !std::isfinite(settings.decimate))
    fail("AprilTagSettings.decimate", "decimate " + std::to_string(settings.decimate) + " is below 1");
  if (!(settings.sigma >= 0.0f) || !std::isfinite(settings.sigma))
    fail("AprilTagSettings.sigma", "sigma " + std::to_string(settings.sigma) + " is negative or not finite");
  if (settings.threads < 1)
    fail("AprilTagSettings.threads", "threads " + std::to_string(settings.threads) + " is below 1");
  if (!std::isfinite(settings.minDecisionMargin))
    fail("AprilTagSettings.minDecisionMargin", "minimum decision margin is not finite");
  if (settings.maxHamming < 0 || settings.maxHamming > 2)
    fail("AprilTagSettings.maxHamming", "max hamming " + std::to_string(settings.maxHamming) +
                                            " is outside 0 .. 2 (libapriltag corrects at most 2 bits)");
  for (std::size_t i = before; i < diagnostics.items.size(); ++i)
    if (diagnostics.items[i].severity == Severity::Error) return nullptr;

  auto impl = std::make_unique<Impl>();
  impl->camera = camera;
  impl->settings = settings;
  impl->k = intrinsics(camera);
  impl->family = tag36h11_create();
  impl->detector = apriltag_detector_create();
  if (impl->family == nullptr || impl->detector == nullptr) {
    fail("apriltag", "libapriltag could not create the 36h11 detector");
    return nullptr;
  }
  apriltag_detector_add_family_bits(impl->detector, impl->family, settings.maxHamming);
  impl->detector->quad_decimate = settings.decimate;
  impl->detector->quad_sigma = settings.sigma;
  impl->detector->nthreads = settings.threads;
  impl->detector->refine_edges = settings.refineEdges;
  impl->detector->debug = false;
  impl->grey.create(camera.height, camera.width, CV_8UC1);
  const std::size_t corners = 4 * std::max<std::size_t>(settings.board.size(), 1);
  impl->detections.reserve(std::max<std::size_t>(settings.board.size(), 16));
  impl->object.reserve(corners);
  impl->image.reserve(corners);
  impl->projected.reserve(corners);
  return std::unique_ptr<AprilTagTracker>(new AprilTagTracker(std::move(impl)));
}

TrackedPose AprilTagTracker::update(const ImageView& frame, double /*seconds: no motion model*/) noexcept {
  Impl& m = *impl_;
  m.detections.clear();
  if (!frame.valid() || frame.width != m.camera.width || frame.height != m.camera.height ||
      frame.width < kMinFrameSide || frame.height < kMinFrameSide)
    return {};
  try {
    if (!m.toGrey(frame)) return {};
    m.detect();
    return m.settings.board.empty() ? m.singleTag() : m.board();
  } catch (...) {  // cv::Exception, or std::bad_alloc from a buffer that grew
    m.detections.clear();
    return {};
  }
}

void AprilTagTracker::reset() noexcept { impl_->detections.clear(); }
const CameraModel& AprilTagTracker::camera() const noexcept { return impl_->camera; }
const std::vector<AprilTagTracker::Detection>& AprilTagTracker::detections() const noexcept {
  return impl_->detections;
}

std::optional<glm::dmat4> AprilTagTracker::cameraToTag(const CameraModel& camera, const Detection& detection,
                                                       double tagSize) {
  if (!camera.problem().empty() || !(tagSize > 0) || !std::isfinite(tagSize)) return std::nullopt;
  for (const glm::dvec2& c : detection.corners)
    if (!std::isfinite(c.x) || !std::isfinite(c.y)) return std::nullopt;
  try {
    const cv::Matx33d k = intrinsics(camera);
    std::array<cv::Point2d, 4> img;
    undistortCorners(camera, k, detection, img, 0);
    cv::Mat rvec(3, 1, CV_64F), tvec(3, 1, CV_64F);
    if (!solveSquare(idealCorners(tagSize), img, k, rvec, tvec)) return std::nullopt;
    return toCameraToWorld(rvec, tvec, kWorldToIdeal.t());
  } catch (const cv::Exception&) {
    return std::nullopt;
  }
}

}  // namespace marionette::ar
