/* The installed C API alone, from CMake or pkg-config: the version it was compiled
 * against is the library's, a scene updates, and the library says no GPL synthesizer
 * is linked in (libmarionette_c). The engine's hooks: its allocator (set first) gets the
 * runtime's blocks and every one back; an asset is loaded from memory, its buffer read
 * through the engine's read function, and 20 characters share it; the scene's work runs
 * through the engine's parallel-for; the event callback and the blend-space calls answer. */
#include <marionette/marionette.h>
#include <marionette/version.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static long blocks = 0, allocations = 0;
static void* engine_alloc(void* user, size_t size, size_t alignment) {
  (void)user;
  ++blocks, ++allocations;
  return aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
}
static void engine_free(void* user, void* block, size_t size, size_t alignment) {
  (void)user, (void)size, (void)alignment;
  --blocks;
  free(block);
}

static int chunks_run = 0;
static void engine_parallel_for(void* user, mn_parallel_task_fn task, void* context, int chunk_count) {
  int i;
  (void)user;
  for (i = chunk_count - 1; i >= 0; --i, ++chunks_run) task(context, i); /* any order */
}

static void on_event(void* user, const mn_animation_event* event) {
  (void)user, (void)event;
}

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
  char name[16];
  int i;
  int ok = mn_set_allocator(engine_alloc, engine_free, NULL) == MN_OK;
  ok = ok && strcmp(mn_version(), MARIONETTE_VERSION_STRING) == 0;
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
  for (i = 0; ok && i < 18; ++i) {
    snprintf(name, sizeof name, "c%d", i);
    ok = mn_scene_add_character_from_asset(scene, name, asset, NULL) == MN_OK;
  }
  mn_asset_release(asset);
  ok = ok && mn_scene_set_parallel_for(scene, engine_parallel_for, NULL) == MN_OK &&
       mn_scene_set_event_callback(scene, on_event, NULL) == MN_OK;
  ok = ok && mn_scene_update(scene, 1.0 / 60.0) == MN_OK && chunks_run >= 2 &&
       mn_character_palette(b, MN_PALETTE_MAT4_COLUMN_MAJOR, 0, palette, 32) == MN_OK && palette[16 + 13] == 1.0f;
  ok = ok && mn_character_blend_space_count(a) == 0 &&
       mn_character_play_blend(a, 0, "locomotion", NULL) == MN_ERROR_NOT_FOUND &&
       mn_character_set_blend_parameter(a, 0, 1.0f, 0.0f) == MN_ERROR_INVALID_ARGUMENT;
  mn_scene_destroy(scene);
  /* Destroyed handles are held back from reuse; going back to the default allocator frees them. */
  ok = ok && mn_set_allocator(NULL, NULL, NULL) == MN_OK;
  ok = ok && allocations > 0 && blocks == 0; /* every runtime block came back to the engine */
  if (allocations == 0 || blocks != 0) fprintf(stderr, "c_only: %ld allocations, %ld blocks not freed\n", allocations, blocks);
  printf("c_only: %s (marionette %s)\n", ok ? "ok" : "FAILED", mn_version());
  return ok ? 0 : 1;
}
