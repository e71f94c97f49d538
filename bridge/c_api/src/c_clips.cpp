// The C API's clip functions (marionette.h): the rig's clips, and playing and stopping
// them on a character's layers (Character::play / stop).
#include <cmath>
#include <string>
#include <vector>

#include "handles.hpp"
#include "marionette/core/text.hpp"

using marionette::capi::fail;
using marionette::capi::isLive;
using marionette::capi::notLive;

namespace {

const marionette::AnimationClip* clipAt(const mn_character* c, size_t clip) {
  if (!isLive(c)) return nullptr;
  const auto& clips = c->character->rig().clips();
  return clip < clips.size() ? clips[clip].get() : nullptr;
}

// "'Idle', 'Walking' and 6 more", for messages.
std::string clipList(const marionette::Rig& rig) {
  std::vector<std::string> names;
  for (const auto& c : rig.clips()) names.push_back(c->clip.name);
  return names.empty() ? std::string("none") : marionette::quotedNameList(names);
}

}  // namespace

extern "C" {

size_t mn_character_clip_count(const mn_character* character) {
  return isLive(character) ? character->character->rig().clips().size() : 0;
}

const char* mn_character_clip_name(const mn_character* character, size_t clip) {
  const marionette::AnimationClip* c = clipAt(character, clip);
  return c ? c->clip.name.c_str() : nullptr;
}

double mn_character_clip_duration(const mn_character* character, size_t clip) {
  const marionette::AnimationClip* c = clipAt(character, clip);
  return c ? static_cast<double>(c->clip.duration) : 0.0;
}

mn_play_options mn_play_options_default(void) {
  const marionette::PlayOptions d;
  return mn_play_options{sizeof(mn_play_options), d.weight, d.speed, d.wrap == marionette::WrapMode::Loop ? 1 : 0, d.startTime,
                         d.fadeIn,  d.additive ? 1 : 0, d.rootMotion ? 1 : 0};
}

mn_status mn_character_play(mn_character* character, int layer, const char* clip, const mn_play_options* options) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_play: character") + notLive(character));
  mn_scene* scene = character->owner;
  if (!clip) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_character_play: clip is NULL");
  marionette::Character& c = *character->character;
  if (layer < 0 || layer >= marionette::Character::kMaxLayers)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_play: layer " + std::to_string(layer) + " is not in 0.." +
                    std::to_string(marionette::Character::kMaxLayers - 1));
  if (options && options->struct_size != sizeof(mn_play_options))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, marionette::capi::badStructSize("mn_character_play", "mn_play_options",
                                                                               options->struct_size, sizeof(mn_play_options)));
  const mn_play_options o = options ? *options : mn_play_options_default();
  if (!std::isfinite(o.weight) || o.weight < 0.0f || !std::isfinite(o.speed) || !std::isfinite(o.start_time) ||
      !std::isfinite(o.fade_in) || o.fade_in < 0.0f)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_play: options: weight and fade_in must be finite and >= 0, speed and start_time finite");
  auto found = c.rig().findClip(clip);
  if (!found)
    return fail(scene, MN_ERROR_NOT_FOUND,
                "mn_character_play: character '" + c.name() + "' has no clip '" + clip + "' (it has " + clipList(c.rig()) + ")");
  return marionette::capi::guarded(scene, [&] {  // the clip callback hears it start
    return c.play(layer, std::move(found), marionette::capi::toPlayOptions(o)) ? MN_OK
                                               : fail(scene, MN_ERROR_INTERNAL, "mn_character_play: the character refused the clip");
  });
}

mn_status mn_character_stop(mn_character* character, int layer, float fade_out) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_stop: character") + notLive(character));
  if (layer < 0 || layer >= marionette::Character::kMaxLayers || !std::isfinite(fade_out) || fade_out < 0.0f)
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_stop: layer must be in 0.." + std::to_string(marionette::Character::kMaxLayers - 1) +
                    " and fade_out finite and >= 0");
  return marionette::capi::guarded(character->owner, [&] {
    character->character->stop(layer, fade_out);
    return MN_OK;
  });
}

}  // extern "C"
