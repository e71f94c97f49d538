/* An engine's use of Marionette's assets from C (C11, marionette.h alone):
 *   c_shared_assets CHARACTER_FILE [MOTION_FILE...]
 * The engine keeps its data in a packed archive: here the files are read into memory first
 * and served under "pak/<file name>" by a read function, so the library touches no file of
 * its own. The character is loaded once from memory (mn_asset_load_memory) and 100
 * characters share it; each motion file (a BVH, an FBX, ...) is loaded through the same read
 * function. Nothing here starts a process (Assimp's formats are read in-process:
 * mn_import_options.isolate stays 0). Prints one line per fact:
 *   asset: NAME, J joints, C clips, T ms
 *   characters: 100 added in T ms, B bytes each
 *   frames: 60 updates of 100 characters, T us per character
 *   motion: NAME, J joints, C clips, T ms */
#include <marionette/marionette.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#define CHARACTERS 100
#define MAX_FILES 8

/* The engine's archive: whole files by name. */
typedef struct {
  char name[256];
  unsigned char* bytes;
  size_t size;
} packed_file;
typedef struct {
  packed_file files[MAX_FILES];
  int count;
  int reads;
} archive;

static const char* base_name(const char* path) {
  const char* slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

static int pack(archive* a, const char* path) {
  packed_file* f;
  FILE* in;
  long size;
  if (a->count == MAX_FILES) return 0;
  f = &a->files[a->count];
  in = fopen(path, "rb");
  if (!in) return 0;
  if (fseek(in, 0, SEEK_END) != 0 || (size = ftell(in)) <= 0 || fseek(in, 0, SEEK_SET) != 0) {
    fclose(in);
    return 0;
  }
  f->bytes = malloc((size_t)size);
  f->size = (size_t)size;
  if (!f->bytes || fread(f->bytes, 1, f->size, in) != f->size) {
    fclose(in);
    return 0;
  }
  fclose(in);
  snprintf(f->name, sizeof f->name, "pak/%s", base_name(path));
  ++a->count;
  return 1;
}

/* mn_read_file_fn: the library asks for a file; the archive writes it into the sink. */
static int read_from_archive(void* user, const char* path, mn_file_sink* sink) {
  archive* a = user;
  int i;
  for (i = 0; i < a->count; ++i)
    if (strcmp(a->files[i].name, path) == 0) {
      ++a->reads;
      return mn_file_sink_write(sink, a->files[i].bytes, a->files[i].size) == MN_OK;
    }
  return 0; /* not in the archive */
}

static double now_ms(void) {
  struct timespec t;
  timespec_get(&t, TIME_UTC);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static size_t heap_in_use(void) {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  return mallinfo2().uordblks;
#else
  return 0; /* not measured on this C library */
#endif
}

int main(int argc, char** argv) {
  archive a;
  mn_import_options options = mn_import_options_default();
  mn_asset* robot = NULL;
  mn_scene* scene = NULL;
  double t0, load_ms, add_ms, frames_ms;
  size_t heap0, extra;
  char name[32];
  int i;
  if (argc < 2) {
    fprintf(stderr, "usage: c_shared_assets CHARACTER_FILE [MOTION_FILE...]\n");
    return 2;
  }
  memset(&a, 0, sizeof a);
  for (i = 1; i < argc; ++i)
    if (!pack(&a, argv[i])) {
      fprintf(stderr, "cannot read %s\n", argv[i]);
      return 2;
    }
  options.read_file = read_from_archive;
  options.read_file_user = &a;

  /* One load from memory; the bytes may go once it returns. */
  t0 = now_ms();
  if (mn_asset_load_memory(a.files[0].bytes, a.files[0].size, a.files[0].name, &options, &robot) != MN_OK) {
    fprintf(stderr, "%s\n", mn_scene_last_error(NULL));
    return 1;
  }
  load_ms = now_ms() - t0;
  printf("asset: %s, %zu joints, %zu clips, %.2f ms\n", mn_asset_name(robot), mn_asset_joint_count(robot),
         mn_asset_clip_count(robot), load_ms);

  if (mn_scene_create(&scene) != MN_OK) return 1;
  /* The first character sizes the scene's shared scratch; the rest are what each costs,
   * each walking (a clip layer of its own). */
  heap0 = 0;
  t0 = now_ms();
  for (i = 0; i < CHARACTERS; ++i) {
    mn_character* c = NULL;
    mn_play_options play = mn_play_options_default();
    play.start_time = 0.013 * i; /* not in lockstep */
    snprintf(name, sizeof name, "robot%d", i);
    if (mn_scene_add_character_from_asset(scene, name, robot, &c) != MN_OK ||
        mn_character_play(c, 0, "Walking", &play) != MN_OK) {
      fprintf(stderr, "%s\n", mn_scene_last_error(scene));
      return 1;
    }
    if (i == 0) heap0 = heap_in_use();
  }
  add_ms = now_ms() - t0;
  extra = heap_in_use() - heap0;
  mn_asset_release(robot); /* the characters keep what they share */
  printf("characters: %d added in %.2f ms, %zu bytes each\n", CHARACTERS, add_ms, extra / (CHARACTERS - 1));

  t0 = now_ms();
  for (i = 0; i < 60; ++i)
    if (mn_scene_update(scene, 1.0 / 60.0) != MN_OK) return 1;
  frames_ms = now_ms() - t0;
  printf("frames: 60 updates of %d characters, %.2f us per character\n", CHARACTERS,
         frames_ms * 1e3 / (60.0 * CHARACTERS));
  mn_scene_destroy(scene);

  /* Motion files through the same archive: Assimp's readers run in this process. */
  for (i = 1; i < a.count; ++i) {
    mn_asset* motion = NULL;
    t0 = now_ms();
    if (mn_asset_load_file(a.files[i].name, &options, &motion) != MN_OK) {
      fprintf(stderr, "%s\n", mn_scene_last_error(NULL));
      return 1;
    }
    printf("motion: %s, %zu joints, %zu clips, %.2f ms\n", mn_asset_name(motion), mn_asset_joint_count(motion),
           mn_asset_clip_count(motion), now_ms() - t0);
    mn_asset_release(motion);
  }
  printf("archive reads: %d\n", a.reads);
  for (i = 0; i < a.count; ++i) free(a.files[i].bytes);
  return 0;
}
