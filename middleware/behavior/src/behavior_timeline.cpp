#include "marionette/behavior/behavior_timeline.hpp"

#include "marionette/core/easing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace marionette {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string seconds(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g s", t);
  return buf;
}

bool activeAt(const BehaviorTimeline::Entry& e, double t) noexcept {
  return t >= e.request.start() && t < e.finishTime();
}
}  // namespace

double BehaviorTimeline::Entry::finishTime() const noexcept {
  const double natural = request.persistent ? kInfinity : request.end();
  return std::min(natural, cancelAt + cancelBlend);
}

std::string BehaviorTimeline::check(const BehaviorRequest& r) const {
  if (r.id.empty()) return "a behavior request needs an id";
  const std::string who = "behavior request '" + r.id + "'";
  if (find(r.id)) return who + ": a request with this id is still on the character's timeline";
  if (r.syncs.empty()) return who + " has no sync points (it needs at least a start and an end)";
  for (std::size_t i = 0; i < r.syncs.size(); ++i) {
    const BehaviorSync& s = r.syncs[i];
    if (!std::isfinite(s.time)) return who + ": sync point '" + s.name + "' has a time that is not finite";
    if (i > 0 && s.time < r.syncs[i - 1].time)
      return who + ": sync point '" + s.name + "' (" + seconds(s.time) + ") comes before '" + r.syncs[i - 1].name +
             "' (" + seconds(r.syncs[i - 1].time) + "); sync points must be in time order";
  }
  if (!(r.weight >= 0.0f && r.weight <= 1.0f)) return who + ": weight must be in [0, 1]";
  return {};
}

BehaviorTimeline::Entry& BehaviorTimeline::add(BehaviorRequest request) {
  Entry e;
  const double start = request.start(), end = request.end();
  const double fallback = std::min(kDefaultBlendSeconds, 0.25 * (end - start));
  const auto ready = request.time("ready") ? request.time("ready") : request.time("attackPeak");  // face: attack
  const auto relax = request.time("relax");
  e.blendInEnd = (ready && *ready > start && *ready <= end) ? *ready : start + fallback;
  e.blendOutStart = (relax && *relax < end && *relax >= start) ? *relax : end - fallback;
  e.blendOutStart = std::max(e.blendOutStart, e.blendInEnd);
  e.request = std::move(request);
  e.order = ++nextOrder_;
  entries_.push_back(std::move(e));
  return entries_.back();
}

bool BehaviorTimeline::cancel(std::string_view id, double at, double blendOut) {
  auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.request.id == id; });
  if (it == entries_.end()) return false;
  if (!std::isfinite(at)) return false;
  if (at <= it->request.start()) {  // never started: nothing to blend out
    entries_.erase(it);
    return true;
  }
  if (at < it->cancelAt) {
    it->cancelAt = at;
    it->cancelBlend = std::isfinite(blendOut) ? std::max(0.0, blendOut) : 0.0;
  }
  return true;
}

std::size_t BehaviorTimeline::cancelPrefix(std::string_view prefix, double at, double blendOut) {
  std::vector<std::string> ids;
  for (const Entry& e : entries_)
    if (std::string_view(e.request.id).substr(0, prefix.size()) == prefix) ids.push_back(e.request.id);
  for (const std::string& id : ids) cancel(id, at, blendOut);
  return ids.size();
}

float BehaviorTimeline::weightAt(const Entry& e, double t) noexcept {
  const double start = e.request.start(), end = e.request.end();
  if (!(t >= start) || (end <= start && !e.request.persistent)) return 0.0f;
  double w = 1.0;
  if (t < e.blendInEnd) w = smoothstep((t - start) / (e.blendInEnd - start));
  if (!e.request.persistent && t > e.blendOutStart)
    w = t >= end ? 0.0 : std::min(w, smoothstep((end - t) / (end - e.blendOutStart)));
  if (t > e.cancelAt) w *= e.cancelBlend > 0.0 ? smoothstep(1.0 - (t - e.cancelAt) / e.cancelBlend) : 0.0;
  return static_cast<float>(w) * e.request.weight;
}

const BehaviorRequest* BehaviorTimeline::owner(BodyChannel channels, double t) const noexcept {
  for (auto it = entries_.rbegin(); it != entries_.rend(); ++it)
    if (any(it->request.channelBits() & channels) && activeAt(*it, t)) return &it->request;
  return nullptr;
}

void BehaviorTimeline::prune(double t) noexcept {
  auto covered = [&](const Entry& e) {
    if (!e.request.persistent || e.cancelled()) return false;
    const BodyChannel bits = e.request.channelBits();
    for (const Entry& later : entries_)
      if (later.order > e.order && later.request.persistent && (later.request.channelBits() & bits) == bits &&
          later.request.weight >= 1.0f && weightAt(later, t) >= 1.0f)
        return true;
    return false;
  };
  // Mark first, then remove: remove_if moves entries while `covered` still reads them.
  for (Entry& e : entries_) e.done = t >= e.finishTime() || covered(e);
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(), [](const Entry& e) { return e.done; }),
                 entries_.end());
}

const BehaviorTimeline::Entry* BehaviorTimeline::find(std::string_view id) const noexcept {
  for (const Entry& e : entries_)
    if (e.request.id == id) return &e;
  return nullptr;
}

}  // namespace marionette
