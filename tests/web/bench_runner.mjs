// The web side of the update benchmark (native_trace.cpp --bench): N copies of a character
// playing "Idle" with a gaze at the camera; the update cost per character, the median of 5
// runs of frames/5 updates (timed as a batch: browsers coarsen performance.now()), after a
// warm-up of at least 1.5 s.
export function benchUpdate(marionette, bytes, fileName, n, frames) {
  const asset = marionette.loadAsset(bytes, fileName);
  const scene = marionette.createScene();
  try {
    scene.setObject('camera', 0, 1.5, 6);
    for (let k = 0; k < n; ++k) {
      const c = scene.addCharacter(`c${k}`, asset);
      c.setPosition((k % 10) - 4.5, 0, -Math.floor(k / 10));
      c.play('Idle');
      scene.sendBml(`<bml id="bc${k}" characterId="c${k}"><gaze id="g" target="camera"/></bml>`);
    }
    // Warm-up: at least 1.5 s of updates, so that the engine's optimizing compiler has taken
    // over from its baseline one (V8 tiers WebAssembly up as functions get hot).
    const warm = performance.now();
    for (let f = 0; f < 60 || performance.now() - warm < 1500; ++f) scene.update(1 / 60);
    const perCharacter = [];
    for (let run = 0; run < 5; ++run) {
      const t0 = performance.now();
      for (let f = 0; f < Math.floor(frames / 5); ++f) scene.update(1 / 60);
      perCharacter.push(((performance.now() - t0) * 1000) / Math.floor(frames / 5) / n);
    }
    perCharacter.sort((a, b) => a - b);
    return { characters: n, frames, usPerCharacter: perCharacter[2] };
  } finally {
    scene.dispose();
    asset.dispose();
  }
}
