// web.trace_matches_native (Node.js): the package and the native C API play the same scenario;
// every bone world matrix of every frame agrees within 1e-4 (docs/web.md).
//   node tests/web/trace_test.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR
import { execFileSync } from 'node:child_process';
import { readFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { runTrace, compareTraces } from './trace_runner.mjs';

const [nativeProgram, packageDir, assetsDir] = process.argv.slice(2);
if (!nativeProgram || !packageDir || !assetsDir) {
  console.error('usage: node trace_test.mjs NATIVE_TRACE_PROGRAM PACKAGE_DIR SHARED_ASSETS_DIR');
  process.exit(2);
}
const scenarioPath = new URL('./trace_scenario.json', import.meta.url);
const scenario = JSON.parse(readFileSync(scenarioPath, 'utf8'));
const work = mkdtempSync(join(tmpdir(), 'marionette-trace-'));
let failed = false;
try {
  const nativeOut = join(work, 'native.bin');
  const log = execFileSync(nativeProgram, [scenarioPath.pathname, assetsDir, nativeOut], { encoding: 'utf8' });
  process.stdout.write(log);
  const bytes = readFileSync(nativeOut);
  const native = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 4);
  const { loadMarionette } = await import(pathToFileURL(join(packageDir, 'marionette.mjs')).href);
  const marionette = await loadMarionette();
  const web = await runTrace(marionette, scenario, async (p) => new Uint8Array(readFileSync(join(assetsDir, p))));
  const r = compareTraces(native, web.matrices);
  const starts = web.feedback.filter((f) => f.kind === 'blockProgress' && f.syncPoint === 'start').length;
  const warnings = web.feedback.filter((f) => f.kind === 'warning').map((f) => f.message);
  console.log(`web trace: ${scenario.frames} frames, joints ${web.joints.join('+')}, median update ${web.medianMicros.toFixed(1)} us, ` +
    `max |native - web| ${r.maxAbs.toExponential(2)} (translation ${r.maxTranslation.toExponential(2)} m, axes ${r.maxAxis.toExponential(2)}; largest raw float difference ${r.maxRaw.toExponential(2)}), ${starts} block starts`);
  if (warnings.length) console.log(`BML warnings:\n  ${warnings.join('\n  ')}`);
  if (!r.sameLength) { console.error(`FAIL: native ${native.length} floats, web ${web.matrices.length}`); failed = true; }
  if (!(r.maxAbs <= 1e-4)) { console.error(`FAIL: the traces differ by ${r.maxAbs} at float ${r.at} (> 1e-4)`); failed = true; }
  const blocks = scenario.characters.reduce((n, c) => n + c.bml.length, 0);
  if (starts !== blocks) { console.error(`FAIL: ${starts} of ${blocks} blocks started`); failed = true; }
  // The callbacks reach JavaScript: the line's visemes, and the foot contacts of a walk clip
  // (animation events come from clip layers: docs/animation-events.md).
  const walker = marionette.createScene();
  const feet = [];
  walker.onEvent((e) => feet.push(e));
  const robot = walker.addCharacter('walker', new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb'))),
    { fileName: 'RobotExpressive.glb' });
  robot.play('Walking');
  for (let f = 0; f < 120; ++f) walker.update(1 / 60);
  walker.dispose();
  console.log(`callbacks: ${feet.length} foot events in 2 s of Walking (${[...new Set(feet.map((e) => e.name))].join(', ')}), ${web.visemes.length} visemes`);
  if (feet.length < 4 || !feet.every((e) => e.character === 'walker' && e.clip === 'Walking' && (e.foot === 'left' || e.foot === 'right'))) {
    console.error('FAIL: the walk\'s foot contacts did not arrive as events'); failed = true;
  }
  if (web.visemes.length < 10 || !web.visemes.every((v) => v.character === 'godette' && v.weight >= 0 && v.weight <= 1)) {
    console.error('FAIL: the line\'s visemes did not arrive'); failed = true;
  }
  // The TypeScript declarations promise what the classes have, and declare every public method.
  {
    const dts = readFileSync(join(packageDir, 'marionette.d.ts'), 'utf8');
    const declared = (name) => {
      const block = dts.match(new RegExp(`export interface ${name} \\{([\\s\\S]*?)\\n\\}`));
      return block ? [...block[1].matchAll(/^\s+(\w+)\(/gm)].map((m) => m[1]) : null;
    };
    const internal = new Set(['constructor', 'malloc', 'string', 'allocString', 'allocBytes', 'withTemp', 'check', 'alive',
      'fileReader', 'call', 'setCallback', 'buffer', 'release', 'rethrowCallbackError', 'playOptions']);
    const s2 = marionette.createScene();
    const c2 = s2.addCharacter('typed', new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb'))),
      { fileName: 'RobotExpressive.glb' });
    const b2 = c2.bind({ bones: c2.jointNames });
    const a2 = marionette.loadAsset(new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb'))), 'r.glb');
    for (const [name, object] of [['Marionette', marionette], ['Scene', s2], ['Character', c2], ['Binding', b2], ['Asset', a2]]) {
      const methods = declared(name);
      const actual = Object.getOwnPropertyNames(Object.getPrototypeOf(object)).filter((m) => typeof object[m] === 'function' && !internal.has(m));
      const missing = (methods || []).filter((m) => typeof object[m] !== 'function');
      const undeclared = actual.filter((m) => !(methods || []).includes(m));
      if (!methods || missing.length || undeclared.length) {
        console.error(`FAIL: marionette.d.ts ${name}: declared but missing [${missing}], undeclared [${undeclared}]`); failed = true;
      }
    }
    a2.dispose();
    s2.dispose();
  }
  // A callback that throws: the update finishes, then the exception reaches the caller.
  {
    const s3 = marionette.createScene();
    s3.addCharacter('r', new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb'))), { fileName: 'RobotExpressive.glb' });
    s3.onFeedback(() => { throw new Error('from the callback'); });
    let caught = null;
    try { s3.sendBml('<bml id="t1"><head id="h" lexeme="NOD"/></bml>'); } catch (e) { caught = e; }
    let after = null;
    try { for (let f = 0; f < 5; ++f) s3.update(1 / 60); } catch (e) { after = e; }
    s3.onFeedback(null);
    s3.update(1 / 60);  // the scene still works
    if (!caught || caught.message !== 'from the callback' || s3.time <= 0) {
      console.error(`FAIL: a throwing callback: ${caught}`); failed = true;
    }
    s3.dispose();
    void after;
  }
  // The review's cases: a file reader that throws, a removal refused inside a callback, calls on
  // a removed character, parents that do not match the bones.
  {
    const robotBytes = new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb')));
    let thrown = null;
    try {
      marionette.loadAsset(robotBytes, 'r.glb', { profile: 'p.json', files: { get 'p.json'() { throw new Error('reader boom'); } } });
    } catch (e) { thrown = e; }
    if (!thrown || thrown.message !== 'reader boom') { console.error(`FAIL: a throwing file reader gave ${thrown}`); failed = true; }
    const s4 = marionette.createScene();
    const c4 = s4.addCharacter('r', robotBytes, { fileName: 'RobotExpressive.glb' });
    s4.onFeedback(() => c4.remove());  // refused: from a callback of the same scene
    let refused = null;
    try { s4.sendBml('<bml id="t2"><head id="h" lexeme="NOD"/></bml>'); } catch (e) { refused = e; }
    s4.onFeedback(null);
    const stillThere = c4.palette().length === c4.jointNames.length * 16 && s4.characters.has('r');
    if (!refused || refused.status !== 'MN_ERROR_INVALID_ARGUMENT' || !stillThere) {
      console.error(`FAIL: a removal refused in a callback: ${refused}, character kept: ${stillThere}`); failed = true;
    }
    c4.remove();
    let dead = null;
    try { c4.setPosition(0, 0, 0); } catch (e) { dead = e; }
    if (!dead || !/removed/.test(dead.message)) { console.error(`FAIL: a call on a removed character: ${dead}`); failed = true; }
    const c5 = s4.addCharacter('q', robotBytes, { fileName: 'RobotExpressive.glb' });
    let mismatch = null;
    try { c5.bind({ bones: c5.jointNames, parents: [-1] }); } catch (e) { mismatch = e; }
    if (!mismatch || mismatch.status !== 'MN_ERROR_INVALID_ARGUMENT') { console.error(`FAIL: parents for the wrong bones: ${mismatch}`); failed = true; }
    s4.update(1 / 60);
    s4.dispose();
  }
  // Errors are MarionetteErrors with the library's message, naming the file.
  try {
    marionette.loadAsset(new Uint8Array(readFileSync(join(assetsDir, 'characters/RobotExpressive.glb'))).slice(0, 200), 'broken.glb');
    console.error('FAIL: a truncated GLB loaded'); failed = true;
  } catch (e) {
    console.log(`a truncated GLB: ${e.name} ${e.status}: ${e.message.split('\n')[0]}`);
    if (e.name !== 'MarionetteError' || e.status !== 'MN_ERROR_LOAD' || !e.message.includes('broken.glb')) {
      console.error('FAIL: expected a MarionetteError MN_ERROR_LOAD naming broken.glb'); failed = true;
    }
  }
  // The trace must show motion, or matching would prove nothing.
  let moved = 0;
  const per = web.matrices.length / scenario.frames;
  for (let i = 0; i < per; ++i) moved = Math.max(moved, Math.abs(web.matrices[i] - web.matrices[(scenario.frames - 1) * per + i]));
  if (!(moved > 0.01)) { console.error(`FAIL: nothing moved (${moved})`); failed = true; }
} finally {
  rmSync(work, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
