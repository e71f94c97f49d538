// Plays tests/web/trace_scenario.json through the JS package, as native_trace.cpp does through
// the C API, and returns every frame's bone world matrices (Float32Array, the layout of
// native_trace's output) and the median update time. Runs in Node.js and in the page.
//   runTrace(marionette, scenario, readAsset) ; readAsset(path) -> Promise<Uint8Array>
export async function runTrace(marionette, scenario, readAsset) {
  const scene = marionette.createScene();
  try {
    for (const [name, p] of Object.entries(scenario.objects)) scene.setObject(name, p[0], p[1], p[2]);
    for (const line of scenario.speechLines) {
      scene.addSpeechLine(line.text, {
        audio: await readAsset(line.audio), audioName: line.audio.split('/').pop(),
        alignment: await readAsset(line.alignment), alignmentName: line.alignment.split('/').pop(),
      });
    }
    const characters = [];
    for (const c of scenario.characters) {
      const asset = marionette.loadAsset(await readAsset(c.file), c.file.split('/').pop());
      const character = scene.addCharacter(c.name, asset);
      asset.dispose();
      character.setPosition(c.position[0], c.position[1], c.position[2]);
      characters.push(character);
    }
    const floatsPerFrame = characters.reduce((n, c) => n + c.jointNames.length * 16, 0);
    const out = new Float32Array(scenario.frames * floatsPerFrame);
    const micros = [];
    const feedback = [];
    const events = [];
    const visemes = [];
    scene.onFeedback((f) => feedback.push(f));
    scene.onEvent((e) => events.push(e));
    scene.onViseme((v) => visemes.push(v));
    let at = 0;
    for (let frame = 0; frame < scenario.frames; ++frame) {
      scenario.characters.forEach((c) => {
        for (const b of c.bml) if (b.frame === frame) scene.sendBml(b.text);
      });
      const t0 = performance.now();
      scene.update(scenario.dt);
      micros.push((performance.now() - t0) * 1000);
      for (const character of characters) {
        const palette = character.palette(0, false);
        const world = character.worldMatrix();
        for (let j = 0; j * 16 < palette.length; ++j) {  // world * model, column-major, in float
          for (let col = 0; col < 4; ++col) {
            for (let row = 0; row < 4; ++row) {
              let s = 0;
              for (let i = 0; i < 4; ++i) s = Math.fround(s + Math.fround(world[i * 4 + row] * palette[j * 16 + col * 4 + i]));
              out[at + col * 4 + row] = s;
            }
          }
          at += 16;
        }
      }
    }
    micros.sort((a, b) => a - b);
    return { matrices: out, medianMicros: micros[micros.length >> 1], feedback, events, visemes,
      joints: characters.map((c) => c.jointNames.length) };
  } finally {
    scene.dispose();
  }
}

// How far two traces are apart, per bone world matrix: the translation column in metres, and
// the other three columns relative to their length (a joint in a centimetre skeleton under a
// 0.01 scale, or the reverse, has columns of length 100 or 0.01: their entries carry float
// rounding of that size). `maxAbs` is the largest of both over every matrix; `maxRaw` the
// largest plain difference of one float, for the record. NaN counts as the worst.
export function compareTraces(a, b) {
  if (a.length !== b.length) return { sameLength: false, maxAbs: Infinity, maxRaw: Infinity, at: -1 };
  let maxAbs = 0, maxRaw = 0, maxTranslation = 0, maxAxis = 0, at = -1;
  for (let m = 0; m < a.length; m += 16) {
    for (let col = 0; col < 4; ++col) {
      let scale = 1;
      if (col < 3) {
        const o = m + col * 4;
        scale = Math.max(1e-6, Math.hypot(a[o], a[o + 1], a[o + 2]));
      }
      for (let row = 0; row < 4; ++row) {
        const i = m + col * 4 + row;
        const raw = Math.abs(a[i] - b[i]);
        if (!(raw <= maxRaw)) maxRaw = raw;
        const d = col < 3 ? raw / scale : raw;
        if (col < 3) { if (!(d <= maxAxis)) maxAxis = d; } else if (!(d <= maxTranslation)) maxTranslation = d;
        if (!(d <= maxAbs)) { maxAbs = d; at = i; }
      }
    }
  }
  return { sameLength: true, maxAbs, maxRaw, maxTranslation, maxAxis, at };
}
