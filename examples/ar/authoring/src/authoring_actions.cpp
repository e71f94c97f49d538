#include "marionette_ar/authoring/authoring_actions.hpp"

#include <cmath>

#include "json_reader.hpp"
#include "marionette/core/text_file.hpp"

namespace marionette::ar {

namespace {

using detail::Json;
using detail::Reader;

constexpr const char* kFormat = "marionette-actions";
constexpr int kVersion = 1;

// The Keystroke-Level Model's operators (Card, Moran, Newell 1980), seconds.
constexpr double kDecide = 1.35;  // M: mental preparation
constexpr double kPoint = 1.1;    // P: point with the mouse
constexpr double kButton = 0.1;   // B: press or release a mouse button
constexpr double kKey = 0.28;     // K: a key, an average typist

constexpr ActionKind kKinds[] = {ActionKind::PickCharacter, ActionKind::PickBml, ActionKind::Place,
                                 ActionKind::Drag,          ActionKind::Rotate,  ActionKind::Height,
                                 ActionKind::Exposure,      ActionKind::Undo,    ActionKind::Save};

bool isWholeSteps(float degrees) noexcept {
  const float steps = degrees / kRotationStepDegrees;
  return std::abs(steps - std::round(steps)) < 1e-4f && std::round(steps) != 0.0f;
}

bool pixel(Reader& r, const Json& a, const char* key, const std::string& where, glm::vec2& out) {
  return r.floats(a, key, where, 2, &out.x);
}

bool readAction(Reader& r, const Json& a, const std::string& where, Action& out) {
  if (!a.is_object()) {
    r.error(where, "expected an object");
    return false;
  }
  std::string kind;
  if (!r.string(a, "do", where, true, kind)) return false;
  bool known = false;
  for (ActionKind k : kKinds)
    if (kind == actionName(k)) {
      out.kind = k;
      known = true;
    }
  if (!known) {
    std::string list;
    for (ActionKind k : kKinds) list += std::string(list.empty() ? "" : ", ") + actionName(k);
    r.error(where + ".do", "\"" + kind + "\" is not an action (" + list + ")");
    return false;
  }
  double frame = -1;
  bool ok = r.number(a, "frame", where, false, 0, 1e7, frame);
  if (ok && frame != std::floor(frame)) {
    r.error(where + ".frame", "expected a whole frame number");
    ok = false;
  }
  out.frame = static_cast<long>(frame);
  double value = 0;
  switch (out.kind) {
    case ActionKind::PickCharacter:
      r.onlyKeys(a, where, {"do", "frame", "name"});
      ok = r.string(a, "name", where, true, out.name) && ok;
      break;
    case ActionKind::PickBml:
      r.onlyKeys(a, where, {"do", "frame", "file"});
      ok = r.string(a, "file", where, true, out.name) && ok;
      out.name = r.resolve(out.name);
      break;
    case ActionKind::Place:
      r.onlyKeys(a, where, {"do", "frame", "pixel"});
      ok = pixel(r, a, "pixel", where, out.pixel) && ok;
      break;
    case ActionKind::Drag:
      r.onlyKeys(a, where, {"do", "frame", "from", "to"});
      ok = pixel(r, a, "from", where, out.pixel) && ok;
      ok = pixel(r, a, "to", where, out.to) && ok;
      break;
    case ActionKind::Rotate: {
      r.onlyKeys(a, where, {"do", "frame", "axes", "plane", "degrees"});
      std::string axes, plane;
      if (r.string(a, "axes", where, true, axes)) {
        if (axes == "local") out.axes = ga::Axes::Local;
        else if (axes == "global") out.axes = ga::Axes::Global;
        else {
          r.error(where + ".axes", "expected \"local\" or \"global\", not \"" + axes + "\"");
          ok = false;
        }
      } else {
        ok = false;
      }
      if (r.string(a, "plane", where, true, plane)) {
        if (plane == "e23") out.plane = RotationPlane::E23;
        else if (plane == "e31") out.plane = RotationPlane::E31;
        else if (plane == "e12") out.plane = RotationPlane::E12;
        else {
          r.error(where + ".plane", "expected \"e23\" (about x), \"e31\" (about y) or \"e12\" (about z), not \"" +
                                        plane + "\"");
          ok = false;
        }
      } else {
        ok = false;
      }
      ok = r.number(a, "degrees", where, true, -3600, 3600, value) && ok;
      out.value = static_cast<float>(value);
      break;
    }
    case ActionKind::Height:
      r.onlyKeys(a, where, {"do", "frame", "metres"});
      ok = r.number(a, "metres", where, true, 0.01, 100, value) && ok;
      out.value = static_cast<float>(value);
      break;
    case ActionKind::Exposure:
      r.onlyKeys(a, where, {"do", "frame", "ev"});
      ok = r.number(a, "ev", where, true, -20, 20, value) && ok;
      out.value = static_cast<float>(value);
      break;
    case ActionKind::Undo:
    case ActionKind::Save:
      r.onlyKeys(a, where, {"do", "frame"});
      break;
  }
  return ok;
}

}  // namespace

const char* actionName(ActionKind kind) noexcept {
  switch (kind) {
    case ActionKind::PickCharacter: return "pick-character";
    case ActionKind::PickBml: return "pick-bml";
    case ActionKind::Place: return "place";
    case ActionKind::Drag: return "drag";
    case ActionKind::Rotate: return "rotate";
    case ActionKind::Height: return "height";
    case ActionKind::Exposure: return "exposure";
    case ActionKind::Undo: return "undo";
    case ActionKind::Save: return "save";
  }
  return "?";
}

const char* planeName(RotationPlane plane) noexcept {
  switch (plane) {
    case RotationPlane::E23: return "e23";
    case RotationPlane::E31: return "e31";
    case RotationPlane::E12: return "e12";
  }
  return "?";
}

ga::Bivector<float> planeBivector(RotationPlane plane) noexcept {
  switch (plane) {
    case RotationPlane::E23: return ga::kPlaneX<float>;
    case RotationPlane::E31: return ga::kPlaneY<float>;
    case RotationPlane::E12: return ga::kPlaneZ<float>;
  }
  return ga::kPlaneY<float>;
}

double modelledSeconds(const Action& a, const Action* previous) noexcept {
  const double click = kPoint + 2 * kButton;      // point, press, release
  const double drag = 2 * kPoint + 2 * kButton;   // point at the start, press, point at the end, release
  switch (a.kind) {
    case ActionKind::PickCharacter:
    case ActionKind::PickBml:
    case ActionKind::Place:
      return kDecide + click;
    case ActionKind::Drag:
    case ActionKind::Height:
    case ActionKind::Exposure:
      return kDecide + drag;  // a slider is a drag of its handle
    case ActionKind::Rotate: {
      if (!isWholeSteps(a.value)) return kDecide + drag;  // a free turn: drag the rotation handle
      const double keys = std::abs(std::round(a.value / kRotationStepDegrees)) * kKey;
      const bool sameStep = previous && previous->kind == ActionKind::Rotate && previous->axes == a.axes &&
                            previous->plane == a.plane && isWholeSteps(previous->value);
      return (sameStep ? 0.0 : kDecide) + keys;
    }
    case ActionKind::Undo:
      return kDecide + 2 * kKey;  // Ctrl+Z
    case ActionKind::Save:
      return kDecide + 2 * kKey;  // Ctrl+S, to the file the session was started with
  }
  return kDecide;
}

std::optional<std::vector<Action>> parseActions(const std::string& text, const std::string& path,
                                                Diagnostics& diagnostics) {
  Reader r(path, diagnostics);
  const std::optional<Json> parsed = r.document(text, "an action file", kFormat, kVersion);
  if (!parsed) return std::nullopt;
  const Json& root = *parsed;
  r.onlyKeys(root, "", {"format", "version", "comment", "actions"});
  if (!root.contains("actions") || !root["actions"].is_array()) {
    r.error("actions", root.contains("actions") ? "expected an array" : "missing");
    return std::nullopt;
  }
  std::vector<Action> actions;
  bool ok = true;
  const Json& list = root["actions"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    Action a;
    if (readAction(r, list[i], "actions[" + std::to_string(i) + "]", a)) actions.push_back(a);
    else ok = false;
  }
  if (!ok) return std::nullopt;
  return actions;
}

std::optional<std::vector<Action>> readActions(const std::string& path, Diagnostics& diagnostics) {
  std::string text;
  if (!readTextFile(path, text, diagnostics)) return std::nullopt;
  return parseActions(text, path, diagnostics);
}

std::string formatActions(const std::vector<Action>& actions) {
  Json root;
  root["format"] = kFormat;
  root["version"] = kVersion;
  Json list = Json::array();
  for (const Action& a : actions) {
    Json j;
    j["do"] = actionName(a.kind);
    if (a.frame >= 0) j["frame"] = a.frame;
    switch (a.kind) {
      case ActionKind::PickCharacter: j["name"] = a.name; break;
      case ActionKind::PickBml: j["file"] = a.name; break;
      case ActionKind::Place: j["pixel"] = {double(a.pixel.x), double(a.pixel.y)}; break;
      case ActionKind::Drag:
        j["from"] = {double(a.pixel.x), double(a.pixel.y)};
        j["to"] = {double(a.to.x), double(a.to.y)};
        break;
      case ActionKind::Rotate:
        j["axes"] = a.axes == ga::Axes::Local ? "local" : "global";
        j["plane"] = planeName(a.plane);
        j["degrees"] = double(a.value);
        break;
      case ActionKind::Height: j["metres"] = double(a.value); break;
      case ActionKind::Exposure: j["ev"] = double(a.value); break;
      case ActionKind::Undo:
      case ActionKind::Save: break;
    }
    list.push_back(j);
  }
  root["actions"] = list;
  return root.dump(2) + "\n";
}

}  // namespace marionette::ar
