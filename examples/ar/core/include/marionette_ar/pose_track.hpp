// A recorded camera trajectory: the CSV `marionette-ar track` writes (and
// `marionette_write_sequence` writes as truth.csv), read back so that a scene can replay it
// ("camera": {"poses": ...}, docs/ar-renderer.md).
//
//   frame,time,state,px,py,pz,qx,qy,qz,qw
//   0,0.000000,TRACKING,0.1,0.5,0.6,-0.3,0.1,0.0,0.94
//   1,0.033333,LOST,,,,,,,
//
// One header line (exactly those ten column names, or those and `sigma_position_m,
// sigma_rotation_deg`: the pose's standard deviations, empty when unknown, as marionette-ar
// track writes them since issue 40), then one row per camera frame: `frame` a
// whole number >= 0, `time` seconds >= 0, both strictly increasing; `state` TRACKING, LIMITED or
// LOST; the camera-to-world position (metres) and rotation quaternion, the camera looking along
// -Z with +Y up (tracker.hpp's convention). A LOST row's seven pose fields are empty, or numbers
// (truth.csv writes them for frames without the target): either way it has no pose. A pose row's
// fields are finite numbers, |p| <= 1e6 m, the quaternion of norm 1 within 1e-3 (then
// normalised). Lines may end in CRLF; blank lines are skipped; at most kMaxPoseRows rows.
//
// Every problem is an error naming the file, the line and the field ("poses.csv:7: 'qw': not a
// number"), never a crash or a NaN pose.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

#include "marionette/core/diagnostic.hpp"

#include "marionette_ar/tracking_state.hpp"

namespace marionette::ar {


struct RecordedPose {
  std::int64_t frame = 0;
  double time = 0;
  TrackingState state = TrackingState::Lost;
  glm::dmat4 cameraToWorld{1.0};  // identity when Lost
  double positionSigmaM = 0, rotationSigmaDeg = 0;  // the pose's standard deviations; 0 when unknown
};

inline constexpr std::size_t kMaxPoseRows = 1'000'000;

class PoseTrack {
 public:
  explicit PoseTrack(std::vector<RecordedPose> rows) : rows_(std::move(rows)) {}

  [[nodiscard]] const std::vector<RecordedPose>& rows() const noexcept { return rows_; }
  // The row of camera frame `frame`; nullptr when the file has none (no allocation, O(log n)).
  [[nodiscard]] const RecordedPose* atFrame(std::int64_t frame) const noexcept;
  // The row shown at `seconds`: the last one whose time is <= seconds + kTimeTolerance (the
  // file's times are rounded to microseconds), the first row before it, the last row after
  // the end.
  [[nodiscard]] const RecordedPose& atTime(double seconds) const noexcept;
  static constexpr double kTimeTolerance = 1e-5;

 private:
  std::vector<RecordedPose> rows_;  // never empty
};

// Parses the CSV text; `name` (the file) goes into every diagnostic. nullopt on any error.
[[nodiscard]] std::optional<PoseTrack> parsePoseTrack(std::string_view text, const std::string& name,
                                                      Diagnostics& diagnostics);
// Reads and parses the file (a regular file within limits::kMaxTextFileBytes).
[[nodiscard]] std::optional<PoseTrack> readPoseTrack(const std::string& path, Diagnostics& diagnostics);

}  // namespace marionette::ar
