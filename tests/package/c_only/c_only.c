/* The installed C API alone, from CMake or pkg-config: the version it was compiled
 * against is the library's, a scene updates, and the library says no GPL synthesizer
 * is linked in (libmarionette_c). An asset is loaded from memory, its buffer read
 * through the engine's read function, and two characters share it. */
#include <marionette/marionette.h>
#include <marionette/version.h>
#include <stdio.h>
#include <string.h>

/* Two joints and a buffer of their own file ("pak/two.bin", 0 bytes used). */
static const char kGltf[] =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
    "\"nodes\":[{\"name\":\"root\",\"children\":[1]},{\"name\":\"tip\",\"translation\":[0,1,0]}],"
    "\"buffers\":[{\"uri\":\"two.bin\",\"byteLength\":4}]}";

static int reads = 0;
static int read_file(void* user, const char* path, mn_file_sink* sink) {
  static const unsigned char bin[4] = {0, 0, 0, 0};
  (void)user;
  if (strcmp(path, "pak/two.bin") != 0) return 0;
  ++reads;
  return mn_file_sink_write(sink, bin, sizeof bin) == MN_OK;
}

int main(void) {
  mn_scene* scene = 0;
  mn_asset* asset = 0;
  mn_character *a = 0, *b = 0;
  mn_import_options options = mn_import_options_default();
  float palette[2 * 16];
  int ok = strcmp(mn_version(), MARIONETTE_VERSION_STRING) == 0;
  if (!ok) fprintf(stderr, "c_only: library %s, header %s\n", mn_version(), MARIONETTE_VERSION_STRING);
  ok = ok && mn_has_speech_synthesis() == 0;
  ok = ok && mn_scene_create(&scene) == MN_OK && mn_scene_update(scene, 1.0 / 60.0) == MN_OK;
  options.read_file = read_file;
  if (ok && mn_asset_load_memory(kGltf, sizeof kGltf - 1, "pak/two.gltf", &options, &asset) != MN_OK) {
    fprintf(stderr, "c_only: %s\n", mn_scene_last_error(NULL));
    ok = 0;
  }
  ok = ok && reads == 1 && mn_asset_joint_count(asset) == 2;
  ok = ok && mn_scene_add_character_from_asset(scene, "a", asset, &a) == MN_OK &&
       mn_scene_add_character_from_asset(scene, "b", asset, &b) == MN_OK;
  mn_asset_release(asset);
  ok = ok && mn_scene_update(scene, 1.0 / 60.0) == MN_OK &&
       mn_character_palette(b, MN_PALETTE_MAT4_COLUMN_MAJOR, 0, palette, 32) == MN_OK && palette[16 + 13] == 1.0f;
  mn_scene_destroy(scene);
  printf("c_only: %s (marionette %s)\n", ok ? "ok" : "FAILED", mn_version());
  return ok ? 0 : 1;
}
