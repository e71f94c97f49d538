// TypeScript declarations of marionette.mjs (docs/web.md).

/** How palettes are laid out: 16 floats per joint column- or row-major, or 12 (3x4 rows). */
export declare const PaletteLayout: Readonly<{ MAT4_COLUMN_MAJOR: 0; MAT4_ROW_MAJOR: 1; MAT3X4_ROW_MAJOR: 2 }>;
export type PaletteLayoutValue = 0 | 1 | 2;

/** A failed call: the library's message names the file or block, line:column and the problem.
 * Calls on a disposed or removed object throw one too (status "MN_ERROR_INVALID_ARGUMENT"). */
export declare class MarionetteError extends Error {
  /** The C API's status name: "MN_ERROR_BML", "MN_ERROR_LOAD", ... */
  readonly status: string;
}

/** Bytes a load may read: glTF buffers, profiles, WAVs, alignments; by path or file name. */
export type FileMap = Map<string, Uint8Array | ArrayBuffer | string> | Record<string, Uint8Array | ArrayBuffer | string>;

/** Loads the WebAssembly module; options go to emscripten's factory (wasmBinary, locateFile). */
export declare function loadMarionette(options?: { wasmBinary?: ArrayBuffer | Uint8Array; locateFile?: (path: string, prefix: string) => string }): Promise<Marionette>;

export interface Marionette {
  /** "MAJOR.MINOR.PATCH" */
  readonly version: string;
  createScene(): Scene;
  /** Loads a glTF, GLB or VRM from bytes, once; `name` is its file name (the extension chooses the format). */
  loadAsset(bytes: Uint8Array | ArrayBuffer, name: string, options?: { files?: FileMap; profile?: string }): Asset;
}

export interface Asset {
  readonly name: string;
  /** What the load warned about, one line each; "" when nothing. */
  readonly report: string;
  dispose(): void;
}

export interface Feedback {
  kind: 'prediction' | 'blockProgress' | 'syncPoint' | 'warning' | 'event';
  character: string;
  block: string;
  behavior: string;
  syncPoint: string;
  message: string;
  blockTime: number;
  sceneTime: number;
}
export interface Viseme { character: string; viseme: string; weight: number; time: number }
export interface SpeechLine {
  character: string; behavior: string; samples: Int16Array | null; sampleRate: number;
  audioFile: string; startTime: number; duration: number;
}
export interface AnimationEvent {
  kind: 'footDown' | 'footUp' | 'marker'; foot: 'none' | 'left' | 'right'; character: string; name: string;
  clip: string; layer: number; weight: number; clipTime: number; sceneTime: number;
}
export interface ClipEvent { kind: 'started' | 'stopped'; character: string; clip: string; sceneTime: number }
export interface AudioEvent {
  kind: 'play' | 'stop'; character: string; behavior: string; samples: Float32Array | null; channels: number;
  sampleRate: number; file: string; sceneTime: number; duration: number;
}
export interface PlayOptions {
  weight?: number; speed?: number; loop?: boolean; startTime?: number; fadeIn?: number; additive?: boolean; rootMotion?: boolean;
}

export interface Scene {
  /** Files <bmlt:audiofile> reads: name -> bytes. */
  readonly files: Map<string, Uint8Array | ArrayBuffer | string>;
  readonly characters: Map<string, Character>;
  /** Seconds on the scene clock. */
  readonly time: number;
  addCharacter(name: string, source: Asset | Uint8Array | ArrayBuffer, options?: { fileName?: string; files?: FileMap; profile?: string }): Character;
  /** Sends one BML block; throws MarionetteError (status "MN_ERROR_BML") when the block fails as a whole. */
  sendBml(bml: string, character?: string | Character): void;
  update(dt: number): void;
  setObject(name: string, x: number, y: number, z: number): void;
  removeObject(name: string): void;
  interruptBlock(id: string): void;
  setBmlDialect(dialect: 'auto' | 'bml' | 'smartbody', character?: string | Character): void;
  addSpeechLine(text: string, line: { audio?: Uint8Array | ArrayBuffer; alignment: Uint8Array | ArrayBuffer | string; audioName?: string; alignmentName?: string }): void;
  // Callbacks run during update() and sendBml(); one that throws does not stop the library:
  // its exception is thrown again by the update() or sendBml() that ran it.
  onFeedback(fn: ((f: Feedback) => void) | null): void;
  onViseme(fn: ((v: Viseme) => void) | null): void;
  onLog(fn: ((level: 'info' | 'warning' | 'error', message: string) => void) | null): void;
  onSpeech(fn: ((s: SpeechLine) => void) | null): void;
  onEvent(fn: ((e: AnimationEvent) => void) | null): void;
  onAudio(fn: ((a: AudioEvent) => void) | null): void;
  onClip(fn: ((c: ClipEvent) => void) | null): void;
  dispose(): void;
}

export interface Character {
  readonly name: string;
  readonly jointNames: string[];
  /** Parent joint of each joint, -1 for roots. */
  readonly parents: Int32Array;
  readonly morphNames: string[];
  readonly clipNames: string[];
  readonly blendSpaceNames: string[];
  /** Every joint's matrix (skinning matrices with inverseBind, else model space); a view on wasm memory rewritten by each call. */
  palette(layout?: PaletteLayoutValue, inverseBind?: boolean): Float32Array;
  morphWeights(): Float32Array;
  /** World-from-model, column-major. */
  worldMatrix(): Float32Array;
  setPosition(x: number, y: number, z: number): void;
  setHeading(radians: number): void;
  play(clip: string, layer?: number, options?: PlayOptions): void;
  stop(layer?: number, fadeOut?: number): void;
  /** Plays a blend space of the rig on a layer (options as play; additive is refused). */
  playBlend(blendSpace: string, layer?: number, options?: PlayOptions): void;
  /** Moves the parameter point of the blend space on `layer`; no allocation, fine every frame. */
  setBlendParameter(layer: number, x: number, y?: number): void;
  /** Binds to an engine skeleton: bone names in palette order, parents (-1 roots; as many as bones), morph slot names. */
  bind(engine: { bones: string[]; parents?: ArrayLike<number>; morphs?: string[]; throughJointMaps?: boolean }): Binding;
  remove(): void;
}

export interface Binding {
  readonly boneCount: number;
  readonly morphSlotCount: number;
  /** How names were resolved; "" when every bone and slot was bound. */
  readonly report: string;
  /** The character joint each engine bone receives, -1 for none. */
  readonly jointForBone: Int32Array;
  readonly morphForSlot: Int32Array;
  palette(layout?: PaletteLayoutValue, inverseBind?: boolean): Float32Array;
  morphWeights(): Float32Array;
  dispose(): void;
}
