#include "tracking/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <glm/mat3x3.hpp>

#include "tracking/synthetic_sequence.hpp"

namespace marionette::ar::synthetic {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool tracked(const TrackedPose& p) { return p.state == TrackingState::Tracking || p.state == TrackingState::Limited; }

}  // namespace

double rotationErrorDeg(const glm::dmat4& a, const glm::dmat4& b) {
  const glm::dmat3 d = glm::transpose(glm::dmat3(a)) * glm::dmat3(b);
  // atan2 of sine and cosine stays accurate for small angles, where acos of the trace does not.
  const double s = std::sqrt((d[1][2] - d[2][1]) * (d[1][2] - d[2][1]) + (d[2][0] - d[0][2]) * (d[2][0] - d[0][2]) +
                             (d[0][1] - d[1][0]) * (d[0][1] - d[1][0]));
  const double c = d[0][0] + d[1][1] + d[2][2] - 1;
  return std::atan2(s, c) * 180.0 / 3.14159265358979323846;
}

TrajectoryReport compareTrajectory(const std::vector<TrackedPose>& estimated, const std::vector<glm::dmat4>& truth,
                                   const std::vector<double>& visibleFraction, const CameraModel& camera) {
  if (estimated.size() != truth.size() || truth.size() != visibleFraction.size())
    throw std::invalid_argument("compareTrajectory: " + std::to_string(estimated.size()) + " estimates, " +
                                std::to_string(truth.size()) + " true poses, " +
                                std::to_string(visibleFraction.size()) + " visible fractions");
  TrajectoryReport r;
  r.frames = static_cast<int>(truth.size());
  double sumSq = 0, rotSum = 0;
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec2> origins;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const TrackedPose& e = estimated[i];
    const bool visible = visibleFraction[i] > 0;
    if (visible) ++r.visibleFrames;
    if (!tracked(e)) continue;
    ++r.trackedFrames;
    const double err = glm::length(e.position() - glm::dvec3(truth[i][3]));
    const double rot = rotationErrorDeg(e.cameraToWorld, truth[i]);
    sumSq += err * err;
    r.ateMaxM = std::max(r.ateMaxM, err);
    rotSum += rot;
    r.rotationMaxDeg = std::max(r.rotationMaxDeg, rot);
    if (visible && err <= 0.02) ++r.within2cm;
    if (e.state == TrackingState::Tracking) {
      ++r.verifiedFrames;
      if (err > 0.05) ++r.falsePoses;
      if (!visible) ++r.trackedOutOfView;
      positions.push_back(e.position());
      origins.push_back(projectWorldPoint(camera, e.cameraToWorld, glm::dvec3(0)));
    }
  }
  if (r.trackedFrames > 0) {
    r.ateRmsM = std::sqrt(sumSq / r.trackedFrames);
    r.rotationMeanDeg = rotSum / r.trackedFrames;
  } else {
    r.ateRmsM = r.ateMaxM = r.rotationMeanDeg = r.rotationMaxDeg = kNaN;
  }
  if (positions.size() >= 2) {
    glm::dvec3 meanP(0);
    glm::dvec2 meanO(0);
    for (std::size_t i = 0; i < positions.size(); ++i) {
      meanP += positions[i];
      meanO += origins[i];
    }
    meanP /= static_cast<double>(positions.size());
    meanO /= static_cast<double>(origins.size());
    double sp = 0, so = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const glm::dvec3 dp = positions[i] - meanP;
      const glm::dvec2 dq = origins[i] - meanO;
      sp += glm::dot(dp, dp);
      so += glm::dot(dq, dq);
    }
    const double count = static_cast<double>(positions.size());
    r.jitterMm = 1000 * std::sqrt(sp / count);
    r.jitterPx = std::sqrt(so / count);
  } else {
    r.jitterMm = r.jitterPx = kNaN;
  }

  bool seenVisible = false;
  int worst = -1;
  bool anyReturn = false, allRelocalized = true;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const bool visible = visibleFraction[i] > 0;
    if (visible && i > 0 && !(visibleFraction[i - 1] > 0) && seenVisible) {
      anyReturn = true;
      int found = -1;
      for (std::size_t j = i; j < truth.size() && visibleFraction[j] > 0; ++j)
        if (estimated[j].state == TrackingState::Tracking) {
          found = static_cast<int>(j - i);
          break;
        }
      if (found < 0) allRelocalized = false;
      worst = std::max(worst, found);
    }
    seenVisible = seenVisible || visible;
  }
  r.framesToRelocalize = anyReturn && allRelocalized ? worst : -1;
  return r;
}

std::string formatReport(const TrajectoryReport& r) {
  auto num = [](double v, double scale, const char* fmt) {
    if (std::isnan(v)) return std::string("n/a");
    char b[32];
    std::snprintf(b, sizeof b, fmt, v * scale);
    return std::string(b);
  };
  char line[512];
  std::snprintf(line, sizeof line,
                "frames %d visible %d tracked %d (TRACKING %d) <=2cm %d ATE rms %s mm max %s mm rot mean %s max %s deg "
                "false %d jitter %s mm %s px relocalize %s",
                r.frames, r.visibleFrames, r.trackedFrames, r.verifiedFrames, r.within2cm,
                num(r.ateRmsM, 1000, "%.1f").c_str(), num(r.ateMaxM, 1000, "%.1f").c_str(),
                num(r.rotationMeanDeg, 1, "%.2f").c_str(), num(r.rotationMaxDeg, 1, "%.2f").c_str(), r.falsePoses,
                num(r.jitterMm, 1, "%.2f").c_str(), num(r.jitterPx, 1, "%.2f").c_str(),
                r.framesToRelocalize < 0 ? "n/a" : std::to_string(r.framesToRelocalize).c_str());
  return line;
}

}  // namespace marionette::ar::synthetic
