#include "marionette_ar/authoring/authoring_session.hpp"

#include <cmath>

#include <glm/glm.hpp>

namespace marionette::ar {

namespace {

constexpr std::size_t kMaxHistory = 256;  // undo steps kept

glm::vec3 cameraPosition(const AuthoringView& v) { return glm::vec3(glm::inverse(v.view)[3]); }

// The turn about +Y that makes the character's front (+Z) face the camera across the floor.
ga::Rotor facing(const glm::vec3& at, const glm::vec3& camera) {
  const glm::vec2 d(camera.x - at.x, camera.z - at.z);
  if (glm::length(d) < 1e-6f) return {};
  return ga::rotation(ga::kPlaneY<float>, std::atan2(d.x, d.y));
}

}  // namespace

std::optional<glm::vec3> floorPoint(const AuthoringView& v, glm::vec2 pixel, float maxDistance) noexcept {
  if (!v.tracked || v.width <= 0 || v.height <= 0) return std::nullopt;
  // Pixel centres to normalized device coordinates (y up), then the ray from the near to the far plane.
  const float x = 2.0f * (pixel.x + 0.5f) / static_cast<float>(v.width) - 1.0f;
  const float y = 1.0f - 2.0f * (pixel.y + 0.5f) / static_cast<float>(v.height);
  const glm::mat4 inv = glm::inverse(v.projection * v.view);
  const glm::vec4 n = inv * glm::vec4(x, y, -1.0f, 1.0f), f = inv * glm::vec4(x, y, 1.0f, 1.0f);
  if (!(std::abs(n.w) > 0.0f) || !(std::abs(f.w) > 0.0f)) return std::nullopt;
  const glm::vec3 origin = cameraPosition(v);
  const glm::vec3 dir = glm::normalize(glm::vec3(f) / f.w - glm::vec3(n) / n.w);
  if (!(std::abs(dir.y) > 1e-6f)) return std::nullopt;
  const float t = -origin.y / dir.y;
  if (!(t > 0.0f) || t > maxDistance) return std::nullopt;
  glm::vec3 p = origin + t * dir;
  p.y = 0.0f;
  return p;
}

AuthoringSession::AuthoringSession(Augmentation base, std::vector<CatalogueEntry> catalogue)
    : catalogue_(std::move(catalogue)) {
  current_.augmentation = std::move(base);
}

int AuthoringSession::pickedCharacter() const noexcept {
  if (current_.picked < 0) return -1;
  const std::string& name = catalogue_[static_cast<std::size_t>(current_.picked)].name;
  for (std::size_t i = 0; i < current_.augmentation.characters.size(); ++i)
    if (current_.augmentation.characters[i].name == name) return static_cast<int>(i);
  return -1;
}

PlacedCharacter* AuthoringSession::placed() {
  const int i = pickedCharacter();
  return i < 0 ? nullptr : &current_.augmentation.characters[static_cast<std::size_t>(i)];
}

bool AuthoringSession::apply(const Action& a, const AuthoringView& view, Diagnostics& diagnostics) {
  if (a.kind == ActionKind::Undo) {
    if (history_.empty()) {
      diagnostics.error("", "nothing to undo");
      return false;
    }
    current_ = std::move(history_.back());
    history_.pop_back();
    return true;
  }
  if (a.kind == ActionKind::Save) {
    ++saves_;
    return true;
  }
  State before = current_;  // what undo, or a failed action, goes back to
  auto fail = [&](std::string why) {
    current_ = std::move(before);
    diagnostics.error("", std::move(why));
    return false;
  };
  auto needPlaced = [&]() -> PlacedCharacter* {
    if (current_.picked < 0) return nullptr;
    return placed();
  };
  switch (a.kind) {
    case ActionKind::PickCharacter: {
      int found = -1;
      for (std::size_t i = 0; i < catalogue_.size(); ++i)
        if (catalogue_[i].name == a.name) found = static_cast<int>(i);
      if (found < 0) {
        std::string names;
        for (const CatalogueEntry& e : catalogue_) names += (names.empty() ? "" : ", ") + e.name;
        return fail("no character \"" + a.name + "\" in the scene (it has: " + (names.empty() ? "none" : names) + ")");
      }
      current_.picked = found;
      if (PlacedCharacter* c = placed()) current_.bml = c->bml;
      break;
    }
    case ActionKind::PickBml:
      current_.bml = a.name;
      if (PlacedCharacter* c = needPlaced()) c->bml = a.name;
      break;
    case ActionKind::Place: {
      if (current_.picked < 0) return fail("pick a character before placing one");
      const std::optional<glm::vec3> p = floorPoint(view, a.pixel);
      if (!p) return fail(view.tracked ? "the click does not meet the tracked floor" : "no tracked floor: the camera is lost");
      if (PlacedCharacter* c = placed()) {
        c->placement.position = *p;  // a placed character is moved there, turned as it was
      } else {
        const CatalogueEntry& e = catalogue_[static_cast<std::size_t>(current_.picked)];
        PlacedCharacter added;
        added.name = e.name;
        added.asset = e.asset;
        added.bml = current_.bml;
        added.placement.position = *p;
        added.placement.rotation = facing(*p, cameraPosition(view));  // facing the user
        // Life size: scale 1 (exactly: x / x) when its file's own height is a person's.
        added.placement.scale = e.heightMetres > 0.0f ? e.lifeSize().metres / e.heightMetres : 1.0f;
        added.placement.pivot = e.pivot;
        current_.augmentation.characters.push_back(std::move(added));
      }
      break;
    }
    case ActionKind::Drag: {
      PlacedCharacter* c = needPlaced();
      if (!c) return fail("nothing to drag: place the picked character first");
      const std::optional<glm::vec3> from = floorPoint(view, a.pixel), to = floorPoint(view, a.to);
      if (!from || !to) return fail(view.tracked ? "the drag does not stay on the tracked floor" : "no tracked floor: the camera is lost");
      c->placement.position += *to - *from;
      break;
    }
    case ActionKind::Rotate: {
      PlacedCharacter* c = needPlaced();
      if (!c) return fail("nothing to turn: place the picked character first");
      c->placement.rotation = ga::turn(c->placement.rotation, a.axes, planeBivector(a.plane), glm::radians(a.value));
      break;
    }
    case ActionKind::Height: {
      PlacedCharacter* c = needPlaced();
      if (!c) return fail("nothing to size: place the picked character first");
      const CatalogueEntry& e = catalogue_[static_cast<std::size_t>(current_.picked)];
      c->placement.scale = a.value / e.heightMetres;
      break;
    }
    case ActionKind::Exposure:
      current_.augmentation.exposureEv = a.value;
      break;
    case ActionKind::Undo:
    case ActionKind::Save:
      break;
  }
  history_.push_back(std::move(before));
  if (history_.size() > kMaxHistory) history_.erase(history_.begin());
  return true;
}

}  // namespace marionette::ar
