#include "marionette/animation/blend_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "marionette/animation/animation_clip.hpp"

namespace marionette {

namespace {

std::string number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

std::string pointText(float x, float y, int dimensions) {
  return dimensions == 1 ? "x = " + number(x) : "(" + number(x) + ", " + number(y) + ")";
}

double wrap01(double p) noexcept {
  p -= std::floor(p);
  return p >= 1.0 ? 0.0 : p;
}

// Twice the signed area of (a, b, c): > 0 when counter-clockwise.
double cross(double ax, double ay, double bx, double by, double cx, double cy) noexcept {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

struct Point {
  double x, y;
};

// True when `p` lies strictly inside the circumcircle of the counter-clockwise triangle (a, b, c).
bool inCircumcircle(const Point& a, const Point& b, const Point& c, const Point& p) noexcept {
  const double ax = a.x - p.x, ay = a.y - p.y, bx = b.x - p.x, by = b.y - p.y, cx = c.x - p.x, cy = c.y - p.y;
  const double det = (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay) +
                     (cx * cx + cy * cy) * (ax * by - bx * ay);
  return det > 1e-12;
}

// Bowyer-Watson: the Delaunay triangles of `points` (indices into it, counter-clockwise).
// Small inputs (at most BlendSpace::kMaxSamples points), command time.
std::vector<std::array<int, 3>> delaunay(const std::vector<Point>& points) {
  std::vector<Point> p = points;
  const int n = static_cast<int>(points.size());
  // A super triangle far around the unit square the points were scaled into.
  constexpr double kR = 1e4;
  for (double angle : {90.0, 210.0, 330.0}) {
    const double r = angle * 3.14159265358979323846 / 180.0;
    p.push_back({0.5 + kR * std::cos(r), 0.5 + kR * std::sin(r)});
  }
  std::vector<std::array<int, 3>> tris{{n, n + 1, n + 2}};
  for (int i = 0; i < n; ++i) {
    std::vector<std::array<int, 3>> keep, bad;
    for (const auto& t : tris) (inCircumcircle(p[t[0]], p[t[1]], p[t[2]], p[i]) ? bad : keep).push_back(t);
    // The cavity's boundary: the edges of bad triangles that no other bad triangle shares.
    std::vector<std::array<int, 2>> edges;
    for (const auto& t : bad)
      for (int e = 0; e < 3; ++e) {
        const int a = t[e], b = t[(e + 1) % 3];
        bool shared = false;
        for (const auto& u : bad)
          for (int f = 0; f < 3 && !shared; ++f)
            shared = (&u != &t) && u[f] == b && u[(f + 1) % 3] == a;
        if (!shared) edges.push_back({a, b});
      }
    for (const auto& [a, b] : edges) keep.push_back({a, b, i});  // counter-clockwise like the cavity
    tris = std::move(keep);
  }
  std::vector<std::array<int, 3>> out;
  for (const auto& t : tris) {
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    if (cross(p[t[0]].x, p[t[0]].y, p[t[1]].x, p[t[1]].y, p[t[2]].x, p[t[2]].y) <= 1e-12) continue;  // flat
    out.push_back(t);
  }
  return out;
}

// One touchdown per foot: the begin of its longest contact; -1 when the foot never lifts or has none.
float touchdown(const std::vector<ContactInterval>& contacts) {
  float best = -1.0f, longest = 0.0f;
  for (const ContactInterval& c : contacts) {
    if (c.begin == 0.0f && c.end >= 1.0f) return -1.0f;  // never lifts: no touchdown to align
    const float length = c.begin <= c.end ? c.end - c.begin : 1.0f - c.begin + c.end;
    if (length > longest) longest = length, best = c.begin;
  }
  return best;
}

}  // namespace

std::string validateBlendSpaceDefinition(const BlendSpaceDefinition& d) {
  const std::string space = "blend space '" + d.name + "'";
  if (d.name.empty()) return "a blend space needs a name";
  if (d.dimensions != 1 && d.dimensions != 2)
    return space + ": " + std::to_string(d.dimensions) + " dimensions (expected 1 or 2)";
  const std::size_t n = d.samples.size();
  const std::size_t least = d.dimensions == 2 ? 3 : 1;
  if (n < least || n > BlendSpace::kMaxSamples)
    return space + ": " + std::to_string(n) + " samples (expected " + std::to_string(least) + " to " +
           std::to_string(BlendSpace::kMaxSamples) + (d.dimensions == 2 ? " for a 2D space)" : ")");
  for (std::size_t i = 0; i < n; ++i) {
    const BlendSpaceSampleDefinition& s = d.samples[i];
    if (s.clip.empty()) return space + ": sample " + std::to_string(i) + " names no clip";
    if (!std::isfinite(s.x) || (d.dimensions == 2 && !std::isfinite(s.y)))
      return space + ": sample " + std::to_string(i) + " ('" + s.clip + "') has a coordinate that is not a finite number";
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const auto& a = d.samples[i];
      const auto& b = d.samples[j];
      if (a.x == b.x && (d.dimensions == 1 || a.y == b.y))
        return space + ": samples " + std::to_string(i) + " ('" + a.clip + "') and " + std::to_string(j) + " ('" +
               b.clip + "') are both at " + pointText(a.x, a.y, d.dimensions) +
               " (a point has one weight: move or remove one)";
    }
  if (d.dimensions == 2) {
    // Not all on one line: some triple spans an area, relative to the layout's extent.
    float minX = d.samples[0].x, maxX = minX, minY = d.samples[0].y, maxY = minY;
    for (const auto& s : d.samples)
      minX = std::min(minX, s.x), maxX = std::max(maxX, s.x), minY = std::min(minY, s.y), maxY = std::max(maxY, s.y);
    const double ex = maxX > minX ? maxX - minX : 1.0, ey = maxY > minY ? maxY - minY : 1.0;
    double widest = 0.0;
    const auto& o = d.samples[0];
    for (std::size_t i = 1; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const auto& a = d.samples[i];
        const auto& b = d.samples[j];
        widest = std::max(widest, std::fabs(cross(o.x / ex, o.y / ey, a.x / ex, a.y / ey, b.x / ex, b.y / ey)));
      }
    if (!(widest > 1e-6))
      return space + ": the " + std::to_string(n) +
             " samples lie on one line, which cannot be triangulated (a 2D space needs samples off that line; "
             "or make it a 1D space)";
  }
  return {};
}

std::shared_ptr<const BlendSpace> BlendSpace::make(std::string name, int dimensions, std::vector<BlendSpaceSample> samples,
                                                   const Skeleton& skeleton, const BlendSpaceFeet& feet,
                                                   bool phaseAligned, std::string& error) {
  error.clear();
  BlendSpaceDefinition d{name, dimensions, {}, phaseAligned};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].clip) {
      error = "blend space '" + name + "': sample " + std::to_string(i) + " has no clip";
      return nullptr;
    }
    d.samples.push_back({samples[i].clip->clip.name.empty() ? "#" + std::to_string(i) : samples[i].clip->clip.name,
                         samples[i].x, dimensions == 2 ? samples[i].y : 0.0f});
  }
  if (error = validateBlendSpaceDefinition(d); !error.empty()) return nullptr;

  std::shared_ptr<BlendSpace> space(new BlendSpace());
  space->name_ = std::move(name);
  space->dimensions_ = dimensions;
  space->phaseAligned_ = phaseAligned;
  const int joints = static_cast<int>(skeleton.jointCount());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    Sample s;
    s.clip = std::move(samples[i].clip);
    s.x = samples[i].x;
    s.y = dimensions == 2 ? samples[i].y : 0.0f;
    s.duration = s.clip->clip.duration;
    if (!(s.duration > 0.0f) || !std::isfinite(s.duration)) {
      error = "blend space '" + space->name_ + "': sample " + std::to_string(i) + "'s clip '" + s.clip->clip.name +
              "' has no duration (a blend space cycles its clips)";
      return nullptr;
    }
    // The contacts are found whenever the feet are known (tools measure with them); the
    // keys only when the space aligns its cycles.
    const int foot[2] = {feet.left, feet.right};
    float down[2] = {-1.0f, -1.0f};
    for (int f = 0; f < 2; ++f)
      if (foot[f] >= 0 && foot[f] < joints) {
        s.contacts[f] = detectFootContacts(*s.clip, skeleton, foot[f], feet.contacts);
        down[f] = touchdown(s.contacts[f]);
      }
    if (phaseAligned) {
      const float apart = down[0] >= 0.0f && down[1] >= 0.0f ? static_cast<float>(wrap01(down[1] - down[0])) : 0.0f;
      if (apart > 0.05f && apart < 0.95f) {
        s.keys = {{0.0f, down[0]}, {0.5f, down[0] + apart}};
      } else if (down[0] >= 0.0f) {  // left only, or both feet down together (a hop)
        s.keys = {{0.0f, down[0]}};
      } else if (down[1] >= 0.0f) {
        s.keys = {{0.5f, down[1]}};
      }
    }
    space->samples_.push_back(std::move(s));
  }

  const std::size_t n = space->samples_.size();
  if (dimensions == 1) {
    for (std::size_t i = 0; i < n; ++i) space->order1D_.push_back(static_cast<int>(i));
    std::sort(space->order1D_.begin(), space->order1D_.end(),
              [&](int a, int b) { return space->samples_[static_cast<std::size_t>(a)].x < space->samples_[static_cast<std::size_t>(b)].x; });
    const auto& first = space->samples_[static_cast<std::size_t>(space->order1D_.front())];
    const auto& last = space->samples_[static_cast<std::size_t>(space->order1D_.back())];
    space->centreX_ = 0.5f * (first.x + last.x);
    return space;
  }

  // 2D: triangulated in coordinates scaled to the unit square, so that axes of
  // different units (m/s and degrees) make well-shaped triangles.
  float minX = space->samples_[0].x, maxX = minX, minY = space->samples_[0].y, maxY = minY;
  for (const Sample& s : space->samples_)
    minX = std::min(minX, s.x), maxX = std::max(maxX, s.x), minY = std::min(minY, s.y), maxY = std::max(maxY, s.y);
  space->scaleX_ = 1.0f / (maxX - minX);  // both extents are > 0: the points are not on one line
  space->scaleY_ = 1.0f / (maxY - minY);
  space->centreX_ = 0.5f * (minX + maxX);
  space->centreY_ = 0.5f * (minY + maxY);
  std::vector<Point> points;
  for (const Sample& s : space->samples_)
    points.push_back({static_cast<double>(s.x * space->scaleX_), static_cast<double>(s.y * space->scaleY_)});
  space->triangles_ = delaunay(points);
  if (space->triangles_.empty()) {
    error = "blend space '" + space->name_ + "': its samples could not be triangulated (nearly on one line?)";
    return nullptr;
  }
  // The hull: edges of one triangle only.
  for (const auto& t : space->triangles_)
    for (int e = 0; e < 3; ++e) {
      const int a = t[e], b = t[(e + 1) % 3];
      bool shared = false;
      for (const auto& u : space->triangles_)
        for (int f = 0; f < 3 && !shared; ++f) shared = u[f] == b && u[(f + 1) % 3] == a;
      if (!shared) space->hull_.push_back({a, b});
    }
  return space;
}

void BlendSpace::weights(float x, float y, std::span<float> out) const noexcept {
  const std::size_t n = std::min(out.size(), samples_.size());
  std::fill(out.begin(), out.end(), 0.0f);
  if (n == 0) return;
  if (!std::isfinite(x)) x = centreX_;
  if (!std::isfinite(y)) y = centreY_;
  if (out.size() < samples_.size()) {  // the caller's span is short: nothing sensible to write
    out[0] = 1.0f;
    return;
  }
  if (dimensions_ == 1) weights1D(x, out);
  else weights2D(x, y, out);
}

void BlendSpace::weights1D(float x, std::span<float> out) const noexcept {
  const auto at = [&](std::size_t k) { return samples_[static_cast<std::size_t>(order1D_[k])].x; };
  const std::size_t n = order1D_.size();
  if (x <= at(0)) {
    out[static_cast<std::size_t>(order1D_[0])] = 1.0f;
    return;
  }
  if (x >= at(n - 1)) {
    out[static_cast<std::size_t>(order1D_[n - 1])] = 1.0f;
    return;
  }
  std::size_t k = 0;
  while (k + 2 < n && x >= at(k + 1)) ++k;
  const float t = (x - at(k)) / (at(k + 1) - at(k));  // in [0, 1): x >= at(k), x < at(k + 1)
  out[static_cast<std::size_t>(order1D_[k])] = 1.0f - t;
  out[static_cast<std::size_t>(order1D_[k + 1])] += t;
}

void BlendSpace::weights2D(float x, float y, std::span<float> out) const noexcept {
  for (std::size_t i = 0; i < samples_.size(); ++i)
    if (samples_[i].x == x && samples_[i].y == y) {  // exact at a sample, whatever the rounding below
      out[i] = 1.0f;
      return;
    }
  const double px = static_cast<double>(x) * scaleX_, py = static_cast<double>(y) * scaleY_;
  const auto pt = [&](int i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    return Point{static_cast<double>(s.x * scaleX_), static_cast<double>(s.y * scaleY_)};
  };
  for (const auto& t : triangles_) {
    const Point a = pt(t[0]), b = pt(t[1]), c = pt(t[2]);
    const double area = cross(a.x, a.y, b.x, b.y, c.x, c.y);
    const double wa = cross(px, py, b.x, b.y, c.x, c.y) / area;
    const double wb = cross(a.x, a.y, px, py, c.x, c.y) / area;
    const double wc = 1.0 - wa - wb;
    constexpr double kEdge = -1e-9;  // on an edge: either triangle gives its two weights
    if (wa >= kEdge && wb >= kEdge && wc >= kEdge) {
      const double ca = std::max(wa, 0.0), cb = std::max(wb, 0.0), cc = std::max(wc, 0.0), sum = ca + cb + cc;
      out[static_cast<std::size_t>(t[0])] = static_cast<float>(ca / sum);
      out[static_cast<std::size_t>(t[1])] = static_cast<float>(cb / sum);
      out[static_cast<std::size_t>(t[2])] = static_cast<float>(cc / sum);
      return;
    }
  }
  // Outside the hull: the weights of its nearest point (on a boundary edge), which
  // clamps the parameter onto the hull and stays continuous.
  double best = INFINITY, bestT = 0.0;
  int ea = hull_.empty() ? 0 : hull_[0][0], eb = ea;
  for (const auto& [i, j] : hull_) {
    const Point a = pt(i), b = pt(j);
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    const double t = len2 > 0.0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
    const double qx = a.x + t * dx - px, qy = a.y + t * dy - py, d2 = qx * qx + qy * qy;
    if (d2 < best) best = d2, bestT = t, ea = i, eb = j;
  }
  out[static_cast<std::size_t>(ea)] = static_cast<float>(1.0 - bestT);
  out[static_cast<std::size_t>(eb)] += static_cast<float>(bestT);
}

double BlendSpace::cycleDuration(std::span<const float> weights) const noexcept {
  double sum = 0.0, total = 0.0;
  for (std::size_t i = 0; i < samples_.size() && i < weights.size(); ++i)
    if (weights[i] > 0.0f) {
      sum += static_cast<double>(weights[i]) * samples_[i].duration;
      total += weights[i];
    }
  return total > 0.0 ? sum / total : (samples_.empty() ? 0.0 : samples_[0].duration);
}

double BlendSpace::clipTime(std::size_t sample, double phase) const noexcept {
  if (sample >= samples_.size() || !std::isfinite(phase)) return 0.0;
  const Sample& s = samples_[sample];
  const double cycles = std::floor(phase), p = phase - cycles;
  const std::vector<PhaseKey>& k = s.keys;
  double clipPhase = p;
  if (k.size() == 1) {
    clipPhase = k[0].clip + (p - k[0].shared);
  } else if (k.size() >= 2) {
    // The segment holding p; before the first key it is the last key's, around the loop.
    std::size_t i = 0;
    while (i + 1 < k.size() && p >= k[i + 1].shared) ++i;
    double s0 = k[i].shared, c0 = k[i].clip, s1, c1;
    if (p < k[0].shared) {
      s0 = k.back().shared - 1.0, c0 = k.back().clip - 1.0, s1 = k[0].shared, c1 = k[0].clip;
    } else if (i + 1 < k.size()) {
      s1 = k[i + 1].shared, c1 = k[i + 1].clip;
    } else {
      s1 = k[0].shared + 1.0, c1 = k[0].clip + 1.0;
    }
    clipPhase = c0 + (p - s0) / (s1 - s0) * (c1 - c0);
  }
  return (cycles + clipPhase) * static_cast<double>(s.duration);
}

double BlendSpace::sharedPhase(std::size_t sample, double clipPhase) const noexcept {
  if (sample >= samples_.size() || !std::isfinite(clipPhase)) return 0.0;
  const std::vector<PhaseKey>& k = samples_[sample].keys;
  const double c = wrap01(clipPhase);
  if (k.empty()) return c;
  if (k.size() == 1) return wrap01(k[0].shared + (c - k[0].clip));
  const double u = k[0].clip + wrap01(c - k[0].clip);  // in [first key, first key + 1)
  for (std::size_t i = 0; i < k.size(); ++i) {
    const double c0 = k[i].clip, s0 = k[i].shared;
    const double c1 = i + 1 < k.size() ? k[i + 1].clip : k[0].clip + 1.0;
    const double s1 = i + 1 < k.size() ? k[i + 1].shared : k[0].shared + 1.0;
    if (u >= c0 && u < c1) return wrap01(s0 + (u - c0) / (c1 - c0) * (s1 - s0));
  }
  return wrap01(k[0].shared);
}

}  // namespace marionette
