/* The C API through the installed header and shared library: a scene made and freed. */
#include <marionette/marionette.h>

int c_consumer_ok(void);
int c_consumer_ok(void) {
  mn_scene* scene = 0;
  if (mn_scene_create(&scene) != MN_OK) return 0;
  const int ok = mn_scene_update(scene, 1.0 / 60.0) == MN_OK && mn_scene_update(scene, -1.0) == MN_ERROR_INVALID_ARGUMENT;
  mn_scene_destroy(scene);
  return ok;
}
