/* Marionette C API: the runtime for engines and languages that cannot take C++
 * (C programs, C#, Python ctypes, Rust, Lua FFI). Library: marionette_c, a shared
 * library (CMake target marionette::c). Plain C99; also compiles as C++.
 *
 * Handles. mn_scene is created and destroyed by the caller. mn_character handles
 * belong to their scene: valid until the scene is destroyed; never freed by the
 * caller. Every function checks its handles: a destroyed one (a second
 * mn_scene_destroy, a character of a destroyed scene) is MN_ERROR_INVALID_ARGUMENT,
 * never a use after free, as long as fewer than 256 other handles have been
 * destroyed since (their memory is held back so that no new handle takes a stale
 * one's address sooner). A callback may destroy its own scene: the scene goes when
 * the call that ran the callback returns. Strings returned (names, errors) stay valid until the next call that
 * changes the same handle (for last errors: the next failing call on it).
 *
 * Errors. Every function that can fail returns an mn_status. The message of the
 * last failure is kept per scene (mn_scene_last_error) and names the file or BML
 * block, the place (line:column) and the problem. Failures without a valid scene
 * (a NULL handle, mn_scene_create) keep theirs per thread: mn_scene_last_error(NULL).
 * No C++ exception crosses this interface; NULL handles and bad arguments give
 * MN_ERROR_INVALID_ARGUMENT, never a crash.
 *
 * Threads. A scene, its characters and its callbacks are used from one thread at a
 * time (the caller serializes); different scenes may be used on different threads
 * at once, independently. Callbacks come on the thread that calls mn_scene_update or
 * mn_scene_send_bml, during that call (with mn_scene_set_parallel_for, clip and log
 * callbacks may come on the engine's threads, one at a time); strings and structs passed to a callback are
 * valid only during the call. A callback must not add characters to its own scene;
 * mn_scene_update and mn_scene_send_bml on it from a callback are refused
 * (MN_ERROR_INVALID_ARGUMENT). A callback must not throw (C++) or longjmp out.
 *
 * Per frame: mn_character_palette, mn_character_morph_weights, mn_binding_palette and
 * mn_binding_morph_weights allocate nothing;
 * mn_scene_update is the scene's update (no allocation once warm) plus the BML
 * realizer's progress and the callbacks.
 */
#ifndef MARIONETTE_MARIONETTE_H
#define MARIONETTE_MARIONETTE_H

#include <stddef.h>

#if defined(_WIN32) && defined(MARIONETTE_C_BUILDING)
#define MN_API __declspec(dllexport)
#elif defined(_WIN32)
#define MN_API __declspec(dllimport)
#elif defined(__GNUC__)
#define MN_API __attribute__((visibility("default")))
#else
#define MN_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mn_status {
  MN_OK = 0,
  MN_ERROR_INVALID_ARGUMENT = 1, /* NULL handle or pointer, bad number, buffer too small */
  MN_ERROR_NOT_FOUND = 2,        /* no such character, joint, morph */
  MN_ERROR_IO = 3,               /* a file cannot be read */
  MN_ERROR_LOAD = 4,             /* a file was read but is not valid (asset, profile, scene) */
  MN_ERROR_BML = 5,              /* the BML block failed (malformed, no id, unschedulable) */
  MN_ERROR_UNSUPPORTED = 6,      /* the library was built without the feature (BML) */
  MN_ERROR_OUT_OF_MEMORY = 7,
  MN_ERROR_INTERNAL = 8,         /* an unexpected failure; the message says what */
  /* Not statuses: they make every int a valid mn_status value (an FFI may pass any). */
  MN_STATUS_MIN_ENUM_ = -0x7FFFFFFF - 1,
  MN_STATUS_MAX_ENUM_ = 0x7FFFFFFF
} mn_status;

/* A short name of a status ("MN_OK", "MN_ERROR_IO", ...); never NULL. */
MN_API const char* mn_status_name(mn_status status);

/* The library's version, "MAJOR.MINOR.PATCH" (the loaded library's, which a program
 * compiled against another marionette/version.h may compare with
 * MARIONETTE_VERSION_STRING); never NULL. */
MN_API const char* mn_version(void);
/* Whether this library says <speech> lines with espeak-ng (libmarionette_c_espeak, GPL):
 * 1, or only recorded lines and an engine's own voice (libmarionette_c, MIT): 0. */
MN_API int mn_has_speech_synthesis(void);

typedef struct mn_scene mn_scene;
typedef struct mn_character mn_character;

/* ---- scene ---- */
MN_API mn_status mn_scene_create(mn_scene** out);
MN_API void mn_scene_destroy(mn_scene* scene); /* NULL is a no-op; its characters die with it */
/* The last failure's message on this scene ("" if none); with NULL, this thread's
 * last failure that had no valid scene. Never NULL. */
MN_API const char* mn_scene_last_error(const mn_scene* scene);

/* ---- assets: a character file loaded once, shared by every character made from it ---- */
typedef struct mn_asset mn_asset;

/* Where files are read: an engine's packed archive or virtual file system. The library calls
 * `read_file(user, path, sink)` for every file it reads during a load (the character file, a
 * glTF's buffers and images, an FBX/OBJ's companion files, the profile and the joint map it
 * names, a scene file's assets, clips, recorded lines and BML files); the function writes the
 * file's bytes with mn_file_sink_write (in one or several pieces) and returns nonzero, or
 * returns 0 when there is no such file. `path` is as the library formed it: the one the caller
 * gave, or one resolved against the file that names it, '/'-separated. Called on the loading
 * thread during the load call only; the sink is valid during the call only. */
typedef struct mn_file_sink mn_file_sink;
typedef int (*mn_read_file_fn)(void* user, const char* path, mn_file_sink* sink);
/* Appends bytes to the file being read. MN_ERROR_INVALID_ARGUMENT for a NULL sink or bytes
 * (with size > 0), or a file past 512 MiB (the load then fails naming the file). */
MN_API mn_status mn_file_sink_write(mn_file_sink* sink, const void* bytes, size_t size);

/* How a character file is loaded; mn_import_options_default() gives the defaults in brackets. */
typedef struct mn_import_options {
  size_t struct_size;           /* sizeof(mn_import_options), as the default sets it (the library checks) */
  mn_read_file_fn read_file;    /* NULL: the disk [NULL] */
  void* read_file_user;         /* passed to read_file [NULL] */
  const char* profile_path;     /* a character profile JSON (docs/character-profiles.md), read through
                                   read_file; NULL: the installed profile of a known asset (share/
                                   marionette/profiles, $MARIONETTE_PROFILES), else guessed [NULL] */
  int isolate;                  /* nonzero: Assimp's formats (FBX, BVH, DAE, ...) are first read in a
                                   forked child, so that a crash or hang of its readers becomes an
                                   error; this forks the calling process: for tools, never inside an
                                   engine [0] */
  int allow_files_outside_model_folder; /* nonzero: a glTF may name buffers and images outside its
                                   folder (trusted files only) [0] */
  float extra_scale;            /* multiplies every length after the file's own unit conversion [1] */
} mn_import_options;
MN_API mn_import_options mn_import_options_default(void);

/* Loads a character file (glTF, GLB, VRM; FBX, BVH, DAE, ... through Assimp) once: its skeleton,
 * clips, morph names and profile, without meshes. `options` NULL: the defaults. Any thread; the
 * asset is read-only once loaded, so characters of scenes on different threads may share it.
 * Failures without a scene keep their message per thread: mn_scene_last_error(NULL). */
MN_API mn_status mn_asset_load_file(const char* path, const mn_import_options* options, mn_asset** out);
/* The same from bytes in memory (copied; they need not outlive the call). `name_hint` is the
 * file's name: its extension chooses the format, messages name it, and the files it refers to
 * are resolved against its folder and read through options->read_file (else the disk). */
MN_API mn_status mn_asset_load_memory(const void* bytes, size_t size, const char* name_hint,
                                      const mn_import_options* options, mn_asset** out);
/* Drops the caller's reference. The asset lives while any character made from it does; the
 * handle is invalid afterwards (a later call with it is MN_ERROR_INVALID_ARGUMENT). NULL: no-op. */
MN_API void mn_asset_release(mn_asset* asset);
MN_API const char* mn_asset_name(const mn_asset* asset); /* the file or name_hint; "" for NULL */
MN_API size_t mn_asset_joint_count(const mn_asset* asset);
MN_API size_t mn_asset_clip_count(const mn_asset* asset);
/* What the load warned about (the file's, the profile's), one line each, and which installed
 * profile it took; "" when nothing. Valid until the asset is released. Never NULL. */
MN_API const char* mn_asset_report(const mn_asset* asset);
/* Adds a character made from a loaded asset as `name` (unique): it shares the asset's skeleton,
 * clips and profile (about 5 KiB of its own for a 50-joint skeleton, instead of a copy of the
 * file). The asset handle may be released at once. `out` may be NULL. */
MN_API mn_status mn_scene_add_character_from_asset(mn_scene* scene, const char* name, mn_asset* asset,
                                                   mn_character** out);

/* Adds the characters of a scene JSON file (marionette/scene/scene_file.hpp). Its
 * "bml" list is sent by mn_scene_update as the clock reaches each file's time. On
 * an error nothing is added (MN_ERROR_IO, MN_ERROR_LOAD). */
MN_API mn_status mn_scene_load_file(mn_scene* scene, const char* path);
/* Loads a character file (glTF, VRM, FBX, ...) and adds it as `name` (unique).
 * `profile_path` is a character profile JSON (docs/character-profiles.md) or NULL for
 * the installed profile of a known asset, else the guessed one. A file (and profile)
 * this scene has loaded already for a character that still exists is not read again:
 * the characters share it, as with mn_asset. `out` may be NULL. */
MN_API mn_status mn_scene_add_character(mn_scene* scene, const char* name, const char* asset_path,
                                        const char* profile_path, mn_character** out);
/* MN_ERROR_NOT_FOUND when the scene has no character of that name. */
MN_API mn_status mn_scene_find_character(mn_scene* scene, const char* name, mn_character** out);
MN_API size_t mn_scene_character_count(const mn_scene* scene);
MN_API mn_character* mn_scene_character_at(mn_scene* scene, size_t index); /* NULL past the end */

/* Sends one BML 1.0 block, for `character` (NULL: the block's characterId, else the
 * first character). Non-fatal problems arrive as MN_FEEDBACK_WARNING feedback; a
 * block that fails as a whole returns MN_ERROR_BML with a message naming the block,
 * line:column and problem. MN_ERROR_UNSUPPORTED when built without BML. */
MN_API mn_status mn_scene_send_bml(mn_scene* scene, const char* character, const char* bml_text);
/* How a block's <speech> is said. BACKGROUND (the default): on the scene's speech
 * thread; mn_scene_send_bml returns at once and the block waits (with every block sent
 * after it) until its lines are said, then starts at that update: no frame waits for the
 * synthesizer. Problems of a waiting block arrive as MN_FEEDBACK_WARNING feedback.
 * INLINE: mn_scene_send_bml says the lines itself (up to ~0.1 s for a long line) and
 * the block starts at once: deterministic, for offline tools and tests. */
typedef enum mn_speech_synthesis {
  MN_SPEECH_BACKGROUND = 0,
  MN_SPEECH_INLINE = 1,
  MN_SPEECH_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not modes (unknown ones are errors) */
  MN_SPEECH_MAX_ENUM_ = 0x7FFFFFFF
} mn_speech_synthesis;
MN_API mn_status mn_scene_set_speech_synthesis(mn_scene* scene, mn_speech_synthesis mode);
/* Waits until the speech of the blocks that wait for it is said and starts them now. */
MN_API mn_status mn_scene_wait_for_speech(mn_scene* scene);
/* Adds a recorded voice line: a <speech> whose text matches `text` (ignoring case, punctuation
 * and spacing) is said with this recording and its phoneme alignment, before any synthesizer
 * (docs/speech.md). `audio_path` is a WAV (NULL or "": a line without audio, lips only);
 * `alignment_path` the phones (HTK .lab, CMU ARCTIC .phones, or start,end,phoneme CSV). Both are
 * read now through `read_file` (as mn_import_options' read_file; NULL: the disk). A file that
 * cannot be read or is not valid is MN_ERROR_LOAD, with a message naming it. */
MN_API mn_status mn_scene_add_speech_line(mn_scene* scene, const char* text, const char* audio_path,
                                          const char* alignment_path, mn_read_file_fn read_file, void* read_file_user);
/* Advances the clock by dt seconds (finite, >= 0, at most 3600: MN_ERROR_INVALID_ARGUMENT
 * otherwise, and the clock stays) and updates every character and the BML realizer;
 * callbacks come from here. */
MN_API mn_status mn_scene_update(mn_scene* scene, double dt);
MN_API double mn_scene_time(const mn_scene* scene); /* seconds; 0 for NULL */

/* ---- engine hooks: the engine's threads and memory (docs/bridge.md) ---- */
/* A parallel-for on the engine's job system, for a scene's characters. mn_scene_update
 * splits the characters into chunks of 16 consecutive ones and calls fn(user, task,
 * context, chunk_count) once, on its own thread. fn must call task(context, i) exactly
 * once for every i in [0, chunk_count): in any order, on any threads (the calling one
 * included), at once or one after another; and return only when every task has returned.
 * Each chunk has scratch of its own and runs under the calling thread's floating-point
 * environment, so the palettes are bit-identical to an update on one thread. A task never
 * throws, allocates nothing, and costs about 16 character updates. Callbacks made meanwhile
 * (clip, log) are serialized and may come on the engine's threads; fn itself must not call
 * the library. Scenes of at most 16 characters update without calling fn. fn NULL: the
 * library's own threads again (one, the caller's, through this API). Not from a callback. */
typedef void (*mn_parallel_task_fn)(void* context, int chunk);
typedef void (*mn_parallel_for_fn)(void* user, mn_parallel_task_fn task, void* context, int chunk_count);
MN_API mn_status mn_scene_set_parallel_for(mn_scene* scene, mn_parallel_for_fn fn, void* user);

/* The engine's heap for the runtime: scenes, characters and their state, transform buffers,
 * pose, layer and blend scratch, bindings, every handle (docs/bridge.md lists what it does not
 * reach: asset import, rigs and clips, names, the BML realizer, third-party libraries).
 * alloc_fn returns `size` bytes aligned to `alignment` (a power of two, at least 16), or NULL
 * when out of memory (the call that allocates then fails with MN_ERROR_OUT_OF_MEMORY);
 * free_fn gets back every block with the size and alignment it was asked for. Both may be
 * called from any thread that calls the library, at once. Call it before the first
 * mn_scene_create, on one thread, while no other thread uses the library: it is refused
 * (MN_ERROR_INVALID_ARGUMENT) while any handle is alive, and the memory the library holds back
 * of destroyed handles is freed then (to the allocator that gave it). NULL, NULL restores the
 * default (operator new). The failure's message: mn_scene_last_error(NULL). */
typedef void* (*mn_alloc_fn)(void* user, size_t size, size_t alignment);
typedef void (*mn_free_fn)(void* user, void* block, size_t size, size_t alignment);
MN_API mn_status mn_set_allocator(mn_alloc_fn alloc_fn, mn_free_fn free_fn, void* user);

/* ---- characters ---- */
MN_API const char* mn_character_name(const mn_character* character); /* "" for NULL */
MN_API size_t mn_character_joint_count(const mn_character* character);
MN_API const char* mn_character_joint_name(const mn_character* character, size_t joint); /* NULL if out of range */
/* Index of a joint by exact name, or -1. */
MN_API int mn_character_find_joint(const mn_character* character, const char* name);
/* The joint hierarchy: the parent of `joint` (a parent comes before its children), -1 for a
 * root, -2 for a joint out of range or a NULL character. */
MN_API int mn_character_joint_parent(const mn_character* character, size_t joint);
/* The rest (bind) pose, local to each joint's parent: 10 floats per joint, translation x y z,
 * rotation quaternion x y z w, scale x y z; out_floats >= 10 * mn_character_joint_count.
 * Nothing is written on error. */
MN_API mn_status mn_character_rest_pose(const mn_character* character, float* out, size_t out_floats);
/* The space the roots live in (16 floats, column-major): the file's nodes above the skeleton,
 * e.g. a Z-up to Y-up turn or a unit scale. A joint's model matrix (the palette without
 * inverse bind) is this times its parents' rest transforms times its own. */
MN_API mn_status mn_character_root_transform(const mn_character* character, float* out16);
MN_API mn_status mn_character_set_position(mn_character* character, float x, float y, float z); /* metres */
MN_API mn_status mn_character_set_heading(mn_character* character, float radians);              /* about +Y */
/* The character's world-from-model matrix as of the last update (16 floats, column-major).
 * The palette is in model space: an engine places the skinned mesh with this. */
MN_API mn_status mn_character_world_matrix(const mn_character* character, float* out16);
/* How far the last mn_scene_update moved and turned the character (clip root motion and
 * locomotion; not mn_character_set_position/_heading): out4 = world x y z in metres, then
 * the turn about +Y in radians, in [-pi, pi]. For an engine that moves its own object. */
MN_API mn_status mn_character_root_motion_delta(const mn_character* character, float* out4);

typedef enum mn_palette_layout {
  MN_PALETTE_MAT4_COLUMN_MAJOR = 0, /* 16 floats per joint, column after column (OpenGL) */
  MN_PALETTE_MAT4_ROW_MAJOR = 1,    /* 16 floats per joint, row after row (Direct3D row_major) */
  MN_PALETTE_MAT3X4_ROW_MAJOR = 2,  /* 12 floats per joint: rows 0..2 of the affine matrix */
  /* Not layouts: every int is a valid value to pass (unknown ones are errors). */
  MN_PALETTE_MIN_ENUM_ = -0x7FFFFFFF - 1,
  MN_PALETTE_MAX_ENUM_ = 0x7FFFFFFF
} mn_palette_layout;

MN_API size_t mn_palette_floats_per_joint(mn_palette_layout layout); /* 16, 16, 12; 0 if unknown */
/* Writes every joint's matrix, in the skeleton's order, into `out` (at least
 * joint_count * floats_per_joint floats): skinning matrices (model * inverse bind, made
 * as they are copied: a character keeps only its model matrices) when `inverse_bind` is
 * nonzero, else model-space joint matrices. Nothing is
 * written on error (MN_ERROR_INVALID_ARGUMENT for a NULL or too small buffer). */
MN_API mn_status mn_character_palette(const mn_character* character, mn_palette_layout layout, int inverse_bind,
                                      float* out, size_t out_floats);

MN_API size_t mn_character_morph_count(const mn_character* character);
MN_API const char* mn_character_morph_name(const mn_character* character, size_t morph); /* NULL if out of range */
/* Writes the morph weights in mn_character_morph_name order (out_floats >= morph count). */
MN_API mn_status mn_character_morph_weights(const mn_character* character, float* out, size_t out_floats);

/* ---- bindings: the palette and morphs in the engine's own bone and morph order ---- */
/* The engine's skeleton as the engine has it: bone names in palette-slot order, each bone's
 * parent slot (-1 for a root; any order, a parent may come after its child), and the names
 * of the engine's morph slots (blend shapes) in order. */
typedef struct mn_engine_skeleton {
  const char* const* bone_names;  /* bone_count names, none NULL */
  const int* parents;             /* bone_count parent slots; may be NULL when binding by name alone */
  size_t bone_count;
  const char* const* morph_names; /* morph_count names, or NULL when morph_count is 0 */
  size_t morph_count;
} mn_engine_skeleton;

/* Where names differ; mn_binding_options_default() gives the defaults in brackets (by exact
 * name alone). With through_joint_maps, an engine bone whose name the character lacks gets the
 * character joint of the same canonical joint (hips, spine[1], leftUpperArm, leftIndex[2], ...):
 * the engine's joint map names each bone's canonical joint, the character's map the joint for it
 * (docs/joint-maps.md; the shipped maps are in share/marionette/jointmaps). Chains match joint k
 * to joint k. An exact name wins over the maps. A map path without through_joint_maps is an error. */
typedef struct mn_binding_options {
  size_t struct_size;              /* sizeof(mn_binding_options), as the default sets it (the library checks) */
  int through_joint_maps;          /* nonzero: bind through joint maps where names differ [0] */
  const char* engine_joint_map;    /* the engine skeleton's map (JSON; its names are engine bone names);
                                      NULL: guessed from the bone names and parents [NULL] */
  const char* character_joint_map; /* the character's map (JSON); NULL: the character's own VRM
                                      humanoid map, else the shipped map that fits it
                                      ($MARIONETTE_JOINTMAPS, share/marionette/jointmaps beside the
                                      library), else guessed from names and topology [NULL] */
} mn_binding_options;
MN_API mn_binding_options mn_binding_options_default(void);

typedef struct mn_binding mn_binding;
/* Binds a character to an engine skeleton, once (allocates, may read the map files).
 * `options` NULL: the defaults. Engine bones without a joint are written as identity every
 * frame; engine morph slots without a morph are left untouched (the engine may drive them);
 * mn_binding_report names them. The binding is the caller's (mn_binding_destroy); it is
 * refused (MN_ERROR_INVALID_ARGUMENT) once its character is removed or its scene destroyed.
 * MN_ERROR_IO for a map file that cannot be read, MN_ERROR_LOAD for one that is not a valid
 * map; the message names the file, line:column and the problem. */
MN_API mn_status mn_binding_create(mn_character* character, const mn_engine_skeleton* engine,
                                   const mn_binding_options* options, mn_binding** out);
MN_API void mn_binding_destroy(mn_binding* binding); /* NULL is a no-op */
/* How the names were resolved, one line per problem (an engine bone without a joint, a joint
 * that drives no bone, a morph slot without a morph, a morph no slot takes) and the joint
 * maps' warnings; "" when everything was bound. Never NULL. */
MN_API const char* mn_binding_report(const mn_binding* binding);
MN_API size_t mn_binding_bone_count(const mn_binding* binding);
MN_API size_t mn_binding_morph_slot_count(const mn_binding* binding);
/* The character joint (mn_character_joint_name) that engine bone `slot` receives, or the
 * morph (mn_character_morph_name) that engine morph slot `slot` receives; -1 when none or
 * out of range. */
MN_API int mn_binding_joint_for_bone(const mn_binding* binding, size_t slot);
MN_API int mn_binding_morph_for_slot(const mn_binding* binding, size_t slot);
/* Per frame, no allocation: the palette in the engine's bone order (bone_count *
 * mn_palette_floats_per_joint(layout) floats; as mn_character_palette otherwise), and the
 * morph weights into the engine's morph slots (out_floats >= morph slot count; the slots
 * without a morph are not written). Nothing is written on error. */
MN_API mn_status mn_binding_palette(const mn_binding* binding, mn_palette_layout layout, int inverse_bind, float* out,
                                    size_t out_floats);
MN_API mn_status mn_binding_morph_weights(const mn_binding* binding, float* out, size_t out_floats);

/* ---- clips ---- */
/* The clips of the character's rig, by index (0..count-1): name (NULL if out of range)
 * and length in seconds (0 if out of range). */
MN_API size_t mn_character_clip_count(const mn_character* character);
MN_API const char* mn_character_clip_name(const mn_character* character, size_t clip);
MN_API double mn_character_clip_duration(const mn_character* character, size_t clip);

/* How a clip plays on a layer; mn_play_options_default() gives the defaults in brackets. */
typedef struct mn_play_options {
  size_t struct_size; /* sizeof(mn_play_options), as the default sets it (the library checks) */
  float weight;      /* target weight, >= 0 [1] */
  float speed;       /* playback rate; 0 holds, negative plays backwards [1] */
  int loop;          /* nonzero loops; 0 holds the last frame [1] */
  double start_time; /* clip-local seconds to start at [0] */
  float fade_in;     /* seconds to reach the weight; 0 at once [0] */
  int additive;      /* nonzero: a delta over the layers below, against the clip's first frame [0] */
  int root_motion;   /* nonzero: the clip's root motion moves the character [0] */
} mn_play_options;
MN_API mn_play_options mn_play_options_default(void);
/* Plays a clip of the character's rig on a layer (0..7; a later layer blends over the
 * earlier ones), replacing what played there; `options` NULL: the defaults.
 * MN_ERROR_NOT_FOUND names the clip and lists the rig's; MN_ERROR_INVALID_ARGUMENT for a
 * layer out of range or a value that is not finite. The clip callback hears it start. */
MN_API mn_status mn_character_play(mn_character* character, int layer, const char* clip, const mn_play_options* options);
/* Stops a layer's clip, fading it out over `fade_out` seconds (0: at once); a layer with
 * nothing playing is not an error. */
MN_API mn_status mn_character_stop(mn_character* character, int layer, float fade_out);

/* ---- blend spaces: clips blended by a parameter point (docs/blend-spaces.md) ---- */
/* The blend spaces of the character's rig (its profile's "blendSpaces"), by index
 * (0..count-1): name (NULL if out of range). */
MN_API size_t mn_character_blend_space_count(const mn_character* character);
MN_API const char* mn_character_blend_space_name(const mn_character* character, size_t blend_space);
/* Plays a blend space of the character's rig by name on a layer (0..7), replacing what played
 * there, at the parameter point (0, 0) until mn_character_set_blend_parameter moves it (clamped
 * into the space). `options` as for a clip (NULL: the defaults), except: start_time is the start
 * phase in cycles, speed scales the phase's rate, loop 0 holds the cycle's end, additive is
 * refused (MN_ERROR_INVALID_ARGUMENT); root_motion moves the character by the clips' root motion,
 * weighted. MN_ERROR_NOT_FOUND names the space and lists the rig's. Allocates (what the frame
 * needs); the clip callback hears it start, with the space's name. */
MN_API mn_status mn_character_play_blend(mn_character* character, int layer, const char* blend_space,
                                         const mn_play_options* options);
/* Moves the parameter point of the blend space playing on `layer` (y is ignored by a 1D space);
 * the weights change from the next update, at once (smooth the parameter for gradual changes).
 * No allocation: fine every frame. MN_ERROR_INVALID_ARGUMENT for a layer out of range or that
 * plays no blend space, or x or y not finite. */
MN_API mn_status mn_character_set_blend_parameter(mn_character* character, int layer, float x, float y);

/* Removes a character from its scene; its handle is invalid afterwards (a later call with
 * it is MN_ERROR_INVALID_ARGUMENT, never a crash). Not from inside a callback. */
MN_API mn_status mn_scene_remove_character(mn_scene* scene, mn_character* character);
/* Interrupts a BML block by its id (BML's interrupt: the block and its behaviors end now,
 * blending out; a block still waiting for its speech is dropped). MN_ERROR_NOT_FOUND when
 * no block has that id; MN_ERROR_UNSUPPORTED without BML. */
MN_API mn_status mn_scene_interrupt_block(mn_scene* scene, const char* block_id);

/* Named places that gaze, pointing and locomotion targets may name, as they name characters
 * (SmartBody's pawns, props; "camera" for the viewer: move it with the engine's camera every
 * frame). Setting an existing name moves it. MN_ERROR_INVALID_ARGUMENT for a NULL or empty
 * name or a position that is not finite; removing an unknown name is MN_ERROR_NOT_FOUND. */
MN_API mn_status mn_scene_set_object(mn_scene* scene, const char* name, float x, float y, float z);
MN_API mn_status mn_scene_remove_object(mn_scene* scene, const char* name);

/* How BML is read: "auto" (the default: SmartBody's forms, such as blocks without ids, when a
 * block uses them), "bml" (BML 1.0 strictly) or "smartbody". For one character (its own comes
 * first), or for the scene's blocks when `character` is NULL. A scene file's "bmlDialect" sets
 * the same. MN_ERROR_INVALID_ARGUMENT for another name; MN_ERROR_UNSUPPORTED without BML. */
MN_API mn_status mn_scene_set_bml_dialect(mn_scene* scene, const char* character, const char* dialect);

/* ---- callbacks (one of each kind per scene; NULL function removes it) ---- */
typedef enum mn_feedback_kind {
  MN_FEEDBACK_PREDICTION = 0,     /* right after scheduling: when each sync point will be */
  MN_FEEDBACK_BLOCK_PROGRESS = 1, /* a block's "start" or "end" */
  MN_FEEDBACK_SYNC_POINT = 2,     /* a behavior's sync point was passed */
  MN_FEEDBACK_WARNING = 3,        /* a problem with a block; `message` says what */
  MN_FEEDBACK_EVENT = 4,          /* an <event message> reached its stroke; `message` is the script's */
  /* Not kinds: they fix the enum's width at 32 bits, whatever the compiler (ABI). */
  MN_FEEDBACK_MIN_ENUM_ = -0x7FFFFFFF - 1,
  MN_FEEDBACK_MAX_ENUM_ = 0x7FFFFFFF
} mn_feedback_kind;

typedef struct mn_feedback {
  mn_feedback_kind kind;
  const char* character;  /* never NULL; "" when not known */
  const char* block;
  const char* behavior;   /* "" for block progress */
  const char* sync_point; /* "start"/"end" for block progress; the sync point's name otherwise */
  const char* message;    /* warnings: "TYPE: text"; events: the script's message; "" otherwise */
  double block_time;      /* seconds from the block's start */
  double scene_time;      /* on the scene clock */
} mn_feedback;

typedef struct mn_viseme {
  const char* character;
  const char* viseme; /* OVR viseme name: "sil", "PP", "FF", "aa", ... */
  float weight;       /* the weight its channel reaches in that phoneme */
  double time;        /* the phoneme's start on the scene clock */
} mn_viseme;

/* A line a character starts to say: play `samples` (or the WAV `audio_file`, written when
 * the scene has an audio directory; "" otherwise) from `start_time` on the scene clock so
 * that the lips stay in sync. Comes when the speech is realized, before its start. */
typedef struct mn_speech {
  const char* character;
  const char* behavior;       /* "block:behavior" for BML */
  const short* samples;       /* mono 16-bit PCM, valid during the call; NULL when the line has no audio */
  size_t sample_count;
  int sample_rate;
  const char* audio_file;
  double start_time;
  double duration;            /* seconds */
} mn_speech;

typedef enum mn_clip_event_kind {
  MN_CLIP_STARTED = 0, /* a layer began playing a clip */
  MN_CLIP_STOPPED = 1, /* a layer's clip was stopped, or faded out to nothing */
  MN_CLIP_EVENT_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not kinds: 32 bits wide (ABI) */
  MN_CLIP_EVENT_MAX_ENUM_ = 0x7FFFFFFF
} mn_clip_event_kind;
typedef struct mn_clip_event {
  mn_clip_event_kind kind;
  const char* character;
  const char* clip;
  double scene_time;
} mn_clip_event;

typedef enum mn_log_level {
  MN_LOG_INFO = 0,
  MN_LOG_WARNING = 1,
  MN_LOG_ERROR = 2,
  MN_LOG_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not levels: 32 bits wide (ABI) */
  MN_LOG_MAX_ENUM_ = 0x7FFFFFFF
} mn_log_level;

typedef void (*mn_feedback_fn)(void* user, const mn_feedback* feedback);
typedef void (*mn_viseme_fn)(void* user, const mn_viseme* viseme);
typedef void (*mn_log_fn)(void* user, mn_log_level level, const char* message);
typedef void (*mn_speech_fn)(void* user, const mn_speech* speech);
typedef void (*mn_clip_fn)(void* user, const mn_clip_event* event);

MN_API mn_status mn_scene_set_feedback_callback(mn_scene* scene, mn_feedback_fn fn, void* user);
MN_API mn_status mn_scene_set_viseme_callback(mn_scene* scene, mn_viseme_fn fn, void* user);
MN_API mn_status mn_scene_set_log_callback(mn_scene* scene, mn_log_fn fn, void* user);
MN_API mn_status mn_scene_set_speech_callback(mn_scene* scene, mn_speech_fn fn, void* user);
MN_API mn_status mn_scene_set_clip_callback(mn_scene* scene, mn_clip_fn fn, void* user);

/* Animation events: a clip layer's playhead crossed a foot contact's start or end, or an
 * authored marker (glTF animation extras "events", a profile's "events"), once per crossing
 * and in the order crossed, at the end of the character's update (docs/animation-events.md).
 * Strings are valid during the call only; threads as the other callbacks. */
typedef enum mn_animation_event_kind {
  MN_ANIMATION_EVENT_FOOT_DOWN = 0, /* a foot touched the ground (`foot` says which) */
  MN_ANIMATION_EVENT_FOOT_UP = 1,   /* a foot lifted off */
  MN_ANIMATION_EVENT_MARKER = 2,    /* an authored marker; `name` is its name */
  MN_ANIMATION_EVENT_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not kinds: 32 bits wide (ABI) */
  MN_ANIMATION_EVENT_MAX_ENUM_ = 0x7FFFFFFF
} mn_animation_event_kind;
typedef enum mn_foot_side {
  MN_FOOT_NONE = 0, /* markers */
  MN_FOOT_LEFT = 1, /* the character's own left */
  MN_FOOT_RIGHT = 2,
  MN_FOOT_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not sides: 32 bits wide (ABI) */
  MN_FOOT_MAX_ENUM_ = 0x7FFFFFFF
} mn_foot_side;
typedef struct mn_animation_event {
  mn_animation_event_kind kind;
  mn_foot_side foot;
  const char* character;
  const char* name;   /* the marker's; feet: "left_foot_down", "left_foot_up", "right_foot_down", "right_foot_up" */
  const char* clip;
  int layer;          /* the layer that plays the clip */
  float weight;       /* the layer's weight this frame */
  double clip_time;   /* the event's time in the clip, seconds */
  double scene_time;  /* when it was crossed, on the scene clock (within the frame) */
} mn_animation_event;
typedef void (*mn_animation_event_fn)(void* user, const mn_animation_event* event);
MN_API mn_status mn_scene_set_event_callback(mn_scene* scene, mn_animation_event_fn fn, void* user);

/* Sounds a behavior plays (AsapRealizer's <bmlt:audiofile fileName>; docs/bridge.md). PLAY
 * comes once, when the block is realized, before its start: play `samples` from `scene_time`.
 * STOP comes at most once, when the sound must end before its own end: its block was
 * interrupted or replaced, or the BML gave an earlier end (then `scene_time` is that end).
 * Samples are decoded floats, interleaved (frame after frame, `channels` samples each);
 * PCM files give [-1, 1). Valid during the call only; threads as the other callbacks. */
typedef enum mn_audio_event_kind {
  MN_AUDIO_PLAY = 0,
  MN_AUDIO_STOP = 1,
  MN_AUDIO_EVENT_MIN_ENUM_ = -0x7FFFFFFF - 1, /* not kinds: 32 bits wide (ABI) */
  MN_AUDIO_EVENT_MAX_ENUM_ = 0x7FFFFFFF
} mn_audio_event_kind;
typedef struct mn_audio {
  mn_audio_event_kind kind;
  const char* character;
  const char* behavior;   /* "block:behavior" for BML */
  const float* samples;   /* PLAY: frame_count * channels samples; STOP: NULL */
  size_t frame_count;     /* STOP: 0 */
  int channels;           /* STOP: 0 */
  int sample_rate;        /* frames per second; STOP: 0 */
  const char* file;       /* PLAY: the WAV as it was read (resolved); STOP: "" */
  double scene_time;      /* PLAY: when to start; STOP: when to stop */
  double duration;        /* PLAY: the clip's seconds; STOP: 0 */
} mn_audio;
typedef void (*mn_audio_fn)(void* user, const mn_audio* audio);
MN_API mn_status mn_scene_set_audio_callback(mn_scene* scene, mn_audio_fn fn, void* user);
/* Where <bmlt:audiofile fileName> is read, when its block is realized: relative names in
 * `directory` (NULL or "": the working directory; a scene file's BML files read theirs beside
 * themselves), through `read_file` (as mn_import_options' read_file; NULL: the disk). A file
 * that cannot be read or is not a WAV removes its behavior with MN_FEEDBACK_WARNING feedback
 * naming the file. MN_ERROR_UNSUPPORTED when built without BML. */
MN_API mn_status mn_scene_set_audio_files(mn_scene* scene, const char* directory, mn_read_file_fn read_file,
                                          void* read_file_user);

#ifdef __cplusplus
}
#endif

#endif /* MARIONETTE_MARIONETTE_H */
