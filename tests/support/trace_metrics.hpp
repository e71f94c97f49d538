// Measurements on the trace that `marionette run SCENE --trace OUT.csv` writes
// (examples/cli/run_command.cpp, writeTraceRows): one row per frame, character
// and joint, `frame,time,character,joint,px,py,pz,qx,qy,qz,qw`, world-space
// positions (metres) and unit rotations. Header-only, no gtest: the trace is a
// public format, and these are the metrics the tests and docs quote.
//
// - readTrace / parseTrace: a per-character, per-joint time series. Malformed
//   input is reported as errors "FILE:LINE: what" (never an exception or a crash);
//   "nan" and "inf" are values, left for findNonFinite to name.
// - findNonFinite: every non-finite number, by frame, character, joint and column.
// - maxAngularSpeed: the fastest turn of any joint between consecutive frames,
//   the angle of q_prev^-1 q_next on the shortest arc over the time step.
// - footSkating: the import tests' definition (tests/behavior/locomotion_real_test.cpp):
//   a frame is a contact frame when the foot is within 5 cm of its lowest height
//   in the trace, it skates when the foot moved faster than 0.5 m/s horizontally
//   since the previous frame; ratio = skating / contact frames.
// - finalPlacement / characterPlacement: where a joint (a character's root) ends
//   and which way it faces.
#pragma once
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace marionette::test {

inline constexpr std::string_view kTraceHeader = "frame,time,character,joint,px,py,pz,qx,qy,qz,qw";

struct TraceSample {
  long frame = 0;
  long line = 0;  // in the file, for messages
  double time = 0.0;
  double p[3] = {0.0, 0.0, 0.0};       // world position, metres
  double q[4] = {0.0, 0.0, 0.0, 1.0};  // world rotation x, y, z, w
};

struct Trace {
  std::string source;               // the file name in messages
  std::vector<std::string> errors;  // "source:line: what", the first kMaxErrors
  long errorCount = 0;
  long rows = 0;
  // character -> joint -> samples in frame order.
  std::map<std::string, std::map<std::string, std::vector<TraceSample>>> series;
  // character -> its joints in the order of the file (the skeleton's: the root first).
  std::map<std::string, std::vector<std::string>> jointOrder;

  static constexpr std::size_t kMaxErrors = 20;
  [[nodiscard]] bool ok() const { return errorCount == 0; }
  [[nodiscard]] const std::vector<TraceSample>* find(const std::string& character, const std::string& joint) const {
    const auto c = series.find(character);
    if (c == series.end()) return nullptr;
    const auto j = c->second.find(joint);
    return j == c->second.end() ? nullptr : &j->second;
  }
  [[nodiscard]] std::string errorSummary() const {
    std::string s;
    for (const std::string& e : errors) s += e + "\n";
    if (errorCount > static_cast<long>(errors.size()))
      s += "... and " + std::to_string(errorCount - static_cast<long>(errors.size())) + " more\n";
    return s;
  }
  void fail(long line, const std::string& what) {
    ++errorCount;
    if (errors.size() < kMaxErrors) errors.push_back(source + ":" + std::to_string(line) + ": " + what);
  }
};

namespace trace_detail {

// A whole field as a number (strtod: "nan", "inf" and "-nan" are numbers too).
inline bool parseDouble(const std::string& field, double& out) {
  if (field.empty() || std::isspace(static_cast<unsigned char>(field.front()))) return false;
  char* end = nullptr;
  out = std::strtod(field.c_str(), &end);
  return end == field.c_str() + field.size();
}

inline bool parseFrame(const std::string& field, long& out) {
  if (field.empty() || field.front() < '0' || field.front() > '9') return false;
  char* end = nullptr;
  out = std::strtol(field.c_str(), &end, 10);
  return end == field.c_str() + field.size() && out >= 0 && out < 1000000000L;
}

inline std::string shown(const std::string& s) { return s.size() > 60 ? s.substr(0, 60) + "..." : s; }

// q^-1 r for unit quaternions (x, y, z, w): the conjugate of q times r.
inline void relativeRotation(const double a[4], const double b[4], double out[4]) {
  const double ax = -a[0], ay = -a[1], az = -a[2], aw = a[3];
  out[0] = aw * b[0] + ax * b[3] + ay * b[2] - az * b[1];
  out[1] = aw * b[1] - ax * b[2] + ay * b[3] + az * b[0];
  out[2] = aw * b[2] + ax * b[1] - ay * b[0] + az * b[3];
  out[3] = aw * b[3] - ax * b[0] - ay * b[1] - az * b[2];
}

inline bool normalized(const double q[4], double out[4]) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 1e-12) || !std::isfinite(n)) return false;
  for (int i = 0; i < 4; ++i) out[i] = q[i] / n;
  return true;
}

// Rotates v by the unit quaternion q.
inline void rotate(const double q[4], const double v[3], double out[3]) {
  const double u[3] = {q[0], q[1], q[2]}, w = q[3];
  const double c1[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double c2[3] = {u[1] * c1[2] - u[2] * c1[1], u[2] * c1[0] - u[0] * c1[2], u[0] * c1[1] - u[1] * c1[0]};
  for (int i = 0; i < 3; ++i) out[i] = v[i] + 2.0 * (w * c1[i] + c2[i]);
}

inline bool finiteSample(const TraceSample& s) {
  if (!std::isfinite(s.time)) return false;
  for (double v : s.p)
    if (!std::isfinite(v)) return false;
  for (double v : s.q)
    if (!std::isfinite(v)) return false;
  return true;
}

constexpr double kPi = 3.14159265358979323846;

}  // namespace trace_detail

// Reads a trace from `in`; `source` names it in the errors.
inline Trace parseTrace(std::istream& in, const std::string& source) {
  using namespace trace_detail;
  Trace t;
  t.source = source;
  std::string line;
  long number = 0;
  auto readLine = [&]() {
    if (!std::getline(in, line)) return false;
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows
    return true;
  };
  if (!readLine()) {
    t.fail(1, "empty trace: no header line");
    return t;
  }
  if (line != kTraceHeader) {
    t.fail(number, "the header is '" + shown(line) + "', expected '" + std::string(kTraceHeader) + "'");
    return t;
  }
  std::vector<std::string> cells;
  while (readLine()) {
    cells.clear();
    std::size_t from = 0;
    for (;;) {
      const std::size_t comma = line.find(',', from);
      cells.push_back(line.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    if (cells.size() != 11) {
      t.fail(number, std::to_string(cells.size()) + " fields, expected 11: '" + shown(line) + "'");
      continue;
    }
    TraceSample s;
    s.line = number;
    if (!parseFrame(cells[0], s.frame)) {
      t.fail(number, "frame '" + shown(cells[0]) + "' is not a whole number");
      continue;
    }
    static const char* const kColumns[] = {"time", "px", "py", "pz", "qx", "qy", "qz", "qw"};
    double* const targets[] = {&s.time, &s.p[0], &s.p[1], &s.p[2], &s.q[0], &s.q[1], &s.q[2], &s.q[3]};
    const std::size_t cellOf[] = {1, 4, 5, 6, 7, 8, 9, 10};
    bool good = true;
    for (std::size_t k = 0; k < 8 && good; ++k)
      if (!parseDouble(cells[cellOf[k]], *targets[k])) {
        t.fail(number, std::string(kColumns[k]) + " '" + shown(cells[cellOf[k]]) + "' is not a number");
        good = false;
      }
    if (!good) continue;
    if (cells[2].empty() || cells[3].empty()) {
      t.fail(number, "empty character or joint name");
      continue;
    }
    std::vector<TraceSample>& series = t.series[cells[2]][cells[3]];
    if (series.empty()) t.jointOrder[cells[2]].push_back(cells[3]);
    if (!series.empty() && s.frame <= series.back().frame) {
      t.fail(number, cells[2] + "/" + cells[3] + ": frame " + std::to_string(s.frame) + " after frame " +
                         std::to_string(series.back().frame) + " (line " + std::to_string(series.back().line) + ")");
      continue;
    }
    series.push_back(s);
    ++t.rows;
  }
  if (t.rows == 0 && t.ok()) t.fail(number, "no rows after the header");
  return t;
}

inline Trace readTrace(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    Trace t;
    t.source = path;
    t.fail(0, "cannot open the trace");
    return t;
  }
  return parseTrace(in, path);
}

// Every non-finite number: `count`, and the first `keep` of them by frame as
// "frame F (time T) character/joint: column = value".
struct NonFiniteReport {
  long count = 0;
  std::vector<std::string> first;
  [[nodiscard]] std::string summary() const {
    std::string s = std::to_string(count) + " non-finite values";
    for (const std::string& f : first) s += "\n  " + f;
    return s;
  }
};

inline NonFiniteReport findNonFinite(const Trace& trace, std::size_t keep = 10) {
  NonFiniteReport r;
  std::multimap<long, std::string> earliest;
  static const char* const kColumns[] = {"time", "px", "py", "pz", "qx", "qy", "qz", "qw"};
  for (const auto& [character, joints] : trace.series)
    for (const auto& [joint, samples] : joints)
      for (const TraceSample& s : samples) {
        const double values[] = {s.time, s.p[0], s.p[1], s.p[2], s.q[0], s.q[1], s.q[2], s.q[3]};
        for (std::size_t k = 0; k < 8; ++k) {
          if (std::isfinite(values[k])) continue;
          ++r.count;
          if (keep == 0 || (earliest.size() >= keep && s.frame >= std::prev(earliest.end())->first)) continue;
          char buf[64];
          std::snprintf(buf, sizeof buf, "%g", values[k]);
          earliest.emplace(s.frame, "frame " + std::to_string(s.frame) + " (line " + std::to_string(s.line) + ") " +
                                        character + "/" + joint + ": " + kColumns[k] + " = " + buf);
          if (earliest.size() > keep) earliest.erase(std::prev(earliest.end()));
        }
      }
  for (const auto& [frame, text] : earliest) r.first.push_back(text);
  return r;
}

// The fastest joint turn between consecutive frames of the trace.
struct AngularSpeedPeak {
  double radiansPerSecond = 0.0;
  std::string character, joint;
  long frame = -1;  // the later frame of the pair
  double time = 0.0, angle = 0.0, dt = 0.0;
  long steps = 0;    // frame pairs measured
  long skipped = 0;  // pairs with a non-finite or zero-length rotation, or a time step not > 0
  [[nodiscard]] std::string describe() const {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.2f rad/s: %s/%s turned %.4f rad in %.4f s into frame %ld (t = %.3f s)",
                  radiansPerSecond, character.c_str(), joint.c_str(), angle, dt, frame, time);
    return buf;
  }
};

// Over every joint of `character`, or of all characters when it is empty.
inline AngularSpeedPeak maxAngularSpeed(const Trace& trace, const std::string& character = {}) {
  using namespace trace_detail;
  AngularSpeedPeak peak;
  for (const auto& [name, joints] : trace.series) {
    if (!character.empty() && name != character) continue;
    for (const auto& [joint, samples] : joints)
      for (std::size_t k = 1; k < samples.size(); ++k) {
        const TraceSample &a = samples[k - 1], &b = samples[k];
        const double dt = b.time - a.time;
        double qa[4], qb[4], d[4];
        if (!(dt > 0.0) || !std::isfinite(dt) || !normalized(a.q, qa) || !normalized(b.q, qb)) {
          ++peak.skipped;
          continue;
        }
        relativeRotation(qa, qb, d);
        // 2 atan2(|v|, |w|): the shortest arc (q and -q are one rotation), accurate near 0.
        const double angle = 2.0 * std::atan2(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), std::fabs(d[3]));
        ++peak.steps;
        if (angle / dt > peak.radiansPerSecond || peak.frame < 0) {
          peak.radiansPerSecond = angle / dt;
          peak.character = name;
          peak.joint = joint;
          peak.frame = b.frame;
          peak.time = b.time;
          peak.angle = angle;
          peak.dt = dt;
        }
      }
  }
  return peak;
}

struct SkatingMeasure {
  int contactFrames = 0, skatingFrames = 0;
  double ratio = 1.0;  // skating over contact frames; 1 when there is no contact frame
  double worstSpeed = 0.0;  // m/s, the fastest contact frame
  std::string worstJoint;
  long worstFrame = -1;
  std::vector<std::string> missing;  // feet that are not in the trace
};

// `contactHeight` (m) above each foot's lowest height in the trace, `skateSpeed` (m/s).
inline SkatingMeasure footSkating(const Trace& trace, const std::string& character, const std::vector<std::string>& feet,
                                  double contactHeight = 0.05, double skateSpeed = 0.5) {
  using namespace trace_detail;
  SkatingMeasure m;
  for (const std::string& foot : feet) {
    const std::vector<TraceSample>* samples = trace.find(character, foot);
    if (!samples) {
      m.missing.push_back(character + "/" + foot);
      continue;
    }
    double lowest = INFINITY;
    for (const TraceSample& s : *samples)
      if (finiteSample(s)) lowest = std::min(lowest, s.p[1]);
    for (std::size_t k = 1; k < samples->size(); ++k) {
      const TraceSample &a = (*samples)[k - 1], &b = (*samples)[k];
      const double dt = b.time - a.time;
      if (!finiteSample(a) || !finiteSample(b) || !(dt > 0.0)) continue;
      if (b.p[1] - lowest > contactHeight) continue;
      ++m.contactFrames;
      const double speed = std::hypot(b.p[0] - a.p[0], b.p[2] - a.p[2]) / dt;
      if (speed > skateSpeed) ++m.skatingFrames;
      if (speed > m.worstSpeed || m.worstFrame < 0) {
        m.worstSpeed = speed;
        m.worstJoint = foot;
        m.worstFrame = b.frame;
      }
    }
  }
  m.ratio = m.contactFrames > 0 ? static_cast<double>(m.skatingFrames) / m.contactFrames : 1.0;
  return m;
}

// Where a joint is and which way it faces on one frame: heading is the yaw of
// the joint's +Z axis about +Y in degrees, (-180, 180], 0 facing +Z and 90
// facing +X (the convention of a character's heading).
struct JointPlacement {
  bool found = false;
  long frame = -1;
  double time = 0.0;
  double x = 0.0, y = 0.0, z = 0.0;
  double headingDegrees = 0.0;
};

inline JointPlacement placementOf(const TraceSample& s) {
  using namespace trace_detail;
  JointPlacement p;
  p.found = true;
  p.frame = s.frame;
  p.time = s.time;
  p.x = s.p[0], p.y = s.p[1], p.z = s.p[2];
  double q[4], forward[3];
  const double plusZ[3] = {0.0, 0.0, 1.0};
  if (normalized(s.q, q)) {
    rotate(q, plusZ, forward);
    p.headingDegrees = std::atan2(forward[0], forward[2]) * 180.0 / kPi;
  } else {
    p.headingDegrees = NAN;
  }
  return p;
}

inline JointPlacement firstPlacement(const Trace& trace, const std::string& character, const std::string& joint) {
  const std::vector<TraceSample>* s = trace.find(character, joint);
  return s && !s->empty() ? placementOf(s->front()) : JointPlacement{};
}
inline JointPlacement finalPlacement(const Trace& trace, const std::string& character, const std::string& joint) {
  const std::vector<TraceSample>* s = trace.find(character, joint);
  return s && !s->empty() ? placementOf(s->back()) : JointPlacement{};
}

// The character's own place (its origin) and heading at the end, from its root
// joint (the skeleton's first, `Trace::jointOrder`): a root need not sit at the
// origin (RobotExpressive's "Bone" is 0.195 m behind it). Its offset in the
// character's frame is measured on the first frame, where the character stands
// at (startX, startZ) with `startHeadingDegrees` (the scene file's), and taken
// off at the end. Exact while the root does not move within the character (the
// in-place clips of RobotExpressive; locomotion moves the character itself).
inline JointPlacement characterPlacement(const Trace& trace, const std::string& character, const std::string& rootJoint,
                                         double startX, double startZ, double startHeadingDegrees) {
  using trace_detail::kPi;
  const JointPlacement first = firstPlacement(trace, character, rootJoint);
  JointPlacement last = finalPlacement(trace, character, rootJoint);
  if (!first.found || !last.found) return {};
  // The offset in the character's frame: world offset turned back by the start heading.
  const double h0 = startHeadingDegrees * kPi / 180.0;
  const double wx = first.x - startX, wz = first.z - startZ;
  const double ox = wx * std::cos(h0) - wz * std::sin(h0), oz = wx * std::sin(h0) + wz * std::cos(h0);
  // The root's own yaw within the character, then the character's heading at the end.
  const double rootYaw = first.headingDegrees - startHeadingDegrees;
  const double heading = std::remainder(last.headingDegrees - rootYaw, 360.0);
  const double h = heading * kPi / 180.0;
  last.x -= ox * std::cos(h) + oz * std::sin(h);
  last.z -= -ox * std::sin(h) + oz * std::cos(h);
  last.headingDegrees = heading;
  return last;
}

}  // namespace marionette::test
