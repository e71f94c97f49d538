// The C API's character functions (marionette.h): joints, placement, the bone
// palette through the bridge's PaletteBinding, morph weights.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstring>
#include <string>

#include "handles.hpp"

using marionette::capi::fail;

namespace {

using marionette::capi::isLive;
using marionette::capi::notLive;

const mn_scene* ownerOf(const mn_character* c) { return c ? c->owner : nullptr; }

bool validLayout(mn_palette_layout layout) {
  return layout == MN_PALETTE_MAT4_COLUMN_MAJOR || layout == MN_PALETTE_MAT4_ROW_MAJOR ||
         layout == MN_PALETTE_MAT3X4_ROW_MAJOR;
}

}  // namespace

extern "C" {

const char* mn_character_name(const mn_character* character) {
  return isLive(character) ? character->character->name().c_str() : "";
}

size_t mn_character_joint_count(const mn_character* character) {
  return isLive(character) ? character->character->skeleton().jointCount() : 0;
}

const char* mn_character_joint_name(const mn_character* character, size_t joint) {
  if (!isLive(character) || joint >= character->character->skeleton().jointCount()) return nullptr;
  return character->character->skeleton().names[joint].c_str();
}

int mn_character_find_joint(const mn_character* character, const char* name) {
  return isLive(character) && name ? character->character->skeleton().findJoint(name) : -1;
}

mn_status mn_character_set_position(mn_character* character, float x, float y, float z) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_set_position: character") + notLive(character));
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_set_position: a coordinate is not finite");
  return marionette::capi::guarded(character->owner, [&] {  // listeners hear of the change
    character->character->setPosition({x, y, z});
    return MN_OK;
  });
}

mn_status mn_character_set_heading(mn_character* character, float radians) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_set_heading: character") + notLive(character));
  if (!std::isfinite(radians))
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_set_heading: the heading is not finite");
  return marionette::capi::guarded(character->owner, [&] {
    character->character->setHeading(radians);
    return MN_OK;
  });
}

int mn_character_joint_parent(const mn_character* character, size_t joint) {
  if (!isLive(character) || joint >= character->character->skeleton().jointCount()) return -2;
  return character->character->skeleton().parents[joint];
}

mn_status mn_character_rest_pose(const mn_character* character, float* out, size_t out_floats) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_rest_pose: character") + notLive(character));
  const marionette::Skeleton& s = character->character->skeleton();
  if (!out || out_floats < 10 * s.jointCount())
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_rest_pose: out is NULL or holds fewer than 10 * " + std::to_string(s.jointCount()) + " floats");
  for (const marionette::Transform& t : s.restPose) {
    const float values[10] = {t.translation.x, t.translation.y, t.translation.z, t.rotation.x, t.rotation.y,
                              t.rotation.z,    t.rotation.w,    t.scale.x,       t.scale.y,    t.scale.z};
    out = std::copy(std::begin(values), std::end(values), out);
  }
  return MN_OK;
}

mn_status mn_character_root_transform(const mn_character* character, float* out16) {
  if (!isLive(character))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_root_transform: character") + notLive(character));
  if (!out16) return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_root_transform: out16 is NULL");
  const glm::mat4& m = character->character->skeleton().rootTransform;
  std::memcpy(out16, &m[0][0], 16 * sizeof(float));
  return MN_OK;
}

mn_status mn_character_root_motion_delta(const mn_character* character, float* out4) {
  if (!isLive(character))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_root_motion_delta: character") + notLive(character));
  if (!out4) return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_root_motion_delta: out4 is NULL");
  const marionette::PlacementDelta d = character->character->lastMotion();
  out4[0] = d.translation.x;
  out4[1] = d.translation.y;
  out4[2] = d.translation.z;
  out4[3] = d.turn;
  return MN_OK;
}

mn_status mn_character_world_matrix(const mn_character* character, float* out16) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_world_matrix: character") + notLive(character));
  if (!out16) return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_world_matrix: out16 is NULL");
  std::memcpy(out16, character->character->transformBuffer().world(), 16 * sizeof(float));
  return MN_OK;
}

size_t mn_palette_floats_per_joint(mn_palette_layout layout) {
  return validLayout(layout) ? marionette::bridge::floatsPerBone(static_cast<marionette::bridge::PaletteLayout>(layout))
                             : 0;
}

mn_status mn_character_palette(const mn_character* character, mn_palette_layout layout, int inverse_bind, float* out,
                               size_t out_floats) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_palette: character") + notLive(character));
  if (!validLayout(layout))
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_palette: unknown layout " + std::to_string(layout));
  if (!out) return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_palette: out is NULL");
  const auto cppLayout = static_cast<marionette::bridge::PaletteLayout>(layout);
  if (character->palette->copy(character->character->transformBuffer(), {out, out_floats}, {cppLayout, inverse_bind != 0}))
    return MN_OK;
  return marionette::capi::guarded(ownerOf(character), [&] {
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT,
                "mn_character_palette: character '" + character->character->name() + "' needs " +
                    std::to_string(character->palette->floatCount(cppLayout)) + " floats (" +
                    std::to_string(character->palette->slotCount()) + " joints x " +
                    std::to_string(marionette::bridge::floatsPerBone(cppLayout)) + "), got " +
                    std::to_string(out_floats));
  });
}

size_t mn_character_morph_count(const mn_character* character) {
  return isLive(character) ? character->character->transformBuffer().morphCount() : 0;
}

const char* mn_character_morph_name(const mn_character* character, size_t morph) {
  if (!isLive(character)) return nullptr;
  const std::vector<std::string>& names = character->character->rig().morphTargets();
  return morph < names.size() ? names[morph].c_str() : nullptr;
}

mn_status mn_character_morph_weights(const mn_character* character, float* out, size_t out_floats) {
  if (!isLive(character)) return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_character_morph_weights: character") + notLive(character));
  const std::span<const float> weights = character->character->transformBuffer().morphWeights();
  if (!out && !weights.empty())
    return fail(character->owner, MN_ERROR_INVALID_ARGUMENT, "mn_character_morph_weights: out is NULL");
  if (out_floats < weights.size())
    return marionette::capi::guarded(character->owner, [&] {
      return fail(character->owner, MN_ERROR_INVALID_ARGUMENT,
                  "mn_character_morph_weights: character '" + character->character->name() + "' has " +
                      std::to_string(weights.size()) + " morphs, got room for " + std::to_string(out_floats));
    });
  if (!weights.empty()) std::memcpy(out, weights.data(), weights.size() * sizeof(float));
  return MN_OK;
}

}  // extern "C"
