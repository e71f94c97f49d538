/* The installed C API alone, from CMake or pkg-config: the version it was compiled
 * against is the library's, a scene updates, and the library says no GPL synthesizer
 * is linked in (libmarionette_c). */
#include <marionette/marionette.h>
#include <marionette/version.h>
#include <stdio.h>
#include <string.h>

int main(void) {
  mn_scene* scene = 0;
  int ok = strcmp(mn_version(), MARIONETTE_VERSION_STRING) == 0;
  if (!ok) fprintf(stderr, "c_only: library %s, header %s\n", mn_version(), MARIONETTE_VERSION_STRING);
  ok = ok && mn_has_speech_synthesis() == 0;
  ok = ok && mn_scene_create(&scene) == MN_OK && mn_scene_update(scene, 1.0 / 60.0) == MN_OK;
  mn_scene_destroy(scene);
  printf("c_only: %s (marionette %s)\n", ok ? "ok" : "FAILED", mn_version());
  return ok ? 0 : 1;
}
