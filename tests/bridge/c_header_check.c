/* marionette.h compiles as strict C99 (-pedantic -Werror): no C++ in the C API header. */
#include <marionette/marionette.h>

size_t marionette_c_header_check(const mn_character* character);
size_t marionette_c_header_check(const mn_character* character) {
  mn_feedback feedback;
  feedback.kind = MN_FEEDBACK_WARNING;
  (void)feedback;
  return mn_character_joint_count(character) * mn_palette_floats_per_joint(MN_PALETTE_MAT3X4_ROW_MAJOR);
}
