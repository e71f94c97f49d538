#include "dialect_forms.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "marionette/core/number_list.hpp"
#include "marionette/core/text.hpp"

namespace marionette::bml::detail {

namespace {

Attribute* find(Behavior& b, std::string_view name) {
  for (Attribute& a : b.attributes)
    if (a.name == name) return &a;
  return nullptr;
}

// Renames `from` to `to` unless `to` is given too (the standard spelling wins).
void rename(Behavior& b, std::string_view from, const char* to) {
  Attribute* a = find(b, from);
  if (!a) return;
  if (find(b, to)) {
    b.attributes.erase(b.attributes.begin() + (a - b.attributes.data()));
    return;
  }
  a->name = to;
}

void add(std::string& warning, const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; }

}  // namespace

std::string standardizeSpellings(Behavior& b, bool smartBody) {
  std::string warning;
  if (b.type == "locomotion" && smartBody) {
    // SmartBody's target="x y z" is z-up: x and y on the ground. Rewritten to BML's y-up
    // "x 0 z"; a height it gives is said and dropped (a walk stays on the ground).
    if (Attribute* target = find(b, "target")) {
      const auto v = parseNumberList(target->value);
      if (v && v->size() == 3 && std::isfinite((*v)[0]) && std::isfinite((*v)[1]) && std::isfinite((*v)[2])) {
        const std::string given = target->value;
        char buf[200];
        std::snprintf(buf, sizeof buf, "%.9g 0 %.9g", static_cast<double>((*v)[0]), static_cast<double>((*v)[1]));
        target->value = buf;
        if ((*v)[2] != 0.0f && (*v)[1] != (*v)[2]) {
          std::snprintf(buf, sizeof buf,
                        "locomotion target '%.60s' is read as SmartBody's (z up): the ground point x=%g, z=%g here, its "
                        "height %g dropped (as BML's y-up x y z it would be x=%g, z=%g)",
                        given.c_str(), static_cast<double>((*v)[0]), static_cast<double>((*v)[1]),
                        static_cast<double>((*v)[2]), static_cast<double>((*v)[0]), static_cast<double>((*v)[2]));
          add(warning, buf);
        }
      }
    }
  }
  if (b.type == "head") {
    rename(b, "type", "lexeme");  // SmartBody: <head type="NOD">
    if (Attribute* repeats = find(b, "repeats")) {
      // SmartBody counts nods as a number (repeats="1.5"); BML repeats whole strokes.
      const auto v = parseNumberList(repeats->value);
      if (v && v->size() == 1 && std::isfinite(v->front()) && v->front() > 0.0f) {
        const long whole = std::max(1L, std::lround(v->front()));
        if (static_cast<float>(whole) != v->front())
          add(warning, "repeats=\"" + repeats->value + "\" is read as " + std::to_string(whole) +
                           " repetitions (BML repeats whole strokes)");
        repeats->value = std::to_string(whole);
      } else {
        add(warning, "repeats=\"" + repeats->value.substr(0, 40) + "\" is not a positive number; 1 is used");
        repeats->value = "1";
      }
      rename(b, "repeats", "repetition");
    }
  } else if (b.type == "face") {
    if (Attribute* type = find(b, "type")) {
      // SmartBody: <face type="facs" au="12" side="BOTH" amount="0.5"/> is BML's <faceFacs>.
      if (equalsIgnoringCase(type->value, "facs")) b.type = "faceFacs";
      else add(warning, "face type=\"" + type->value.substr(0, 40) + "\" is not facs (the only SmartBody face type); " +
                            "it was ignored");
      b.attributes.erase(b.attributes.begin() + (type - b.attributes.data()));
    }
  } else if (b.type == "animation") {
    if (!find(b, "name")) add(warning, "<animation> needs a name (the clip to play)");
    if (Attribute* speed = find(b, "speed")) {
      const auto v = parseNumberList(speed->value);
      if (!v || v->size() != 1 || !std::isfinite(v->front()) || !(v->front() > 0.0f))
        add(warning, "speed=\"" + speed->value.substr(0, 40) + "\" is not a positive number; 1 is used");
      else if (v->front() < 0.01f || v->front() > 100.0f)
        add(warning, "speed=\"" + speed->value.substr(0, 40) + "\" is outside [0.01, 100]; it is clamped");
    }
  } else if (b.type == "event") {
    if (!find(b, "message")) add(warning, "<event> has no message; it sends an empty one");
  } else if (b.type == "gesture") {
    rename(b, "name", "lexeme");  // SmartBody: <gesture name="CLIP"/> plays that clip
  }
  return warning;
}

}  // namespace marionette::bml::detail
