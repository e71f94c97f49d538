// Marionette for the web: the C API (bridge/c_api/include/marionette/marionette.h) compiled to
// WebAssembly, as JavaScript classes (docs/web.md). Each class owns one C handle; dispose()
// frees it. Failures throw MarionetteError with the library's message (file or block,
// line:column, problem). Palettes and morph weights are Float32Array views on the module's
// memory, written in place by each call: nothing is copied per frame on the JS side.
import createMarionetteWasm from './marionette_wasm.mjs';

const STATUS = ['MN_OK', 'MN_ERROR_INVALID_ARGUMENT', 'MN_ERROR_NOT_FOUND', 'MN_ERROR_IO', 'MN_ERROR_LOAD',
  'MN_ERROR_BML', 'MN_ERROR_UNSUPPORTED', 'MN_ERROR_OUT_OF_MEMORY', 'MN_ERROR_INTERNAL'];
const FEEDBACK_KINDS = ['prediction', 'blockProgress', 'syncPoint', 'warning', 'event'];
const LOG_LEVELS = ['info', 'warning', 'error'];
const EVENT_KINDS = ['footDown', 'footUp', 'marker'];
const FOOT_SIDES = ['none', 'left', 'right'];
export const PaletteLayout = Object.freeze({ MAT4_COLUMN_MAJOR: 0, MAT4_ROW_MAJOR: 1, MAT3X4_ROW_MAJOR: 2 });

/** A failed call: `message` is the library's, `status` the C status name ("MN_ERROR_BML", ...). */
export class MarionetteError extends Error {
  constructor(message, status) {
    super(message);
    this.name = 'MarionetteError';
    this.status = status;
  }
}

// Struct layouts on wasm32 (pointers and size_t are 4 bytes, doubles 8-aligned); checked
// against the C header by static_asserts in bridge/web/src/web_module.cpp.
const LAYOUT = {
  importOptions: { size: 28, readFile: 4, readFileUser: 8, profilePath: 12 },
  bindingOptions: { size: 16, throughJointMaps: 4, engineJointMap: 8, characterJointMap: 12 },
  playOptions: { size: 40, weight: 4, speed: 8, loop: 12, startTime: 16, fadeIn: 24, additive: 28, rootMotion: 32 },
  engineSkeleton: { size: 20, boneNames: 0, parents: 4, boneCount: 8, morphNames: 12, morphCount: 16 },
};

/**
 * Loads the WebAssembly module. `options` go to emscripten's module factory (e.g. `wasmBinary`
 * when the page fetches the .wasm itself, or `locateFile`).
 */
export async function loadMarionette(options = {}) {
  const settings = { ...options };
  // Under Node.js (tests, tools) the module is built for browsers: read the .wasm here.
  if (!settings.wasmBinary && typeof process === 'object' && process.versions && process.versions.node) {
    const { readFile } = await import('node:fs/promises');
    settings.wasmBinary = await readFile(new URL('./marionette_wasm.wasm', import.meta.url));
  }
  const wasm = await createMarionetteWasm(settings);
  return new Marionette(wasm);
}

class Marionette {
  constructor(wasm) {
    this.wasm = wasm;
    this.version = wasm.UTF8ToString(wasm._mn_version());
  }

  /** A new scene (characters, BML, callbacks). Speech is said inline: the web build has no threads. */
  createScene() {
    return new Scene(this);
  }

  /** Loads a character file (glTF, GLB, VRM) from bytes once; characters of any scene share it. */
  loadAsset(bytes, name, options = {}) {
    return new Asset(this, bytes, name, options);
  }

  // ---- memory helpers ----
  // malloc, or a MarionetteError: with memory growth on, a failed malloc returns 0, and
  // writing through 0 would overwrite the module's own data.
  malloc(n) {
    const ptr = this.wasm._malloc(Math.max(1, n));
    if (!ptr) throw new MarionetteError(`out of memory (${n} bytes)`, 'MN_ERROR_OUT_OF_MEMORY');
    return ptr;
  }
  string(ptr) { return ptr ? this.wasm.UTF8ToString(ptr) : ''; }
  allocString(text) {
    const n = this.wasm.lengthBytesUTF8(text) + 1;
    const ptr = this.malloc(n);
    this.wasm.stringToUTF8(text, ptr, n);
    return ptr;
  }
  allocBytes(bytes) {
    const u8 = bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes);
    const ptr = this.malloc(u8.length);
    this.wasm.HEAPU8.set(u8, ptr);  // HEAPU8 read after the malloc: it may have grown the memory
    return { ptr, size: u8.length };
  }
  // Runs fn(alloc) and frees what alloc(...) allocated, whatever happens. Every allocation
  // may grow the memory and detach the heap views: allocate first, then write through
  // wasm.HEAP* read afresh (never `wasm.HEAPU32[i] = str(x)`, which writes the old view).
  withTemp(fn) {
    const owned = [];
    const alloc = (n) => { const p = this.malloc(n); owned.push(p); return p; };
    const str = (s) => { if (s === undefined || s === null) return 0; const p = this.allocString(String(s)); owned.push(p); return p; };
    const bytes = (b) => { const r = this.allocBytes(b); owned.push(r.ptr); return r; };
    try {
      return fn({ alloc, str, bytes });
    } finally {
      for (const p of owned) this.wasm._free(p);
    }
  }
  // Throws for a failed status: the message the library recorded (on the live scene, else on
  // the thread), after any exception a JS callback threw during the call.
  check(status, owner, what) {
    if (owner && owner.rethrowCallbackError) owner.rethrowCallbackError();
    if (status === 0) return;
    const scene = owner && owner.handle ? owner.handle : 0;
    const message = this.string(this.wasm._mn_scene_last_error(scene)) || `${what} failed`;
    throw new MarionetteError(message, STATUS[status] || `status ${status}`);
  }
  alive(handle, what) {
    if (!handle) throw new MarionetteError(`${what}: it was disposed or removed`, 'MN_ERROR_INVALID_ARGUMENT');
  }
  // A read_file function (mn_read_file_fn) that serves `files` (a Map or object of name -> bytes).
  // An exception inside it must not unwind the library: it is kept in holder.callbackError
  // (thrown again by the call's wrapper) and the file counts as missing.
  fileReader(files, holder) {
    const wasm = this.wasm;
    const lookup = (path) => {
      if (!files) return undefined;
      const get = (k) => (files instanceof Map ? files.get(k) : files[k]);
      let bytes = get(path);
      if (bytes === undefined) bytes = get(path.replace(/^\.\//, ''));
      if (bytes === undefined) bytes = get(path.split('/').pop());
      return bytes;
    };
    return wasm.addFunction((user, pathPtr, sink) => {
      let ptr = 0;
      try {
        const bytes = lookup(wasm.UTF8ToString(pathPtr));
        if (bytes === undefined) return 0;
        const data = typeof bytes === 'string' ? new TextEncoder().encode(bytes) : new Uint8Array(bytes);
        ptr = this.malloc(data.length);
        wasm.HEAPU8.set(data, ptr);
        return wasm._mn_file_sink_write(sink, ptr, data.length) === 0 ? 1 : 0;
      } catch (e) {
        if (holder && holder.callbackError === undefined) holder.callbackError = e;
        return 0;
      } finally {
        if (ptr) wasm._free(ptr);
      }
    }, 'iiii');
  }
}

// One C call on `object` (a Scene, Character or Binding): refused when its handle is gone
// (disposed or removed), then checked, errors read from `owner` (the scene). `status` is
// the call's result; the per-frame methods pass it directly (no closure to allocate).
function checked(object, owner, what, status) {
  object.mn.check(status, owner, what);
  return status;
}

// Holds an exception from a JS function the library called (a file reader during a load,
// a callback during an update); the scene is one too.
class ErrorHolder {
  rethrowCallbackError() {
    if (this.callbackError === undefined) return;
    const e = this.callbackError;
    this.callbackError = undefined;
    throw e;
  }
}

/** A loaded character file, shared by the characters made from it. */
class Asset {
  constructor(mn, bytes, name, { files, profile } = {}) {
    this.mn = mn;
    const wasm = mn.wasm;
    const errors = new ErrorHolder();
    const reader = files || profile ? mn.fileReader(files, errors) : 0;
    try {
      this.handle = mn.withTemp(({ alloc, str, bytes: put }) => {
        const o = LAYOUT.importOptions;
        const opts = alloc(o.size);
        const profilePtr = str(profile);
        const data = put(bytes);
        const out = alloc(4);
        wasm._mn_import_options_default(opts);  // returned through a hidden result pointer
        wasm.HEAPU32[(opts + o.readFile) >> 2] = reader;
        wasm.HEAPU32[(opts + o.profilePath) >> 2] = profilePtr;
        const status = wasm._mn_asset_load_memory(data.ptr, data.size, str(name), opts, out);
        mn.check(status, errors, 'loadAsset');
        return wasm.HEAPU32[out >> 2];
      });
    } finally {
      if (reader) wasm.removeFunction(reader);
    }
    this.name = mn.string(wasm._mn_asset_name(this.handle));
    this.report = mn.string(wasm._mn_asset_report(this.handle));
  }
  /** Drops this reference; the characters made from it keep the data. */
  dispose() {
    if (this.handle) this.mn.wasm._mn_asset_release(this.handle);
    this.handle = 0;
  }
}

/** A scene: characters, the BML realizer, named objects and callbacks. */
class Scene extends ErrorHolder {
  constructor(mn) {
    super();
    this.mn = mn;
    const wasm = mn.wasm;
    this.characters = new Map();
    this.callbacks = new Map();  // kind -> table index
    /** Files the library may read (the WAVs of <bmlt:audiofile>): name -> bytes. */
    this.files = new Map();
    this.handle = mn.withTemp(({ alloc }) => {
      const out = alloc(4);
      mn.check(wasm._mn_scene_create(out), null, 'createScene');
      return wasm.HEAPU32[out >> 2];
    });
    try {
      this.call('setSpeechSynthesis', () => wasm._mn_scene_set_speech_synthesis(this.handle, 1));  // INLINE: no threads
      this.audioReader = mn.fileReader(this.files, this);
      this.call('setAudioFiles', () => wasm._mn_scene_set_audio_files(this.handle, 0, this.audioReader, 0));
    } catch (e) {
      this.dispose();
      throw e;
    }
  }

  // Runs one C call on this scene and throws for its status (after a callback's exception).
  call(what, fn) {
    this.mn.alive(this.handle, `Scene.${what}`);
    return checked(this, this, what, fn());
  }

  /** Adds a character made from an Asset (or from bytes: `options.fileName` then names the file). */
  addCharacter(name, source, options = {}) {
    const mn = this.mn;
    const wasm = mn.wasm;
    mn.alive(this.handle, 'Scene.addCharacter');
    const asset = source instanceof Asset ? source : mn.loadAsset(source, options.fileName || `${name}.glb`, options);
    try {
      mn.alive(asset.handle, 'Scene.addCharacter: the asset');
      const handle = mn.withTemp(({ alloc, str }) => {
        const out = alloc(4);
        const namePtr = str(name);
        this.call('addCharacter', () => wasm._mn_scene_add_character_from_asset(this.handle, namePtr, asset.handle, out));
        return wasm.HEAPU32[out >> 2];
      });
      const character = new Character(this, handle);
      this.characters.set(character.name, character);
      return character;
    } finally {
      if (!(source instanceof Asset)) asset.dispose();
    }
  }

  /** Sends one BML block (for `character`, or the block's characterId). Throws on a failed block. */
  sendBml(bml, character) {
    this.mn.withTemp(({ str }) => {
      const who = character === undefined || character === null ? 0 : str(typeof character === 'string' ? character : character.name);
      const text = str(bml);
      this.call('sendBml', () => this.mn.wasm._mn_scene_send_bml(this.handle, who, text));
    });
  }

  /** Advances the scene by dt seconds; callbacks come from here. */
  update(dt) {
    this.mn.alive(this.handle, 'Scene.update');
    checked(this, this, 'update', this.mn.wasm._mn_scene_update(this.handle, dt));
  }

  get time() { return this.handle ? this.mn.wasm._mn_scene_time(this.handle) : 0; }

  /** Places a named object ("camera" for the viewer) that gaze, pointing and locomotion may target. */
  setObject(name, x, y, z) {
    this.mn.withTemp(({ str }) => { const n = str(name); this.call('setObject', () => this.mn.wasm._mn_scene_set_object(this.handle, n, x, y, z)); });
  }
  removeObject(name) {
    this.mn.withTemp(({ str }) => { const n = str(name); this.call('removeObject', () => this.mn.wasm._mn_scene_remove_object(this.handle, n)); });
  }
  interruptBlock(id) {
    this.mn.withTemp(({ str }) => { const n = str(id); this.call('interruptBlock', () => this.mn.wasm._mn_scene_interrupt_block(this.handle, n)); });
  }
  /** "auto", "bml" or "smartbody", for one character or (none given) the scene. */
  setBmlDialect(dialect, character) {
    this.mn.withTemp(({ str }) => {
      const who = character ? str(typeof character === 'string' ? character : character.name) : 0;
      const d = str(dialect);
      this.call('setBmlDialect', () => this.mn.wasm._mn_scene_set_bml_dialect(this.handle, who, d));
    });
  }

  /**
   * A recorded voice line: a <speech> with this text is said with the recording (WAV bytes,
   * optional) and its phoneme alignment (HTK .lab, ARCTIC .phones or CSV text or bytes).
   */
  addSpeechLine(text, { audio, alignment, audioName = 'line.wav', alignmentName = 'line.lab' }) {
    const files = new Map([[alignmentName, alignment]]);
    if (audio) files.set(audioName, audio);
    this.mn.alive(this.handle, 'Scene.addSpeechLine');
    const reader = this.mn.fileReader(files, this);
    try {
      this.mn.withTemp(({ str }) => {
        const t = str(text), a = audio ? str(audioName) : 0, l = str(alignmentName);
        this.call('addSpeechLine', () => this.mn.wasm._mn_scene_add_speech_line(this.handle, t, a, l, reader, 0));
      });
    } finally {
      this.mn.wasm.removeFunction(reader);
    }
  }

  // ---- callbacks: fn(object) or null to remove ----
  // A callback must not throw into the library (the C API's rule): an exception is kept and
  // thrown again when the call that ran the callback returns.
  setCallback(kind, setter, signature, fn, wrap) {
    const wasm = this.mn.wasm;
    this.mn.alive(this.handle, `Scene.${kind}`);
    const old = this.callbacks.get(kind);
    const guard = (f) => (...args) => {
      try {
        return f(...args);
      } catch (e) {
        if (this.callbackError === undefined) this.callbackError = e;
        return undefined;
      }
    };
    const index = fn ? wasm.addFunction(guard(wrap(fn)), signature) : 0;
    try {
      this.call(setter, () => wasm[setter](this.handle, index, 0));
    } catch (e) {
      if (index) wasm.removeFunction(index);
      throw e;
    }
    if (old) wasm.removeFunction(old);
    if (index) this.callbacks.set(kind, index); else this.callbacks.delete(kind);
  }
  /** BML feedback: {kind, character, block, behavior, syncPoint, message, blockTime, sceneTime}. */
  onFeedback(fn) {
    const mn = this.mn;
    this.setCallback('feedback', '_mn_scene_set_feedback_callback', 'vii', fn, (f) => (user, p) => {
      const u32 = mn.wasm.HEAPU32, f64 = mn.wasm.HEAPF64;
      f({ kind: FEEDBACK_KINDS[mn.wasm.HEAP32[p >> 2]], character: mn.string(u32[(p + 4) >> 2]),
        block: mn.string(u32[(p + 8) >> 2]), behavior: mn.string(u32[(p + 12) >> 2]),
        syncPoint: mn.string(u32[(p + 16) >> 2]), message: mn.string(u32[(p + 20) >> 2]),
        blockTime: f64[(p + 24) >> 3], sceneTime: f64[(p + 32) >> 3] });
    });
  }
  /** Visemes as speech reaches them: {character, viseme, weight, time}. */
  onViseme(fn) {
    const mn = this.mn;
    this.setCallback('viseme', '_mn_scene_set_viseme_callback', 'vii', fn, (f) => (user, p) => {
      f({ character: mn.string(mn.wasm.HEAPU32[p >> 2]), viseme: mn.string(mn.wasm.HEAPU32[(p + 4) >> 2]),
        weight: mn.wasm.HEAPF32[(p + 8) >> 2], time: mn.wasm.HEAPF64[(p + 16) >> 3] });
    });
  }
  /** The library's log: fn(level, message), level "info" | "warning" | "error". */
  onLog(fn) {
    const mn = this.mn;
    this.setCallback('log', '_mn_scene_set_log_callback', 'viii', fn, (f) => (user, level, msg) => f(LOG_LEVELS[level] || String(level), mn.string(msg)));
  }
  /** A line starts: {character, behavior, samples (Int16Array copy), sampleRate, startTime, duration}. */
  onSpeech(fn) {
    const mn = this.mn;
    this.setCallback('speech', '_mn_scene_set_speech_callback', 'vii', fn, (f) => (user, p) => {
      const u32 = mn.wasm.HEAPU32;
      const samplesPtr = u32[(p + 8) >> 2], count = u32[(p + 12) >> 2];
      f({ character: mn.string(u32[p >> 2]), behavior: mn.string(u32[(p + 4) >> 2]),
        samples: samplesPtr ? mn.wasm.HEAP16.slice(samplesPtr >> 1, (samplesPtr >> 1) + count) : null,
        sampleRate: mn.wasm.HEAP32[(p + 16) >> 2], audioFile: mn.string(u32[(p + 20) >> 2]),
        startTime: mn.wasm.HEAPF64[(p + 24) >> 3], duration: mn.wasm.HEAPF64[(p + 32) >> 3] });
    });
  }
  /** Animation events: {kind: "footDown" | "footUp" | "marker", foot, character, name, clip, layer, weight, clipTime, sceneTime}. */
  onEvent(fn) {
    const mn = this.mn;
    this.setCallback('event', '_mn_scene_set_event_callback', 'vii', fn, (f) => (user, p) => {
      const u32 = mn.wasm.HEAPU32, i32 = mn.wasm.HEAP32;
      f({ kind: EVENT_KINDS[i32[p >> 2]], foot: FOOT_SIDES[i32[(p + 4) >> 2]], character: mn.string(u32[(p + 8) >> 2]),
        name: mn.string(u32[(p + 12) >> 2]), clip: mn.string(u32[(p + 16) >> 2]), layer: i32[(p + 20) >> 2],
        weight: mn.wasm.HEAPF32[(p + 24) >> 2], clipTime: mn.wasm.HEAPF64[(p + 32) >> 3],
        sceneTime: mn.wasm.HEAPF64[(p + 40) >> 3] });
    });
  }
  /** Sounds of <bmlt:audiofile>: {kind: "play" | "stop", character, behavior, samples (Float32Array copy), channels, sampleRate, file, sceneTime, duration}. */
  onAudio(fn) {
    const mn = this.mn;
    this.setCallback('audio', '_mn_scene_set_audio_callback', 'vii', fn, (f) => (user, p) => {
      const u32 = mn.wasm.HEAPU32, i32 = mn.wasm.HEAP32;
      const samples = u32[(p + 12) >> 2], frames = u32[(p + 16) >> 2], channels = i32[(p + 20) >> 2];
      f({ kind: i32[p >> 2] === 0 ? 'play' : 'stop', character: mn.string(u32[(p + 4) >> 2]),
        behavior: mn.string(u32[(p + 8) >> 2]),
        samples: samples ? mn.wasm.HEAPF32.slice(samples >> 2, (samples >> 2) + frames * channels) : null,
        channels, sampleRate: i32[(p + 24) >> 2], file: mn.string(u32[(p + 28) >> 2]),
        sceneTime: mn.wasm.HEAPF64[(p + 32) >> 3], duration: mn.wasm.HEAPF64[(p + 40) >> 3] });
    });
  }

  /** A clip starts or stops on a layer: {kind: "started" | "stopped", character, clip, sceneTime}. */
  onClip(fn) {
    const mn = this.mn;
    this.setCallback('clip', '_mn_scene_set_clip_callback', 'vii', fn, (f) => (user, p) => {
      const u32 = mn.wasm.HEAPU32;
      f({ kind: mn.wasm.HEAP32[p >> 2] === 0 ? 'started' : 'stopped', character: mn.string(u32[(p + 4) >> 2]),
        clip: mn.string(u32[(p + 8) >> 2]), sceneTime: mn.wasm.HEAPF64[(p + 16) >> 3] });
    });
  }

  /** Frees the scene, its characters, their bindings and the callbacks. */
  dispose() {
    const wasm = this.mn.wasm;
    for (const c of this.characters.values()) c.release();
    this.characters.clear();
    if (this.handle) wasm._mn_scene_destroy(this.handle);
    this.handle = 0;
    for (const index of this.callbacks.values()) wasm.removeFunction(index);
    this.callbacks.clear();
    if (this.audioReader) wasm.removeFunction(this.audioReader);
    this.audioReader = 0;
  }
}

// A Float32Array on the module's memory at ptr, made again when memory grows (the old
// ArrayBuffer is then detached).
class HeapFloats {
  constructor(mn, count) {
    this.mn = mn;
    this.count = count;
    this.ptr = mn.malloc(Math.max(4, count * 4));
    mn.wasm.HEAPF32.fill(0, this.ptr >> 2, (this.ptr >> 2) + count);
    this.view = null;
  }
  get array() {
    const heap = this.mn.wasm.HEAPF32;
    if (!this.view || this.view.buffer !== heap.buffer) this.view = new Float32Array(heap.buffer, this.ptr, this.count);
    return this.view;
  }
  free() {
    if (this.ptr) this.mn.wasm._free(this.ptr);
    this.ptr = 0;
    this.view = null;
  }
}

// Keys of a character's buffers: palettes are layout * 2 + inverse bind (0..5).
const kMorphBuffer = 6;
const kWorldBuffer = 7;

/** A character of a scene. */
class Character {
  constructor(scene, handle) {
    this.scene = scene;
    this.mn = scene.mn;
    this.handle = handle;
    const wasm = this.mn.wasm;
    this.name = this.mn.string(wasm._mn_character_name(handle));
    const joints = wasm._mn_character_joint_count(handle);
    this.jointNames = Array.from({ length: joints }, (_, j) => this.mn.string(wasm._mn_character_joint_name(handle, j)));
    this.parents = Int32Array.from({ length: joints }, (_, j) => wasm._mn_character_joint_parent(handle, j));
    const morphs = wasm._mn_character_morph_count(handle);
    this.morphNames = Array.from({ length: morphs }, (_, m) => this.mn.string(wasm._mn_character_morph_name(handle, m)));
    const clips = wasm._mn_character_clip_count(handle);
    this.clipNames = Array.from({ length: clips }, (_, c) => this.mn.string(wasm._mn_character_clip_name(handle, c)));
    const spaces = wasm._mn_character_blend_space_count(handle);
    this.blendSpaceNames = Array.from({ length: spaces }, (_, b) => this.mn.string(wasm._mn_character_blend_space_name(handle, b)));
    this.buffers = new Map();
    this.bindings = new Set();
  }

  // One C call on this character (checked alive first: a removed one's handle is 0).
  call(what, fn) {
    this.mn.alive(this.handle, `Character.${what}`);
    return checked(this, this.scene, what, fn());
  }
  buffer(key, count) {
    let b = this.buffers.get(key);
    if (!b) { b = new HeapFloats(this.mn, count); this.buffers.set(key, b); }
    return b;
  }
  /** Every joint's matrix in the skeleton's order (16 or 12 floats each), as of the last update. */
  palette(layout = PaletteLayout.MAT4_COLUMN_MAJOR, inverseBind = true) {
    this.mn.alive(this.handle, 'Character.palette');
    const n = this.jointNames.length * this.mn.wasm._mn_palette_floats_per_joint(layout);
    const b = this.buffer(layout * 2 + (inverseBind ? 1 : 0), n);
    checked(this, this.scene, 'palette', this.mn.wasm._mn_character_palette(this.handle, layout, inverseBind ? 1 : 0, b.ptr, n));
    return b.array;
  }
  /** Morph weights in morphNames order. */
  morphWeights() {
    this.mn.alive(this.handle, 'Character.morphWeights');
    const b = this.buffer(kMorphBuffer, this.morphNames.length);
    checked(this, this.scene, 'morphWeights', this.mn.wasm._mn_character_morph_weights(this.handle, b.ptr, this.morphNames.length));
    return b.array;
  }
  /** The world-from-model matrix (column-major 16 floats): place the skinned mesh with it. */
  worldMatrix() {
    this.mn.alive(this.handle, 'Character.worldMatrix');
    const b = this.buffer(kWorldBuffer, 16);
    checked(this, this.scene, 'worldMatrix', this.mn.wasm._mn_character_world_matrix(this.handle, b.ptr));
    return b.array;
  }
  setPosition(x, y, z) { this.call('setPosition', () => this.mn.wasm._mn_character_set_position(this.handle, x, y, z)); }
  setHeading(radians) { this.call('setHeading', () => this.mn.wasm._mn_character_set_heading(this.handle, radians)); }

  // mn_play_options from {weight, speed, loop, startTime, fadeIn, additive, rootMotion}.
  playOptions(alloc, options) {
    const wasm = this.mn.wasm;
    const o = LAYOUT.playOptions;
    const p = alloc(o.size);
    wasm._mn_play_options_default(p);
    if (options.weight !== undefined) wasm.HEAPF32[(p + o.weight) >> 2] = options.weight;
    if (options.speed !== undefined) wasm.HEAPF32[(p + o.speed) >> 2] = options.speed;
    if (options.loop !== undefined) wasm.HEAP32[(p + o.loop) >> 2] = options.loop ? 1 : 0;
    if (options.startTime !== undefined) wasm.HEAPF64[(p + o.startTime) >> 3] = options.startTime;
    if (options.fadeIn !== undefined) wasm.HEAPF32[(p + o.fadeIn) >> 2] = options.fadeIn;
    if (options.additive !== undefined) wasm.HEAP32[(p + o.additive) >> 2] = options.additive ? 1 : 0;
    if (options.rootMotion !== undefined) wasm.HEAP32[(p + o.rootMotion) >> 2] = options.rootMotion ? 1 : 0;
    return p;
  }
  /** Plays a clip on a layer (0..7). Options: weight, speed, loop, startTime, fadeIn, additive, rootMotion. */
  play(clip, layer = 0, options = {}) {
    this.mn.withTemp(({ alloc, str }) => {
      const name = str(clip);
      const p = this.playOptions(alloc, options);
      this.call('play', () => this.mn.wasm._mn_character_play(this.handle, layer, name, p));
    });
  }
  stop(layer = 0, fadeOut = 0) { this.call('stop', () => this.mn.wasm._mn_character_stop(this.handle, layer, fadeOut)); }
  /** Plays a blend space of the rig (blendSpaceNames) on a layer; the same options as play. */
  playBlend(blendSpace, layer = 0, options = {}) {
    this.mn.withTemp(({ alloc, str }) => {
      const name = str(blendSpace);
      const p = this.playOptions(alloc, options);
      this.call('playBlend', () => this.mn.wasm._mn_character_play_blend(this.handle, layer, name, p));
    });
  }
  /** Moves the parameter point of the blend space playing on `layer` (no allocation: every frame is fine). */
  setBlendParameter(layer, x, y = 0) {
    this.call('setBlendParameter', () => this.mn.wasm._mn_character_set_blend_parameter(this.handle, layer, x, y));
  }

  /**
   * Binds to an engine skeleton: `bones` (names in the engine's palette order), `parents`
   * (slots, -1 for roots; optional, as many as bones), `morphs` (the engine's morph slot
   * names). Options: throughJointMaps (bind by canonical joint where names differ).
   */
  bind({ bones, parents, morphs = [], throughJointMaps = false }) {
    this.mn.alive(this.handle, 'Character.bind');
    if (parents && parents.length !== bones.length) {
      throw new MarionetteError(`Character.bind: ${parents.length} parents for ${bones.length} bones`, 'MN_ERROR_INVALID_ARGUMENT');
    }
    const binding = new Binding(this, bones, parents, morphs, throughJointMaps);
    this.bindings.add(binding);
    return binding;
  }

  /** Removes the character from its scene (refused from inside a callback: then it stays). */
  remove() {
    this.call('remove', () => this.mn.wasm._mn_scene_remove_character(this.scene.handle, this.handle));
    this.scene.characters.delete(this.name);
    this.release();
  }
  release() {
    for (const b of [...this.bindings]) b.dispose();
    this.bindings.clear();
    for (const b of this.buffers.values()) b.free();
    this.buffers.clear();
    this.handle = 0;
  }
}

/** A character bound to an engine skeleton: the palette and morphs in the engine's order. */
class Binding {
  constructor(character, bones, parents, morphs, throughJointMaps) {
    const mn = character.mn, wasm = mn.wasm;
    this.character = character;
    this.mn = mn;
    this.boneCount = bones.length;
    this.morphSlotCount = morphs.length;
    this.handle = mn.withTemp(({ alloc, str }) => {
      // Every allocation first (each may grow the memory), then the writes.
      const namePtrs = bones.map((n) => str(n));
      const morphPtrs = morphs.map((n) => str(n));
      const names = alloc(4 * Math.max(1, bones.length));
      const parentPtr = parents ? alloc(4 * Math.max(1, bones.length)) : 0;
      const morphNames = morphs.length ? alloc(4 * morphs.length) : 0;
      const s = LAYOUT.engineSkeleton;
      const skeleton = alloc(s.size);
      const o = LAYOUT.bindingOptions;
      const opts = alloc(o.size);
      const out = alloc(4);
      wasm.HEAPU32.set(namePtrs, names >> 2);
      if (parentPtr) wasm.HEAP32.set(Int32Array.from(parents), parentPtr >> 2);
      if (morphNames) wasm.HEAPU32.set(morphPtrs, morphNames >> 2);
      wasm.HEAPU32[(skeleton + s.boneNames) >> 2] = names;
      wasm.HEAPU32[(skeleton + s.parents) >> 2] = parentPtr;
      wasm.HEAPU32[(skeleton + s.boneCount) >> 2] = bones.length;
      wasm.HEAPU32[(skeleton + s.morphNames) >> 2] = morphNames;
      wasm.HEAPU32[(skeleton + s.morphCount) >> 2] = morphs.length;
      wasm._mn_binding_options_default(opts);
      wasm.HEAP32[(opts + o.throughJointMaps) >> 2] = throughJointMaps ? 1 : 0;
      character.call('bind', () => wasm._mn_binding_create(character.handle, skeleton, opts, out));
      return wasm.HEAPU32[out >> 2];
    });
    this.report = mn.string(wasm._mn_binding_report(this.handle));
    this.jointForBone = Int32Array.from({ length: bones.length }, (_, i) => wasm._mn_binding_joint_for_bone(this.handle, i));
    this.morphForSlot = Int32Array.from({ length: morphs.length }, (_, i) => wasm._mn_binding_morph_for_slot(this.handle, i));
    this.paletteBuffers = new Map();
    this.morphBuffer = new HeapFloats(mn, this.morphSlotCount);
  }
  call(what, fn) {
    this.mn.alive(this.handle, `Binding.${what}`);
    return checked(this, this.character.scene, what, fn());
  }
  /** The palette in the engine's bone order (a view on wasm memory, rewritten by each call). */
  palette(layout = PaletteLayout.MAT4_COLUMN_MAJOR, inverseBind = true) {
    this.mn.alive(this.handle, 'Binding.palette');
    const wasm = this.mn.wasm;
    const n = this.boneCount * wasm._mn_palette_floats_per_joint(layout);
    const key = layout * 2 + (inverseBind ? 1 : 0);
    let b = this.paletteBuffers.get(key);
    if (!b) { b = new HeapFloats(this.mn, n); this.paletteBuffers.set(key, b); }
    checked(this, this.character.scene, 'palette', wasm._mn_binding_palette(this.handle, layout, inverseBind ? 1 : 0, b.ptr, n));
    return b.array;
  }
  /** Weights of the engine's morph slots (slots without a morph keep their values). */
  morphWeights() {
    this.mn.alive(this.handle, 'Binding.morphWeights');
    checked(this, this.character.scene, 'morphWeights',
      this.mn.wasm._mn_binding_morph_weights(this.handle, this.morphBuffer.ptr, this.morphSlotCount));
    return this.morphBuffer.array;
  }
  dispose() {
    if (this.handle) this.mn.wasm._mn_binding_destroy(this.handle);
    this.handle = 0;
    for (const b of this.paletteBuffers.values()) b.free();
    this.paletteBuffers.clear();
    this.morphBuffer.free();
    this.character.bindings.delete(this);
  }
}
