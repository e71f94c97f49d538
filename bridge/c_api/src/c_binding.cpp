// The C API's bindings (marionette.h): bridge::PaletteBinding and MorphBinding
// for an engine skeleton given as names, parents and morph slots, with its joint
// maps read from files or guessed.

#include <filesystem>
#include <string>
#include <vector>

#include "handles.hpp"
#include "marionette/rig/joint_map.hpp"

using marionette::capi::fail;
using marionette::capi::isLive;
using marionette::capi::notLive;

namespace {

namespace retarget = marionette::retarget;

const mn_scene* sceneOf(const mn_binding* b) { return isLive(b) && isLive(b->character) ? b->character->owner : nullptr; }

// Refuses a destroyed binding and one whose character is gone; "" when usable.
std::string refused(const mn_binding* b, const char* function) {
  if (!isLive(b)) return std::string(function) + ": binding" + notLive(b);
  if (!isLive(b->character)) return std::string(function) + ": the binding's character was removed or its scene destroyed";
  return {};
}

// The engine's skeleton as a Skeleton (parents before children, as Skeleton wants them),
// and the engine slot of each of its joints. Rest poses are unknown: identity.
struct EngineSkeleton {
  marionette::Asset asset;
  std::vector<int> slotOf;  // joint -> engine slot
};

std::string buildEngineSkeleton(const mn_engine_skeleton& e, EngineSkeleton& out) {
  const std::size_t n = e.bone_count;
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (std::size_t i = 0; i < n; ++i) {
    const int p = e.parents[i];
    if (p == -1) roots.push_back(static_cast<int>(i));
    else if (p < 0 || static_cast<std::size_t>(p) >= n || static_cast<std::size_t>(p) == i)
      return "bone " + std::to_string(i) + " ('" + e.bone_names[i] + "'): parent " + std::to_string(p) +
             " is neither -1 nor another bone (0.." + std::to_string(n - 1) + ")";
    else children[static_cast<std::size_t>(p)].push_back(static_cast<int>(i));
  }
  std::vector<int> jointOf(n, -1);
  for (std::size_t k = 0; k < roots.size(); ++k) {  // breadth first: a parent is placed before its children
    std::vector<int> queue{roots[k]};
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int slot = queue[q];
      const int parent = e.parents[slot] < 0 ? -1 : jointOf[static_cast<std::size_t>(e.parents[slot])];
      jointOf[static_cast<std::size_t>(slot)] = out.asset.skeleton.addJoint(e.bone_names[slot], parent, marionette::Transform{});
      out.slotOf.push_back(slot);
      for (int c : children[static_cast<std::size_t>(slot)]) queue.push_back(c);
    }
  }
  if (out.slotOf.size() != n) {
    for (std::size_t i = 0; i < n; ++i)
      if (jointOf[i] < 0) return "bone " + std::to_string(i) + " ('" + e.bone_names[i] + "') is in a cycle of parents";
  }
  out.asset.sourcePath = "engine skeleton";
  return {};
}

// A map loaded for the engine's Skeleton, its joints turned into engine slots.
void toSlots(retarget::JointMap& map, const std::vector<int>& slotOf) {
  for (int& j : map.bones)
    if (j >= 0) j = slotOf[static_cast<std::size_t>(j)];
  for (auto& chain : map.chains)
    for (int& j : chain) j = slotOf[static_cast<std::size_t>(j)];
}

// Reads or guesses a map; errors become the call's status, warnings lines of the report.
// Where the shipped joint maps are, as `marionette retarget` looks, with this library's
// folder (capi::libraryFolder) in place of the program's.
std::vector<std::string> shippedJointMapFolders() {
  return retarget::shippedJointMapFolders(marionette::capi::libraryFolder(), MARIONETTE_SOURCE_JOINTMAPS);
}

// `shipped`: without a file, and without a VRM humanoid map of its own, the shipped map that
// fits the asset (every joint it names exists, the topology agrees) comes before a guess
// from names (for a character; an engine's skeleton is guessed, as documented).
mn_status mapFrom(const mn_scene* scene, const char* path, const marionette::Asset& asset, const char* whose,
                  bool shipped, retarget::JointMap& map, std::string& report) {
  if (!path && shipped && !asset.hasHumanoid)
    if (auto found = retarget::findJointMap(asset, shippedJointMapFolders())) {
      report += std::string(whose) + " joint map: " + found->file + " (the shipped map that fits)\n";
      map = std::move(found->result.map);
      return MN_OK;
    }
  std::error_code ec;
  if (path && !std::filesystem::is_regular_file(path, ec))
    return fail(scene, MN_ERROR_IO, std::string(path) + ": error: cannot open the " + whose + " joint map");
  retarget::JointMapResult r = path ? retarget::loadJointMap(path, asset) : retarget::guessJointMap(asset);
  if (!r.diagnostics.ok())
    return fail(scene, MN_ERROR_LOAD, "mn_binding_create: the " + std::string(whose) + " joint map:\n" + r.diagnostics.format());
  for (const marionette::Diagnostic& d : r.diagnostics.items) report += std::string(whose) + " joint map: " + d.format() + "\n";
  map = std::move(r.map);
  return MN_OK;
}

}  // namespace

extern "C" {

mn_binding_options mn_binding_options_default(void) { return mn_binding_options{sizeof(mn_binding_options), 0, nullptr, nullptr}; }

mn_status mn_binding_create(mn_character* character, const mn_engine_skeleton* engine, const mn_binding_options* options,
                            mn_binding** out) {
  if (out) *out = nullptr;
  if (!isLive(character))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_binding_create: character") + notLive(character));
  const mn_scene* scene = character->owner;
  if (!engine || !out) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_create: engine or out is NULL");
  if ((engine->bone_count > 0 && !engine->bone_names) || (engine->morph_count > 0 && !engine->morph_names))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_create: engine: bone_names or morph_names is NULL");
  for (std::size_t i = 0; i < engine->bone_count; ++i)
    if (!engine->bone_names[i])
      return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_create: engine: bone_names[" + std::to_string(i) + "] is NULL");
  for (std::size_t i = 0; i < engine->morph_count; ++i)
    if (!engine->morph_names[i])
      return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_create: engine: morph_names[" + std::to_string(i) + "] is NULL");
  if (options && options->struct_size != sizeof(mn_binding_options))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, marionette::capi::badStructSize("mn_binding_create", "mn_binding_options",
                                                                               options->struct_size, sizeof(mn_binding_options)));
  const mn_binding_options o = options ? *options : mn_binding_options_default();
  if (!o.through_joint_maps && (o.engine_joint_map || o.character_joint_map))
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_binding_create: options: a joint map is given but through_joint_maps is 0 (it would be ignored)");
  if (o.through_joint_maps && !engine->parents)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_binding_create: options: binding through joint maps needs the engine's parents (engine->parents is "
                "NULL): a map is checked against the skeleton's topology");

  return marionette::capi::guarded(scene, [&] {
    const marionette::Character& c = *character->character;
    const std::vector<std::string> bones(engine->bone_names, engine->bone_names + engine->bone_count);
    const std::vector<std::string> slots(engine->morph_names, engine->morph_names + engine->morph_count);
    auto b = std::make_unique<mn_binding>();
    b->character = character;
    if (o.through_joint_maps) {
      EngineSkeleton skeleton;
      if (const std::string why = buildEngineSkeleton(*engine, skeleton); !why.empty())
        return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_create: engine: " + why);
      retarget::JointMap engineMap, characterMap;
      if (const mn_status s = mapFrom(scene, o.engine_joint_map, skeleton.asset, "engine", false, engineMap, b->report); s != MN_OK)
        return s;
      toSlots(engineMap, skeleton.slotOf);
      if (!character->asset)
        return fail(scene, MN_ERROR_INTERNAL, "mn_binding_create: the character's imported asset is not known");
      if (const mn_status s = mapFrom(scene, o.character_joint_map, *character->asset, "character", true, characterMap, b->report);
          s != MN_OK)
        return s;
      const marionette::bridge::BindMaps maps{engineMap, characterMap};
      b->palette = marionette::bridge::PaletteBinding(c.skeleton(), bones, &maps);
    } else {
      b->palette = marionette::bridge::PaletteBinding(c.skeleton(), bones);
    }
    b->morphs = marionette::bridge::MorphBinding(c.rig().morphTargets(), slots);
    b->report += b->palette.report().format() + b->morphs.report().format();
    *out = b.release();
    return MN_OK;
  });
}

void mn_binding_destroy(mn_binding* binding) {
  if (isLive(binding)) delete binding;
}

const char* mn_binding_report(const mn_binding* binding) { return isLive(binding) ? binding->report.c_str() : ""; }

size_t mn_binding_bone_count(const mn_binding* binding) { return isLive(binding) ? binding->palette.slotCount() : 0; }

size_t mn_binding_morph_slot_count(const mn_binding* binding) {
  return isLive(binding) ? binding->morphs.slotCount() : 0;
}

int mn_binding_joint_for_bone(const mn_binding* binding, size_t slot) {
  return isLive(binding) && slot < binding->palette.slotCount() ? binding->palette.jointForSlot(slot) : -1;
}

int mn_binding_morph_for_slot(const mn_binding* binding, size_t slot) {
  return isLive(binding) && slot < binding->morphs.slotCount() ? binding->morphs.morphForSlot(slot) : -1;
}

mn_status mn_binding_palette(const mn_binding* binding, mn_palette_layout layout, int inverse_bind, float* out,
                             size_t out_floats) {
  if (!isLive(binding) || !isLive(binding->character))
    return marionette::capi::guarded(sceneOf(binding), [&] {
      return fail(sceneOf(binding), MN_ERROR_INVALID_ARGUMENT, refused(binding, "mn_binding_palette"));
    });
  const mn_scene* scene = binding->character->owner;
  if (layout < MN_PALETTE_MAT4_COLUMN_MAJOR || layout > MN_PALETTE_MAT3X4_ROW_MAJOR)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_palette: unknown layout " + std::to_string(layout));
  if (!out) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_palette: out is NULL");
  const auto cppLayout = static_cast<marionette::bridge::PaletteLayout>(layout);
  if (binding->palette.copy(binding->character->character->transformBuffer(), {out, out_floats},
                            {cppLayout, inverse_bind != 0}))
    return MN_OK;
  return marionette::capi::guarded(scene, [&] {
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_binding_palette: the engine skeleton needs " + std::to_string(binding->palette.floatCount(cppLayout)) +
                    " floats (" + std::to_string(binding->palette.slotCount()) + " bones x " +
                    std::to_string(marionette::bridge::floatsPerBone(cppLayout)) + "), got " + std::to_string(out_floats));
  });
}

mn_status mn_binding_morph_weights(const mn_binding* binding, float* out, size_t out_floats) {
  if (!isLive(binding) || !isLive(binding->character))
    return marionette::capi::guarded(sceneOf(binding), [&] {
      return fail(sceneOf(binding), MN_ERROR_INVALID_ARGUMENT, refused(binding, "mn_binding_morph_weights"));
    });
  const mn_scene* scene = binding->character->owner;
  if (!out && binding->morphs.slotCount() > 0)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_binding_morph_weights: out is NULL");
  if (binding->morphs.copy(binding->character->character->transformBuffer(), {out, out_floats})) return MN_OK;
  return marionette::capi::guarded(scene, [&] {
    return fail(scene, MN_ERROR_INVALID_ARGUMENT,
                "mn_binding_morph_weights: the engine has " + std::to_string(binding->morphs.slotCount()) +
                    " morph slots, got room for " + std::to_string(out_floats));
  });
}

}  // extern "C"
