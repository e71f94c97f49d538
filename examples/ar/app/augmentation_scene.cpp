#include "augmentation_scene.hpp"

#include "scene_catalogue.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>

#if MARIONETTE_AR_HAS_TRACKING
#include "marionette_ar/tracking/planar_map.hpp"
#endif

namespace marionette::ar {

namespace {

namespace fs = std::filesystem;

std::string hex(std::uint32_t v) {
  char s[9];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

// Relative to `folder` when the two share a folder below the root; a system path (say
// /usr/share/...) stays absolute, so that the augmentation can move with its scene.
std::string relative(const std::string& path, const fs::path& folder) {
  if (path.empty()) return path;
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec).lexically_normal();
  const fs::path r = absolute.lexically_relative(folder);
  const auto first = [](const fs::path& p) { return p.begin() == p.end() ? fs::path() : *std::next(p.begin()); };
  if (ec || r.empty() || first(absolute) != first(folder)) return absolute.generic_string();
  return r.generic_string();
}

bool mapChecksum(const std::string& file, std::uint32_t& out, Diagnostics& diagnostics) {
#if !MARIONETTE_AR_HAS_TRACKING
  (void)out;
  diagnostics.error(file, "markerless maps need a build with MARIONETTE_WITH_TRACKING");
  return false;
#else
  const std::optional<PlanarMap> map = readPlanarMap(file, diagnostics);
  if (!map) return false;
  out = map->checksum;
  return true;
#endif
}

}  // namespace

bool trackerReference(const ArTracker& t, TrackerReference& out, Diagnostics& diagnostics) {
  out = {};
  out.camera = t.camera;
  if (t.kind == ArTracker::Kind::AprilTag) {
    out.kind = "apriltag";
    out.tagSize = t.tagSize;
    return true;
  }
  out.kind = "markerless";
  out.map = t.map;
  std::uint32_t crc = 0;
  if (!mapChecksum(t.map, crc, diagnostics)) return false;
  out.mapCrc32 = hex(crc);
  return true;
}

std::optional<AuthoringSession> startAuthoring(const ArScene& scene, const Scene& characters, const SceneLoadResult& loaded,
                                             Diagnostics& diagnostics) {
  const ArTracker& t = scene.camera.tracker;
  if (t.kind == ArTracker::Kind::None) {
    diagnostics.error(scene.path, "'camera.tracker' is needed: placements are made on the tracked floor");
    return std::nullopt;
  }
  if (t.kind == ArTracker::Kind::Markerless && t.map.empty()) {
    diagnostics.error(scene.path, "'camera.tracker.map' is needed: an augmentation belongs to a saved map "
                                  "(make one with marionette-ar track --save-map)");
    return std::nullopt;
  }
  Augmentation base;
  if (!trackerReference(t, base.tracker, diagnostics)) return std::nullopt;
  base.environment = scene.environment.file;
  base.exposureEv = scene.environment.exposure > 0 ? std::log2(scene.environment.exposure) : 0.0f;
  Diagnostics measured;
  std::vector<CatalogueEntry> catalogue = sceneCatalogue(characters, loaded, measured);
  std::fputs(measured.format().c_str(), stderr);
  return AuthoringSession(std::move(base), std::move(catalogue));
}

Augmentation relativeTo(const Augmentation& a, const std::string& file) {
  std::error_code ec;
  const fs::path folder = fs::absolute(fs::path(file), ec).lexically_normal().parent_path();
  Augmentation r = a;
  r.tracker.camera = relative(a.tracker.camera, folder);
  r.tracker.map = relative(a.tracker.map, folder);
  r.environment = relative(a.environment, folder);
  for (PlacedCharacter& c : r.characters) {
    c.asset = relative(c.asset, folder);
    c.bml = relative(c.bml, folder);
  }
  return r;
}

bool restoreInto(const Augmentation& a, const std::string& path, ArScene& scene, Diagnostics& diagnostics) {
  ArTracker t = scene.camera.tracker;  // keeps the scene's holdSeconds and hideWhenLost
  t.camera = a.tracker.camera;
  if (a.tracker.kind == "apriltag") {
    t.kind = ArTracker::Kind::AprilTag;
    t.tagSize = a.tracker.tagSize;
  } else {
    t.kind = ArTracker::Kind::Markerless;
    t.map = a.tracker.map;
    t.target.clear();
    std::uint32_t crc = 0;
    if (Diagnostics unread; !mapChecksum(t.map, crc, unread)) {  // the map's own errors, then the field naming it
      diagnostics.items.insert(diagnostics.items.end(), unread.items.begin(), unread.items.end());
      diagnostics.error(path, "'tracker.map': " + t.map + " is not a readable map");
      return false;
    }
    if (!a.tracker.mapCrc32.empty() && hex(crc) != a.tracker.mapCrc32) {
      diagnostics.error(path, "'tracker.mapCrc32': the map " + t.map + " has checksum " + hex(crc) + ", not " +
                                  a.tracker.mapCrc32 + ": it is not the map this augmentation was authored on");
      return false;
    }
  }
  if (scene.background.kind != ArBackground::Kind::Sequence && scene.background.kind != ArBackground::Kind::Video &&
      scene.background.kind != ArBackground::Kind::Camera) {
    diagnostics.error(path, "the scene " + scene.path + " has no camera frames to relocalize in (its background is "
                            "not a sequence, a video or a camera)");
    return false;
  }
  scene.camera.tracker = t;
  scene.camera.replay = {};
  if (!a.environment.empty()) scene.environment.file = a.environment;
  scene.environment.exposure = std::exp2(a.exposureEv);
  return true;
}

}  // namespace marionette::ar
