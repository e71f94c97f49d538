/* Embedding Marionette from C through marionette.h alone (compiled as C11).
 *   c_embedding CHARACTER_FILE [PROFILE_JSON|-] [PALETTE_OUT]
 * Creates a scene, loads a character, lists its clips and plays "Idle" on layer 0 when
 * it has one, sends a BML block (a nod and a spoken line, whose audio the speech
 * callback hands over),
 * updates 3 s at 60 Hz reading the bone palette (column-major, inverse bind) and
 * the morph weights into its own arrays each frame, counts BML feedback and
 * visemes, and prints one line per fact. Then binds the character to an "engine"
 * skeleton that orders the bones its own way and has a morph slot of its own
 * (mn_binding), and reads the palette and morphs in the engine's order. With
 * PALETTE_OUT, writes the last frame's palette there (one float per line) for the test
 * to compare with the C++ API. */
#include <marionette/marionette.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c_embedding_bml.h"

typedef struct {
  int feedback, predictions, block_starts, block_ends, sync_points, warnings;
  int visemes, log_warnings, lines, clip_starts;
  size_t samples;
  int sample_rate;
  char first_viseme[16];
} counts;

/* A line starts: an engine would queue sp->samples on its audio device at sp->start_time. */
/* An engine's own skeleton: the character's bones in reverse order (each parent after its
 * children, as some engines keep them) and its morphs plus an engine-only "blink" slot.
 * mn_binding matches them by name once; each frame copies in the engine's order. */
static int bind_engine_skeleton(mn_scene* scene, mn_character* c, const float* palette) {
  const size_t bones = mn_character_joint_count(c), morphs = mn_character_morph_count(c);
  const size_t per = mn_palette_floats_per_joint(MN_PALETTE_MAT4_COLUMN_MAJOR);
  const char** names = malloc((bones + morphs + 1) * sizeof *names);
  float* engine_palette = malloc(bones * per * sizeof *engine_palette);
  float* engine_morphs = malloc((morphs + 1) * sizeof *engine_morphs);
  mn_engine_skeleton engine;
  mn_binding* binding = NULL;
  size_t slot, k, bound = 0;
  int same = 1;
  if (!names || !engine_palette || !engine_morphs) return 2;
  for (slot = 0; slot < bones; ++slot) names[slot] = mn_character_joint_name(c, bones - 1 - slot);
  for (k = 0; k < morphs; ++k) names[bones + k] = mn_character_morph_name(c, k);
  names[bones + morphs] = "blink";
  engine.bone_names = names;
  engine.parents = NULL; /* by name alone: the parents are needed only to bind through joint maps */
  engine.bone_count = bones;
  engine.morph_names = names + bones;
  engine.morph_count = morphs + 1;
  if (mn_binding_create(c, &engine, NULL, &binding) != MN_OK ||
      mn_binding_palette(binding, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, engine_palette, bones * per) != MN_OK ||
      mn_binding_morph_weights(binding, engine_morphs, morphs + 1) != MN_OK) {
    fprintf(stderr, "binding: %s\n", mn_scene_last_error(scene));
    return 2;
  }
  for (slot = 0; slot < bones; ++slot) {
    const int joint = mn_binding_joint_for_bone(binding, slot);
    bound += joint >= 0;
    for (k = 0; joint >= 0 && k < per; ++k) same = same && engine_palette[slot * per + k] == palette[(size_t)joint * per + k];
  }
  printf("binding: %zu of %zu engine bones bound, palette in the engine's order equal to the character's: %s\n", bound,
         bones, same ? "yes" : "no");
  printf("binding report: %s", mn_binding_report(binding)); /* names the engine-only "blink" slot */
  mn_binding_destroy(binding);
  free(names);
  free(engine_palette);
  free(engine_morphs);
  return 0;
}

static void on_speech(void* user, const mn_speech* sp) {
  counts* c = (counts*)user;
  ++c->lines;
  c->samples += sp->samples ? sp->sample_count : 0;
  c->sample_rate = sp->sample_rate;
}

static void on_clip(void* user, const mn_clip_event* e) {
  counts* c = (counts*)user;
  if (e->kind == MN_CLIP_STARTED) ++c->clip_starts;
}

static void on_feedback(void* user, const mn_feedback* f) {
  counts* c = (counts*)user;
  ++c->feedback;
  switch (f->kind) {
    case MN_FEEDBACK_PREDICTION: ++c->predictions; break;
    case MN_FEEDBACK_BLOCK_PROGRESS:
      if (strcmp(f->sync_point, "start") == 0) ++c->block_starts;
      if (strcmp(f->sync_point, "end") == 0) ++c->block_ends;
      break;
    case MN_FEEDBACK_SYNC_POINT: ++c->sync_points; break;
    case MN_FEEDBACK_WARNING:
      ++c->warnings;
      fprintf(stderr, "bml warning: %s\n", f->message);
      break;
    default: break; /* script events (MN_FEEDBACK_EVENT), and kinds of later versions */
  }
}

static void on_viseme(void* user, const mn_viseme* v) {
  counts* c = (counts*)user;
  if (c->visemes++ == 0) snprintf(c->first_viseme, sizeof c->first_viseme, "%s", v->viseme);
}

static void on_log(void* user, mn_log_level level, const char* message) {
  counts* c = (counts*)user;
  if (level != MN_LOG_INFO) {
    ++c->log_warnings;
    fprintf(stderr, "log: %s\n", message);
  }
}

int main(int argc, char** argv) {
  mn_scene* scene = NULL;
  mn_character* robot = NULL;
  counts n;
  size_t joints, floats, morphs, i;
  float *palette, *first, *weights;
  float max_weight = 0.0f, motion = 0.0f;
  double checksum = 0.0;
  int frame, finite = 1;
  mn_status status;
  const char* profile = argc > 2 && strcmp(argv[2], "-") != 0 ? argv[2] : NULL;

  if (argc < 2) {
    fprintf(stderr, "usage: %s CHARACTER_FILE [PROFILE_JSON|-] [PALETTE_OUT]\n", argv[0]);
    return 2;
  }
  memset(&n, 0, sizeof n);
  if (mn_scene_create(&scene) != MN_OK) {
    fprintf(stderr, "%s\n", mn_scene_last_error(NULL));
    return 2;
  }
  mn_scene_set_feedback_callback(scene, on_feedback, &n);
  mn_scene_set_viseme_callback(scene, on_viseme, &n);
  mn_scene_set_log_callback(scene, on_log, &n);
  mn_scene_set_speech_callback(scene, on_speech, &n);
  mn_scene_set_clip_callback(scene, on_clip, &n);
  if (mn_scene_add_character(scene, "robot", argv[1], profile, &robot) != MN_OK) {
    fprintf(stderr, "%s\n", mn_scene_last_error(scene));
    mn_scene_destroy(scene);
    return 2;
  }
  joints = mn_character_joint_count(robot);
  floats = joints * mn_palette_floats_per_joint(MN_PALETTE_MAT4_COLUMN_MAJOR);
  morphs = mn_character_morph_count(robot);
  palette = malloc(floats * sizeof *palette);
  first = malloc(floats * sizeof *first);
  weights = malloc((morphs ? morphs : 1) * sizeof *weights);
  if (!palette || !first || !weights) return 2;

  /* The rig's clips; an idle under the behaviors, as a game's character stands. */
  printf("clips: %zu", mn_character_clip_count(robot));
  for (i = 0; i < mn_character_clip_count(robot); ++i) {
    if (strcmp(mn_character_clip_name(robot, i), "Idle") != 0) continue;
    printf(" (Idle, %.2f s, plays on layer 0)", mn_character_clip_duration(robot, i));
    if (mn_character_play(robot, 0, "Idle", NULL) != MN_OK) {
      fprintf(stderr, "%s\n", mn_scene_last_error(scene));
      return 2;
    }
  }
  printf("\n");

  status = mn_scene_send_bml(scene, "robot", C_EMBEDDING_BML);
  if (status == MN_ERROR_UNSUPPORTED) {
    printf("bml: not in this build\n");
  } else if (status != MN_OK) {
    fprintf(stderr, "%s: %s\n", mn_status_name(status), mn_scene_last_error(scene));
    return 2;
  }
  /* The block's speech is said on the scene's speech thread (a game's frames go on
   * meanwhile); this program compares its frames with the C++ API's, so its block
   * starts on the first frame, as a loading screen would do it. */
  if (mn_scene_wait_for_speech(scene) != MN_OK) return 2;
  for (frame = 0; frame < C_EMBEDDING_FRAMES; ++frame) {
    if (mn_scene_update(scene, 1.0 / 60.0) != MN_OK ||
        mn_character_palette(robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette, floats) != MN_OK ||
        mn_character_morph_weights(robot, weights, morphs) != MN_OK) {
      fprintf(stderr, "frame %d: %s\n", frame, mn_scene_last_error(scene));
      return 2;
    }
    if (frame == 0) memcpy(first, palette, floats * sizeof *palette);
    for (i = 0; i < floats; ++i) {
      const float d = fabsf(palette[i] - first[i]);
      motion = d > motion ? d : motion;
      finite = finite && isfinite(palette[i]);
    }
    for (i = 0; i < morphs; ++i) max_weight = weights[i] > max_weight ? weights[i] : max_weight;
  }
  for (i = 0; i < floats; ++i) checksum += palette[i];
  if (bind_engine_skeleton(scene, robot, palette) != 0) return 2;

  printf("character: %s, %zu joints, %zu morphs\n", mn_character_name(robot), joints, morphs);
  printf("frames: %d, scene time %.4f s\n", frame, mn_scene_time(scene));
  printf("feedback: %d messages (%d predictions, %d block start, %d block end, %d sync points, %d warnings)\n",
         n.feedback, n.predictions, n.block_starts, n.block_ends, n.sync_points, n.warnings);
  printf("visemes: %d (first '%s')\n", n.visemes, n.first_viseme);
  printf("speech: %d lines, %zu samples at %d Hz\n", n.lines, n.samples, n.sample_rate);
  printf("clip starts: %d\n", n.clip_starts);
  printf("palette finite: %s\n", finite ? "yes" : "no");
  printf("palette motion: %.6f (largest change of a palette float from the first frame: the idle and the nod)\n", motion);
  printf("palette checksum: %.9g\n", checksum);
  printf("max morph weight: %.4f\n", max_weight);
  /* Errors come back as a status with a message, never as a crash. */
  status = mn_character_palette(robot, MN_PALETTE_MAT4_COLUMN_MAJOR, 1, palette, floats - 1);
  printf("too small a buffer: %s: %s\n", mn_status_name(status), mn_scene_last_error(scene));

  if (argc > 3) {
    FILE* out = fopen(argv[3], "w");
    if (!out) {
      fprintf(stderr, "%s: cannot open for writing\n", argv[3]);
      return 2;
    }
    for (i = 0; i < floats; ++i) fprintf(out, "%.9g\n", palette[i]);
    fclose(out);
  }
  free(palette);
  free(first);
  free(weights);
  mn_scene_destroy(scene); /* its characters go with it */
  return 0;
}
