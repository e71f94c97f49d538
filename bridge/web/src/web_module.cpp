// The WebAssembly module's entry: nothing runs at start; JavaScript calls the C API's mn_
// functions (exported by bridge/web/CMakeLists.txt) through js/marionette.mjs, which reads
// and writes the C structs at fixed offsets. Those offsets are checked here, so a change
// to the header that moves a field fails the web build instead of corrupting memory.
#include <cstddef>

#include "marionette/marionette.h"

#define MN_WEB_FIELD(type, field, offset) static_assert(offsetof(type, field) == (offset), #type "." #field " moved: update LAYOUT in js/marionette.mjs")

static_assert(sizeof(void*) == 4 && sizeof(size_t) == 4, "the JS wrapper assumes wasm32");
static_assert(sizeof(mn_import_options) == 28, "mn_import_options changed size");
MN_WEB_FIELD(mn_import_options, read_file, 4);
MN_WEB_FIELD(mn_import_options, read_file_user, 8);
MN_WEB_FIELD(mn_import_options, profile_path, 12);
static_assert(sizeof(mn_binding_options) == 16, "mn_binding_options changed size");
MN_WEB_FIELD(mn_binding_options, through_joint_maps, 4);
static_assert(sizeof(mn_play_options) == 40, "mn_play_options changed size");
MN_WEB_FIELD(mn_play_options, weight, 4);
MN_WEB_FIELD(mn_play_options, speed, 8);
MN_WEB_FIELD(mn_play_options, loop, 12);
MN_WEB_FIELD(mn_play_options, start_time, 16);
MN_WEB_FIELD(mn_play_options, fade_in, 24);
MN_WEB_FIELD(mn_play_options, additive, 28);
MN_WEB_FIELD(mn_play_options, root_motion, 32);
static_assert(sizeof(mn_engine_skeleton) == 20, "mn_engine_skeleton changed size");
MN_WEB_FIELD(mn_engine_skeleton, parents, 4);
MN_WEB_FIELD(mn_engine_skeleton, bone_count, 8);
MN_WEB_FIELD(mn_engine_skeleton, morph_names, 12);
MN_WEB_FIELD(mn_engine_skeleton, morph_count, 16);
MN_WEB_FIELD(mn_engine_skeleton, bone_names, 0);
MN_WEB_FIELD(mn_binding_options, struct_size, 0);
MN_WEB_FIELD(mn_play_options, struct_size, 0);
// Callback payloads: every field the JS reads.
static_assert(sizeof(mn_feedback_kind) == 4 && sizeof(mn_animation_event_kind) == 4 && sizeof(mn_foot_side) == 4 &&
                  sizeof(mn_clip_event_kind) == 4 && sizeof(mn_audio_event_kind) == 4 && sizeof(mn_log_level) == 4,
              "the JS reads kinds as 32-bit ints");
MN_WEB_FIELD(mn_feedback, kind, 0);
MN_WEB_FIELD(mn_feedback, character, 4);
MN_WEB_FIELD(mn_feedback, block, 8);
MN_WEB_FIELD(mn_feedback, behavior, 12);
MN_WEB_FIELD(mn_feedback, sync_point, 16);
MN_WEB_FIELD(mn_feedback, message, 20);
MN_WEB_FIELD(mn_feedback, block_time, 24);
MN_WEB_FIELD(mn_feedback, scene_time, 32);
MN_WEB_FIELD(mn_viseme, character, 0);
MN_WEB_FIELD(mn_viseme, viseme, 4);
MN_WEB_FIELD(mn_viseme, weight, 8);
MN_WEB_FIELD(mn_viseme, time, 16);
MN_WEB_FIELD(mn_speech, character, 0);
MN_WEB_FIELD(mn_speech, behavior, 4);
MN_WEB_FIELD(mn_speech, samples, 8);
MN_WEB_FIELD(mn_speech, sample_count, 12);
MN_WEB_FIELD(mn_speech, sample_rate, 16);
MN_WEB_FIELD(mn_speech, audio_file, 20);
MN_WEB_FIELD(mn_speech, start_time, 24);
MN_WEB_FIELD(mn_speech, duration, 32);
MN_WEB_FIELD(mn_animation_event, kind, 0);
MN_WEB_FIELD(mn_animation_event, foot, 4);
MN_WEB_FIELD(mn_animation_event, character, 8);
MN_WEB_FIELD(mn_animation_event, name, 12);
MN_WEB_FIELD(mn_animation_event, clip, 16);
MN_WEB_FIELD(mn_animation_event, layer, 20);
MN_WEB_FIELD(mn_animation_event, weight, 24);
MN_WEB_FIELD(mn_animation_event, clip_time, 32);
MN_WEB_FIELD(mn_animation_event, scene_time, 40);
MN_WEB_FIELD(mn_audio, kind, 0);
MN_WEB_FIELD(mn_audio, character, 4);
MN_WEB_FIELD(mn_audio, behavior, 8);
MN_WEB_FIELD(mn_audio, samples, 12);
MN_WEB_FIELD(mn_audio, frame_count, 16);
MN_WEB_FIELD(mn_audio, channels, 20);
MN_WEB_FIELD(mn_audio, sample_rate, 24);
MN_WEB_FIELD(mn_audio, file, 28);
MN_WEB_FIELD(mn_audio, scene_time, 32);
MN_WEB_FIELD(mn_audio, duration, 40);

MN_WEB_FIELD(mn_clip_event, kind, 0);
MN_WEB_FIELD(mn_clip_event, character, 4);
MN_WEB_FIELD(mn_clip_event, clip, 8);
MN_WEB_FIELD(mn_clip_event, scene_time, 16);

int main() { return 0; }
