// The C API's blend-space functions (marionette.h): the rig's spaces, and playing one on a
// character's layer and moving its parameter point (Character::playBlend /
// setBlendParameter).
#include <cmath>
#include <string>
#include <vector>

#include "handles.hpp"
#include "marionette/core/text.hpp"

using marionette::capi::fail;
using marionette::capi::isLive;
using marionette::capi::notLive;

namespace {

// "'locomotion' and 'aim'", for messages.
std::string spaceList(const marionette::Rig& rig) {
  std::vector<std::string> names;
  for (const auto& s : rig.blendSpaces()) names.push_back(s->name());
  return names.empty() ? std::string("none: its profile has no \"blendSpaces\"") : marionette::quotedNameList(names);
}

std::string layerRange() { return "0.." + std::to_string(marionette::Character::kMaxLayers - 1); }

}  // namespace

extern "C" {

size_t mn_character_blend_space_count(const mn_character* character) {
  return isLive(character) ? character->character->rig().blendSpaces().size() : 0;
}

const char* mn_character_blend_space_name(const mn_character* character, size_t blend_space) {
  if (!isLive(character)) return nullptr;
  const auto& spaces = character->character->rig().blendSpaces();
  return blend_space < spaces.size() ? spaces[blend_space]->name().c_str() : nullptr;
}

mn_status mn_character_play_blend(mn_character* character, int layer, const char* blend_space,
                                  const mn_play_options* options) {
  if (!isLive(character))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_play_blend: character") + notLive(character));
  mn_scene* scene = character->owner;
  if (!blend_space) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_character_play_blend: blend_space is NULL");
  marionette::Character& c = *character->character;
  if (layer < 0 || layer >= marionette::Character::kMaxLayers)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_play_blend: layer " + std::to_string(layer) + " is not in " + layerRange());
  if (options && options->struct_size != sizeof(mn_play_options))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                marionette::capi::badStructSize("mn_character_play_blend", "mn_play_options", options->struct_size,
                                                sizeof(mn_play_options)));
  const mn_play_options o = options ? *options : mn_play_options_default();
  if (!std::isfinite(o.weight) || o.weight < 0.0f || !std::isfinite(o.speed) || !std::isfinite(o.start_time) ||
      !std::isfinite(o.fade_in) || o.fade_in < 0.0f)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_play_blend: options: weight and fade_in must be finite and >= 0, speed and start_time finite");
  if (o.additive)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_character_play_blend: options: a blend space cannot play additive");
  auto space = c.rig().findBlendSpace(blend_space);
  if (!space)
    return fail(scene, MN_ERROR_NOT_FOUND,
                "mn_character_play_blend: character '" + c.name() + "' has no blend space '" + blend_space + "' (it has " +
                    spaceList(c.rig()) + ")");
  return marionette::capi::guarded(scene, [&] {  // the clip callback hears it start
    return c.playBlend(layer, std::move(space), marionette::capi::toPlayOptions(o))  // additive refused above
               ? MN_OK
               : fail(scene, MN_ERROR_INTERNAL, "mn_character_play_blend: the character refused the blend space");
  });
}

mn_status mn_character_set_blend_parameter(mn_character* character, int layer, float x, float y) {
  if (!isLive(character))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT,
                std::string("mn_character_set_blend_parameter: character") + notLive(character));
  mn_scene* scene = character->owner;
  if (layer < 0 || layer >= marionette::Character::kMaxLayers)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_set_blend_parameter: layer " + std::to_string(layer) + " is not in " + layerRange());
  if (!std::isfinite(x) || !std::isfinite(y))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_character_set_blend_parameter: x and y must be finite numbers");
  if (!character->character->layerBlendSpace(layer))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_set_blend_parameter: layer " + std::to_string(layer) +
                    " plays no blend space (mn_character_play_blend first)");
  (void)character->character->setBlendParameter(layer, x, y);
  return MN_OK;
}

}  // extern "C"
