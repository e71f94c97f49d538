#include "marionette_ar/authoring/augmentation.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "marionette/core/text_file.hpp"
#include "json_reader.hpp"

namespace marionette::ar {

namespace {

using detail::Json;
using detail::Reader;

constexpr const char* kFormat = "marionette-augmentation";

bool readCharacter(Reader& r, const Json& c, const std::string& where, PlacedCharacter& out) {
  if (!c.is_object()) {
    r.error(where, "expected an object");
    return false;
  }
  r.onlyKeys(c, where, {"name", "asset", "bml", "position", "rotor", "scale", "pivot"});
  bool ok = r.string(c, "name", where, true, out.name);
  ok = r.string(c, "asset", where, true, out.asset) && ok;
  ok = r.string(c, "bml", where, false, out.bml) && ok;
  ok = r.floats(c, "position", where, 3, &out.placement.position.x) && ok;
  ok = r.floats(c, "pivot", where, 3, &out.placement.pivot.x, false) && ok;
  float q[4] = {1, 0, 0, 0};
  if (r.floats(c, "rotor", where, 4, q)) {
    out.placement.rotation = {q[0], q[1], q[2], q[3]};
    // A rotor from this writer is unit to float rounding; anything else was edited by hand or broken.
    if (std::abs(out.placement.rotation.norm() - 1.0f) > 1e-4f) {
      r.error(where + ".rotor", "not a unit rotor [s, e23, e31, e12] (norm " +
                                    std::to_string(out.placement.rotation.norm()) + ")");
      ok = false;
    }
  } else {
    ok = false;
  }
  double scale = 1.0;
  ok = r.number(c, "scale", where, true, 1e-4, 1e4, scale) && ok;
  out.placement.scale = static_cast<float>(scale);
  out.asset = r.resolve(out.asset);
  out.bml = r.resolve(out.bml);
  return ok;
}

}  // namespace

glm::mat4 placementMatrix(const Placement& p) noexcept {
  const glm::mat3 rs = ga::toMatrix3(p.rotation.normalized()) * p.scale;
  glm::mat4 m(rs);
  m[3] = glm::vec4(p.position - rs * p.pivot, 1.0f);
  return m;
}

std::optional<Augmentation> parseAugmentation(const std::string& text, const std::string& path,
                                              Diagnostics& diagnostics) {
  Reader r(path, diagnostics);
  const std::optional<Json> parsed = r.document(text, "an augmentation", kFormat, Augmentation::kVersion);
  if (!parsed) return std::nullopt;
  const Json& root = *parsed;
  r.onlyKeys(root, "", {"format", "version", "tracker", "exposure", "environment", "characters"});
  Augmentation a;
  bool ok = true;
  if (!root.contains("tracker") || !root["tracker"].is_object()) {
    r.error("tracker", root.contains("tracker") ? "expected an object" : "missing");
    ok = false;
  } else {
    const Json& t = root["tracker"];
    r.onlyKeys(t, "tracker", {"kind", "camera", "map", "mapCrc32", "tagSize"});
    ok = r.string(t, "kind", "tracker", true, a.tracker.kind) && ok;
    ok = r.string(t, "camera", "tracker", true, a.tracker.camera) && ok;
    if (a.tracker.kind == "markerless") {
      ok = r.string(t, "map", "tracker", true, a.tracker.map) && ok;
      if (!r.string(t, "mapCrc32", "tracker", false, a.tracker.mapCrc32)) {
        ok = false;
      } else if (!a.tracker.mapCrc32.empty() && (a.tracker.mapCrc32.size() != 8 ||
                                                 a.tracker.mapCrc32.find_first_not_of("0123456789abcdef") != std::string::npos)) {
        r.error("tracker.mapCrc32", "expected 8 lower-case hex digits");
        ok = false;
      }
    } else if (a.tracker.kind == "apriltag") {
      ok = r.number(t, "tagSize", "tracker", true, 1e-3, 100, a.tracker.tagSize) && ok;
    } else if (!a.tracker.kind.empty()) {
      r.error("tracker.kind", "expected \"markerless\" or \"apriltag\", not \"" + a.tracker.kind + "\"");
      ok = false;
    }
    a.tracker.camera = r.resolve(a.tracker.camera);
    a.tracker.map = r.resolve(a.tracker.map);
  }
  double exposure = 0;
  ok = r.number(root, "exposure", "", false, -20, 20, exposure) && ok;
  a.exposureEv = static_cast<float>(exposure);
  ok = r.string(root, "environment", "", false, a.environment) && ok;
  a.environment = r.resolve(a.environment);
  if (!root.contains("characters") || !root["characters"].is_array()) {
    r.error("characters", root.contains("characters") ? "expected an array" : "missing");
    ok = false;
  } else {
    std::set<std::string> names;
    const Json& list = root["characters"];
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string where = "characters[" + std::to_string(i) + "]";
      PlacedCharacter c;
      if (!readCharacter(r, list[i], where, c)) {
        ok = false;
        continue;
      }
      if (!names.insert(c.name).second) {
        r.error(where + ".name", "\"" + c.name + "\" is used twice");
        ok = false;
        continue;
      }
      a.characters.push_back(std::move(c));
    }
  }
  if (!ok) return std::nullopt;
  return a;
}

std::optional<Augmentation> readAugmentation(const std::string& path, Diagnostics& diagnostics) {
  std::string text;
  if (!readTextFile(path, text, diagnostics)) return std::nullopt;
  return parseAugmentation(text, path, diagnostics);
}

std::string formatAugmentation(const Augmentation& a) {
  Json root;
  root["format"] = kFormat;
  root["version"] = Augmentation::kVersion;
  Json t;
  t["kind"] = a.tracker.kind;
  t["camera"] = a.tracker.camera;
  if (a.tracker.kind == "markerless") {
    t["map"] = a.tracker.map;
    if (!a.tracker.mapCrc32.empty()) t["mapCrc32"] = a.tracker.mapCrc32;
  } else {
    t["tagSize"] = a.tracker.tagSize;
  }
  root["tracker"] = t;
  root["exposure"] = static_cast<double>(a.exposureEv);
  if (!a.environment.empty()) root["environment"] = a.environment;
  Json list = Json::array();
  for (const PlacedCharacter& c : a.characters) {
    Json j;
    j["name"] = c.name;
    j["asset"] = c.asset;
    if (!c.bml.empty()) j["bml"] = c.bml;
    const Placement& p = c.placement;
    // Floats widened to double print as the shortest decimal that reads back to that double, so
    // the float comes back bit for bit.
    j["position"] = {double(p.position.x), double(p.position.y), double(p.position.z)};
    j["rotor"] = {double(p.rotation.s), double(p.rotation.b23), double(p.rotation.b31), double(p.rotation.b12)};
    j["scale"] = double(p.scale);
    if (p.pivot != glm::vec3(0.0f)) j["pivot"] = {double(p.pivot.x), double(p.pivot.y), double(p.pivot.z)};
    list.push_back(j);
  }
  root["characters"] = list;
  return root.dump(2) + "\n";
}

bool writeAugmentation(const std::string& path, const Augmentation& augmentation, Diagnostics& diagnostics) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  const std::string text = formatAugmentation(augmentation);
  out << text;
  out.close();
  if (!out) {
    diagnostics.error(path, "cannot be written");
    return false;
  }
  return true;
}

}  // namespace marionette::ar
