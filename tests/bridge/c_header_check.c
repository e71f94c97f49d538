/* marionette.h compiles as strict C99 (-pedantic -Werror): no C++ in the C API header. */
#include <marionette/marionette.h>

/* Every enum of the API is 32 bits wide (C99 has no _Static_assert: a negative array size fails). */
typedef char mn_status_is_32_bits[sizeof(mn_status) == 4 ? 1 : -1];
typedef char mn_speech_synthesis_is_32_bits[sizeof(mn_speech_synthesis) == 4 ? 1 : -1];
typedef char mn_palette_layout_is_32_bits[sizeof(mn_palette_layout) == 4 ? 1 : -1];
typedef char mn_feedback_kind_is_32_bits[sizeof(mn_feedback_kind) == 4 ? 1 : -1];
typedef char mn_clip_event_kind_is_32_bits[sizeof(mn_clip_event_kind) == 4 ? 1 : -1];
typedef char mn_log_level_is_32_bits[sizeof(mn_log_level) == 4 ? 1 : -1];
typedef char mn_animation_event_kind_is_32_bits[sizeof(mn_animation_event_kind) == 4 ? 1 : -1];
typedef char mn_foot_side_is_32_bits[sizeof(mn_foot_side) == 4 ? 1 : -1];
typedef char mn_audio_event_kind_is_32_bits[sizeof(mn_audio_event_kind) == 4 ? 1 : -1];

size_t marionette_c_header_check(const mn_character* character);
size_t marionette_c_header_check(const mn_character* character) {
  mn_feedback feedback;
  feedback.kind = MN_FEEDBACK_WARNING;
  (void)feedback;
  return mn_character_joint_count(character) * mn_palette_floats_per_joint(MN_PALETTE_MAT3X4_ROW_MAJOR);
}
