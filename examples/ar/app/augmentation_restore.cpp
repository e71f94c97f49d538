#include "augmentation_restore.hpp"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "augmentation_scene.hpp"
#include "marionette_ar/camera_pose.hpp"

namespace marionette::ar {

namespace {

// The process's start, seconds since boot: field 22 of /proc/self/stat, in clock ticks.
double processStartSinceBoot() {
  std::ifstream in("/proc/self/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t close = stat.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return -1;
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i)
    if (i == 22) return std::strtod(field.c_str(), nullptr) / static_cast<double>(sysconf(_SC_CLK_TCK));
  return -1;
}

double bootSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_BOOTTIME, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

double secondsSinceProcessStart() noexcept {
  using Clock = std::chrono::steady_clock;
  static const Clock::time_point first = Clock::now();
  static const double atFirst = [] {
    const double start = processStartSinceBoot();
    return start >= 0 ? std::max(0.0, bootSeconds() - start) : 0.0;
  }();
  return atFirst + std::chrono::duration<double>(Clock::now() - first).count();
}

bool AugmentationRestore::load(const std::string& path, ArScene& scene, const std::string& truthCsv) {
  path_ = path;
  std::optional<Augmentation> a = readAugmentation(path, diagnostics_);
  if (a && !restoreInto(*a, path, scene, diagnostics_)) a.reset();
  std::fputs(diagnostics_.format().c_str(), stderr);  // the errors, or the reader's warnings
  if (!a) {
    std::fprintf(stderr, "marionette-ar: the augmentation is not restored; the scene runs without it\n");
    return false;
  }
  augmentation_ = std::move(a);
  if (!truthCsv.empty()) {
    Diagnostics t;
    truth_ = readPoseTrack(truthCsv, t);
    std::fputs(t.format().c_str(), stderr);
  }
  return true;
}

void AugmentationRestore::bind(const Scene& scene, std::vector<TimedFile>& bml) {
  const std::size_t n = scene.characters().size();
  anchors_.assign(n, glm::mat4(1.0f));
  placed_.assign(n, 0);
  if (!active()) return;
  for (std::size_t k = 0; k < augmentation_->characters.size(); ++k) {
    const PlacedCharacter& c = augmentation_->characters[k];
    std::size_t i = 0;
    while (i < n && scene.characters()[i]->name() != c.name) ++i;
    if (i == n) {
      diagnostics_.error(path_, "'characters[" + std::to_string(k) + "].name': '" + c.name +
                                    "' is not a character of the scene: not restored");
      std::fprintf(stderr, "%s\n", diagnostics_.items.back().format().c_str());
      continue;
    }
    anchors_[i] = placementMatrix(c.placement);
    placed_[i] = 1;
    positions_.push_back(c.placement.position);
    if (!c.bml.empty()) bml.push_back({c.bml, 0.0, c.name});
  }
  // The scene's own BML goes to the characters it places, as authored; not to hidden ones.
  std::erase_if(bml, [&](const TimedFile& f) {
    for (std::size_t i = 0; i < n; ++i)
      if (scene.characters()[i]->name() == f.character) return !placed_[i];
    return false;
  });
}

void AugmentationRestore::frameDrawn(long frame, double time, bool verified, const glm::dmat4& view) {
  if (!active() || !verified) return;
  if (firstFrame_ < 0) {
    firstFrame_ = frame;
    firstSeconds_ = secondsSinceProcessStart();
    mark("first_registered_frame", firstSeconds_);  // the same instant: the phases add up to it
  }
  if (!truth_ || positions_.empty()) return;
  const RecordedPose& row = truth_->atTime(time);
  if (row.state == TrackingState::Lost) return;
  // Where the character appears in the true world: drawn through the estimated view, seen by the
  // true camera. The rotation of that map is the orientation error of every placement.
  const glm::dmat4 seen = row.cameraToWorld * view;
  double errorM = 0;
  for (const glm::vec3& p : positions_) {
    const glm::dvec3 at(p);
    errorM = std::max(errorM, glm::length(glm::dvec3(seen * glm::dvec4(at, 1.0)) - at));
  }
  const double errorDeg = viewRotationErrorDegrees(row.cameraToWorld, view);
  if (measured_++ == 0) {
    firstErrorM_ = errorM;
    firstErrorDeg_ = errorDeg;
  }
  maxErrorM_ = std::max(maxErrorM_, errorM);
  maxErrorDeg_ = std::max(maxErrorDeg_, errorDeg);
}

std::string AugmentationRestore::json(long frames) const {
  auto orNull = [](double v) { return v < 0 ? nlohmann::json(nullptr) : nlohmann::json(v); };
  std::string errors;  // the errors, one a line (not the warnings)
  for (const Diagnostic& d : diagnostics_.items)
    if (d.severity == Severity::Error) errors += (errors.empty() ? "" : "\n") + d.format();
  nlohmann::json j = {{"restored", active()},
                      {"error", errors.empty() ? nlohmann::json(nullptr) : nlohmann::json(errors)},
                      {"characters", active() ? augmentation_->characters.size() : 0},
                      {"frames", frames},
                      {"first_registered_frame", firstFrame_},
                      {"launch_to_registered_seconds", orNull(firstSeconds_)},
                      {"placement_error_m", orNull(firstErrorM_)},
                      {"placement_error_deg", orNull(firstErrorDeg_)},
                      {"placement_error_max_m", orNull(maxErrorM_)},
                      {"placement_error_max_deg", orNull(maxErrorDeg_)},
                      {"frames_measured", measured_},
                      {"truth", truth_.has_value()}};
  // Durations, as docs/authoring.md's table lists them: each phase from the end of the one
  // before (the first from process start).
  nlohmann::json phases = nlohmann::json::object();
  double end = 0.0;
  for (const auto& [name, seconds] : phases_) {
    phases[name] = seconds - end;
    end = seconds;
  }
  j["launch_phases_seconds"] = phases;
  return j.dump(2);
}

}  // namespace marionette::ar
