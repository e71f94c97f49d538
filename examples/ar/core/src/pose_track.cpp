#include "marionette_ar/pose_track.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "marionette/core/text_file.hpp"

namespace marionette::ar {

namespace {

constexpr std::array<std::string_view, 12> kColumns = {"frame", "time", "state", "px", "py", "pz",
                                                       "qx",    "qy",   "qz",    "qw", "sigma_position_m",
                                                       "sigma_rotation_deg"};
constexpr std::size_t kPoseColumns = 10;  // the two sigma columns are optional (older files lack them)

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

// Splits `line` at commas into `fields` (up to its size); the number of fields found.
std::size_t split(std::string_view line, std::array<std::string_view, 13>& fields) {
  std::size_t n = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    if (n < fields.size()) fields[n] = trimmed(line.substr(0, comma));
    ++n;
    if (comma == std::string_view::npos) return n;
    line.remove_prefix(comma + 1);
  }
}

bool parseDouble(std::string_view s, double& out) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(out);
}

bool parseInteger(std::string_view s, std::int64_t& out) {
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

const RecordedPose* PoseTrack::atFrame(std::int64_t frame) const noexcept {
  const auto it = std::lower_bound(rows_.begin(), rows_.end(), frame,
                                   [](const RecordedPose& r, std::int64_t f) { return r.frame < f; });
  return it != rows_.end() && it->frame == frame ? &*it : nullptr;
}

const RecordedPose& PoseTrack::atTime(double seconds) const noexcept {
  if (!(seconds == seconds)) return rows_.front();  // NaN
  const auto it = std::upper_bound(rows_.begin(), rows_.end(), seconds + kTimeTolerance,
                                   [](double t, const RecordedPose& r) { return t < r.time; });
  return it == rows_.begin() ? rows_.front() : *(it - 1);
}

std::optional<PoseTrack> parsePoseTrack(std::string_view text, const std::string& name, Diagnostics& d) {
  std::vector<RecordedPose> rows;
  int lineNumber = 0;
  bool header = false;
  auto fail = [&](const std::string& field, const std::string& message) {
    d.error(name, (field.empty() ? "" : "'" + field + "': ") + message, lineNumber);
    return std::nullopt;
  };
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    lineNumber = lineColumnAt(text, static_cast<std::ptrdiff_t>(nul)).first;
    return fail("", "a NUL byte: not a CSV text file");
  }
  std::array<std::string_view, 13> f{};
  std::size_t columns = 0;  // the header's: 10, or 12 with the sigmas
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = trimmed(text.substr(0, eol));
    text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
    ++lineNumber;
    if (line.empty()) continue;
    const std::size_t n = split(line, f);
    if (!header) {
      bool same = n == kPoseColumns || n == kColumns.size();
      for (std::size_t i = 0; same && i < n; ++i) same = f[i] == kColumns[i];
      if (!same)
        return fail("", "the header is not 'frame,time,state,px,py,pz,qx,qy,qz,qw' (optionally followed by "
                        "',sigma_position_m,sigma_rotation_deg'): a pose CSV of marionette-ar track");
      columns = n;
      header = true;
      continue;
    }
    if (n != columns) return fail("", std::to_string(n) + " fields, expected " + std::to_string(columns));
    if (rows.size() >= kMaxPoseRows) return fail("", "more than " + std::to_string(kMaxPoseRows) + " rows");
    RecordedPose r;
    if (!parseInteger(f[0], r.frame) || r.frame < 0) return fail("frame", "expected a whole number >= 0");
    if (!rows.empty() && r.frame <= rows.back().frame)
      return fail("frame", std::to_string(r.frame) + " does not follow frame " + std::to_string(rows.back().frame));
    if (!parseDouble(f[1], r.time) || r.time < 0 || r.time > 1e9) return fail("time", "expected seconds in [0, 1e9]");
    if (!rows.empty() && r.time <= rows.back().time) return fail("time", "not after the previous row's time");
    if (const auto state = trackingStateFromName(f[2])) r.state = *state;
    else return fail("state", "'" + std::string(f[2].substr(0, 32)) + "' is none of " + trackingStateNames());
    // The sigmas: empty (unknown) or numbers >= 0.
    for (std::size_t i = kPoseColumns; i < columns; ++i) {
      double sigma = 0;
      if (f[i].empty()) continue;
      if (!parseDouble(f[i], sigma) || sigma < 0) return fail(std::string(kColumns[i]), "not a number >= 0");
      (i == kPoseColumns ? r.positionSigmaM : r.rotationSigmaDeg) = sigma;
    }
    bool allEmpty = true;
    for (std::size_t i = 3; i < kPoseColumns; ++i) allEmpty = allEmpty && f[i].empty();
    if (r.state == TrackingState::Lost && allEmpty) {
      rows.push_back(r);
      continue;
    }
    std::array<double, 7> v{};
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!parseDouble(f[i + 3], v[i]))
        return fail(std::string(kColumns[i + 3]),
                    f[i + 3].empty() ? "missing (only a LOST row has no pose)" : "not a finite number");
    const glm::dvec3 p(v[0], v[1], v[2]);
    if (std::abs(p.x) > 1e6 || std::abs(p.y) > 1e6 || std::abs(p.z) > 1e6)
      return fail("px", "the position is more than 1e6 m from the origin");
    glm::dquat q(v[6], v[3], v[4], v[5]);  // w, x, y, z
    const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(std::abs(norm - 1.0) <= 1e-3))
      return fail("qw", "the quaternion (qx, qy, qz, qw) has norm " + std::to_string(norm) + ", not 1");
    if (r.state != TrackingState::Lost) {
      q = q * (1.0 / norm);
      r.cameraToWorld = glm::dmat4(glm::mat3_cast(q));
      r.cameraToWorld[3] = glm::dvec4(p, 1.0);
    }
    rows.push_back(r);
  }
  if (!header) return fail("", "empty: no header line");
  if (rows.empty()) return fail("", "no rows after the header");
  return PoseTrack(std::move(rows));
}

std::optional<PoseTrack> readPoseTrack(const std::string& path, Diagnostics& d) {
  std::string text;
  if (!readTextFile(path, text, d, "cannot read the pose CSV")) return std::nullopt;
  return parsePoseTrack(text, path, d);
}

}  // namespace marionette::ar
